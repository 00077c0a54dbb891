"""Basins with ``backend="jax"``: the same rk4 steps as numba's, so the same labels."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.derive import derive
from lagrangian.ensemble.basins import FIRST_POOL, basins_of_attraction
from lagrangian.ensemble.basins_jax import padded_size
from lagrangian.facade import load
from lagrangian.numeric import compile_equations

from .test_basins import DOUBLE_WELL, DRIVEN_DUFFING, _reference_wells

pytest.importorskip("numba")  # the labeller runs on numba for both backends
pytest.importorskip("jax")


def _compiled(tmp_path, text: str):
    path = tmp_path / "model.toml"
    path.write_text(text)
    return compile_equations(derive(load(str(path))))


def _same_maps(jax_map, numba_map) -> None:
    """The same attractors (kind, period, points to 1e-9) and >= 99.5 % of the labels."""
    assert jax_map.settings["backend"] == "jax" and numba_map.settings["backend"] == "numba"
    assert [(a.kind, a.period) for a in jax_map.attractors] == [
        (a.kind, a.period) for a in numba_map.attractors
    ]
    for ours, theirs in zip(jax_map.attractors, numba_map.attractors, strict=True):
        np.testing.assert_allclose(ours.points, theirs.points, atol=1e-9)
    assert np.mean(jax_map.labels == numba_map.labels) >= 0.995


@pytest.mark.slow
def test_double_well_on_jax_is_numbas_map_and_scipys_wells(tmp_path):
    well = _compiled(tmp_path, DOUBLE_WELL)
    grid = {"x": (-2.0, 2.0, 20), "x_dot": (-2.0, 2.0, 20)}
    on_jax = basins_of_attraction(well, grid=grid, interval=1.0, backend="jax")
    on_numba = basins_of_attraction(well, grid=grid, interval=1.0)
    _same_maps(on_jax, on_numba)
    assert np.array_equal(on_jax.labels, on_numba.labels)  # smooth basins: every start
    assert on_jax.settings["iterations"] == on_numba.settings["iterations"]
    # and independently: the well scipy's long DOP853 runs end in
    wells = {a.label: np.sign(a.points[0, 0]) for a in on_jax.attractors}
    reference = _reference_wells(tuple(on_jax.axes[0]), tuple(on_jax.axes[1]))
    assert np.mean(np.vectorize(wells.get)(on_jax.labels) == reference) >= 0.995


@pytest.mark.slow
def test_driven_duffing_on_jax_is_numbas_map(tmp_path):
    duffing = _compiled(tmp_path, DRIVEN_DUFFING)
    grid = {"x": (-2.0, 2.0, 16), "x_dot": (-2.0, 2.0, 16)}
    period = 2 * np.pi / 1.2
    on_jax = basins_of_attraction(duffing, grid=grid, period=period, backend="jax")
    on_numba = basins_of_attraction(duffing, grid=grid, period=period)
    assert [(a.kind, a.period) for a in on_jax.attractors] == [("fixed point", 1)] * 2
    _same_maps(on_jax, on_numba)
    assert on_jax.counts()[-1] == 0


def test_the_pool_is_padded_to_a_few_sizes():
    # FIRST_POOL * 4**k: a pool growing 256 -> 65,536 and shrinking uses five sizes
    assert [padded_size(n, 256) for n in (1, 256, 257, 1024, 1025, 65_536)] == [
        256, 256, 1024, 1024, 4096, 65_536,
    ]  # fmt: skip
    sizes = {padded_size(n, FIRST_POOL) for n in range(1, 65_537)}
    assert sorted(sizes) == [256, 1024, 4096, 16_384, 65_536]


def test_an_unknown_backend_is_refused(tmp_path):
    well = _compiled(tmp_path, DOUBLE_WELL)
    grid = {"x": (-2.0, 2.0, 4), "x_dot": (-2.0, 2.0, 4)}
    with pytest.raises(Exception, match=r"^basins run on backend numba or jax, not 'cuda'$"):
        basins_of_attraction(well, grid=grid, interval=1.0, backend="cuda")


def test_without_jax_the_error_names_the_extra(tmp_path, monkeypatch):
    from lagrangian.errors import MissingDependencyError

    well = _compiled(tmp_path, DOUBLE_WELL)
    monkeypatch.setitem(__import__("sys").modules, "jax", None)  # import jax: ImportError
    grid = {"x": (-2.0, 2.0, 4), "x_dot": (-2.0, 2.0, 4)}
    with pytest.raises(MissingDependencyError, match=r"\.\[jax\]"):
        basins_of_attraction(well, grid=grid, interval=1.0, backend="jax")


def test_one_iteration_is_rk4_by_hand_and_pools_under_256_share_one_compile(tmp_path):
    from lagrangian.ensemble.basins_jax import JaxIterations

    well = _compiled(tmp_path, DOUBLE_WELL)
    steps, h = 50, 1.0 / 50
    grid = np.arange(steps + 1) / steps
    iterations = JaxIterations(well, well.parameter_vector({}), grid, steps, FIRST_POOL)
    rng = np.random.default_rng(7)

    def slope(y):  # x'' = x - x^3 - 0.3 x', written by hand
        return np.stack([y[:, 1], y[:, 0] - y[:, 0] ** 3 - 0.3 * y[:, 1]], axis=1)

    for count in (3, 200):  # both padded to 256: the loop is traced once for both
        states = rng.uniform(-2.0, 2.0, (count, 2))
        y = states.copy()
        for _ in range(steps):
            k1 = slope(y)
            k2 = slope(y + h / 2 * k1)
            k3 = slope(y + h / 2 * k2)
            k4 = slope(y + h * k3)
            y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        after = iterations(states)
        assert after.shape == (count, 2, 1)
        np.testing.assert_allclose(after[:, :, 0], y, rtol=0, atol=1e-12)
    assert iterations.loop._cache_size() == 1

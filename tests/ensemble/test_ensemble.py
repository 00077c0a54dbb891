"""Ensembles: the single run applied to a batch (STYLE habit 9), grids, observables, backends."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.ensemble import EnsembleTrajectory, ensemble_of_system, run_ensemble
from lagrangian.errors import MissingDependencyError, ModelError
from lagrangian.integrate import simulate
from lagrangian.numeric import compile_equations


@pytest.fixture(scope="module")
def pendulum2():
    return compile_equations(lg.load("double_pendulum").equations_of_motion())


@pytest.fixture(scope="module")
def pendulum1():
    return compile_equations(lg.load("simple_pendulum").equations_of_motion())


THETA1 = np.array([-2.9, -1.0, 0.2, 1.5, 2.7])
THETA2 = np.array([0.3, -2.0, 1.1, 0.0, -0.4])


@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_ensemble_equals_a_loop_of_single_runs(pendulum2, method):
    result = run_ensemble(
        pendulum2, initial={"theta1": THETA1, "theta2": THETA2, "theta2_dot": 0.5},
        params={"m2": [1.0, 2.0, 0.5, 1.0, 1.5]}, t_end=1.5, dt=0.01, method=method,
        observables=("final_state", "energy_drift"),
    )  # fmt: skip
    assert result.dims == ("member",) and result.shape == (5,)
    for i in range(5):
        single = simulate(
            pendulum2, t_end=1.5, dt=0.01, method=method,
            initial={"theta1": THETA1[i], "theta2": THETA2[i], "theta2_dot": 0.5},
            params={"m2": [1.0, 2.0, 0.5, 1.0, 1.5][i]},
        )  # fmt: skip
        for name, value in single.final_state.items():
            assert result.final_state[name][i] == pytest.approx(value, rel=1e-12, abs=1e-12)
        energy = single["energy"]
        drift = abs(energy[-1] - energy[0]) / abs(energy[0])
        assert result["energy_drift"][i] == pytest.approx(drift, rel=1e-6, abs=1e-13)


def test_a_grid_has_the_grid_dims_and_chunks_change_nothing(pendulum2):
    grid = {"theta1": np.linspace(-1, 1, 4)[:, None], "theta2": np.linspace(0, 2, 3)[None, :]}
    whole = run_ensemble(pendulum2, initial=grid, t_end=0.5, dt=0.05)
    chunked = run_ensemble(pendulum2, initial=grid, t_end=0.5, dt=0.05, chunk_size=5)
    assert whole.dims == ("theta1", "theta2") and whole.shape == (4, 3)
    assert np.array_equal(whole.dataset["theta2"].values, np.linspace(0, 2, 3))
    for name, values in whole.final_state.items():
        assert values.shape == (4, 3)
        np.testing.assert_allclose(chunked.final_state[name], values, rtol=1e-13, atol=1e-13)
    # the grid point (1, 2): member [3, 2] is the single run from there
    single = simulate(
        pendulum2, t_end=0.5, dt=0.05, method="rk4", initial={"theta1": 1.0, "theta2": 2.0}
    )
    assert whole.final_state["theta2_dot"][3, 2] == pytest.approx(single.final_state["theta2_dot"])
    attrs = whole.attrs
    assert attrs["method"] == "rk4" and attrs["backend"] == "numpy" and attrs["members"] == 12
    assert attrs["trajectory_steps_per_second"] > 0


def test_saved_paths_are_every_kth_step(pendulum1):
    result = run_ensemble(pendulum1, initial={"theta": [0.1, 0.2]}, t_end=1.0, dt=0.1, save_every=2)
    assert result["path_theta"].shape == (2, 6)
    np.testing.assert_allclose(result.dataset["t"].values, np.linspace(0, 1, 6))
    np.testing.assert_allclose(result["path_theta"][:, -1], result.final_state["theta"])


def test_flip_time_at_start_and_never(pendulum1):
    result = run_ensemble(
        pendulum1, initial={"theta": [3.5, 0.0, 3.1], "theta_dot": [0.0, 0.0, 3.0]},
        t_end=2.0, dt=0.01, observables="flip_time",
    )  # fmt: skip
    flips = result["flip_time"]
    assert flips[0] == 0.0
    assert np.isnan(flips[1])
    assert 0.0 < flips[2] < 2.0


def test_unknown_observable_lists_the_valid_names(pendulum1):
    with pytest.raises(ModelError, match="flip_time"):
        run_ensemble(pendulum1, initial={"theta": [0.1]}, t_end=1, observables="nope")


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"precision": "float32"}, r"^precision float32 needs backend jax or cuda \(not numpy\)$"),
        ({"precision": "half"}, r"^unknown precision 'half' \(precisions: float64, float32\)$"),
        ({"backend": "opencl"}, r"^unknown backend 'opencl' \(backends: numpy, numba, jax, cuda"),
    ],
)
def test_bad_backend_options_are_one_line_errors(pendulum1, options, message):
    with pytest.raises(ModelError, match=message):
        run_ensemble(pendulum1, initial={"theta": [0.1]}, t_end=1, **options)


def test_cuda_without_a_gpu_says_what_to_install(pendulum1, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "cupy", None)  # as if CuPy were not installed
    with pytest.raises(
        MissingDependencyError, match=r"^backend 'cuda' needs CuPy and an NVIDIA GPU"
    ):
        run_ensemble(pendulum1, initial={"theta": [0.1]}, t_end=1, backend="cuda")


@pytest.mark.slow
@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_jax_through_run_ensemble_equals_numpy(pendulum2, method):
    pytest.importorskip("jax")
    options = dict(
        initial={"theta1": THETA1, "theta2": THETA2}, t_end=0.5, dt=0.01, method=method,
        observables=("final_state", "flip_time", "energy_drift"),
    )  # fmt: skip
    expected = run_ensemble(pendulum2, **options)
    got = run_ensemble(pendulum2, backend="jax", chunk_size=3, **options)
    assert got.attrs["backend"] == "jax" and got.attrs["precision"] == "float64"
    for name in expected.dataset.data_vars:
        np.testing.assert_allclose(got[name], expected[name], rtol=1e-10, atol=1e-12)
    single = run_ensemble(pendulum2, backend="jax", precision="float32", **options)
    assert single.attrs["precision"] == "float32"
    np.testing.assert_allclose(single["final_theta1"], expected["final_theta1"], atol=1e-3)


def test_numba_equals_numpy(pendulum2):
    pytest.importorskip("numba")
    options = dict(
        initial={"theta1": np.linspace(-3, 3, 7), "theta2": 1.0}, params={"l2": 0.8},
        t_end=2.0, dt=0.01, observables=("final_state", "flip_time", "energy_drift"),
    )  # fmt: skip
    numpy_result = run_ensemble(pendulum2, **options)
    numba_result = run_ensemble(pendulum2, backend="numba", **options)
    for name in numpy_result.dataset.data_vars:
        np.testing.assert_allclose(
            numba_result[name], numpy_result[name], rtol=1e-12, atol=1e-12, equal_nan=True
        )


@pytest.mark.slow
def test_dask_equals_numpy(pendulum2):
    pytest.importorskip("distributed")
    options = dict(
        initial={"theta1": np.linspace(-3, 3, 6), "theta2": 0.5}, t_end=0.5, dt=0.01,
        observables=("final_state", "flip_time"),
    )  # fmt: skip
    local = run_ensemble(pendulum2, **options)
    remote = run_ensemble(pendulum2, backend="dask", chunk_size=2, **options)
    assert remote.attrs["backend"] == "dask"
    for name in local.dataset.data_vars:
        np.testing.assert_allclose(remote[name], local[name], rtol=1e-13, equal_nan=True)


def test_ensemble_of_system_uses_the_model_defaults():
    result = ensemble_of_system(lg.load("simple_pendulum"), initial={"theta": [0.1]}, t_end=0.2)
    assert isinstance(result, EnsembleTrajectory) and result.attrs["t_end"] == 0.2


def test_cli_writes_a_map_and_a_dataset(tmp_path, capsys):
    png, nc = tmp_path / "flip.png", tmp_path / "flip.nc"
    grid = ["--grid", "theta1=-3.14:3.14:40", "--grid", "theta2=-3.14:3.14:40"]
    common = ["ensemble", "double_pendulum", *grid, "--observable", "flip_time", "--t-end", "1"]
    assert main([*common, "--dt", "0.01", "--out", str(png)]) == ExitStatus.SUCCESS
    from matplotlib.image import imread

    pixels = imread(png)
    assert pixels.std() > 0.05
    assert main([*common, "--dt", "0.05", "--out", str(nc)]) == ExitStatus.SUCCESS
    with xr.open_dataset(nc) as dataset:
        assert dataset["flip_time"].dims == ("theta1", "theta2")
        assert dataset["flip_time"].shape == (40, 40)
    assert "wrote" in capsys.readouterr().out


@pytest.mark.slow
def test_cli_define_gives_the_unspecified_functions(tmp_path, capsys):
    # V = k r^2 / 2 with A = -y/2, B = x/2: a charge in a uniform field B_z = 1 and a trap
    nc = tmp_path / "run.nc"
    common = ["ensemble", "velocity_dependent_potential", "--grid", "x=0.1:0.3:3", "--t-end", "1"]
    assert main(common) == ExitStatus.BAD_INPUT
    assert "--define NAME=EXPR" in capsys.readouterr().err
    defines = ["--define", "V=(x^2 + y^2 + z^2)/2", "--define", "A=-y/2", "--define", "B=x/2"]
    arguments = [*common, *defines, "--define", "C=0", "--out", str(nc)]
    assert main(arguments) == ExitStatus.SUCCESS
    system = lg.load("velocity_dependent_potential")
    definitions = {"V": "(x^2 + y^2 + z^2)/2", "A": "-y/2", "B": "x/2", "C": "0"}
    compiled = compile_equations(system.equations_of_motion(), definitions=definitions)
    single = simulate(compiled, t_end=1, method="rk4", dt=0.001, initial={"x": 0.3})
    with xr.open_dataset(nc) as dataset:
        assert float(dataset["final_x"][-1]) == pytest.approx(single.final_state["x"], abs=1e-12)


@pytest.mark.parametrize("bad", ["theta1", "theta1=0:1", "theta1=0:1:x", "=0:1:3", "theta1=0:1:0"])
def test_bad_grid_is_exit_2_with_one_line(capsys, bad):
    status = main(["ensemble", "double_pendulum", "--grid", bad])
    err = capsys.readouterr().err
    assert status == ExitStatus.BAD_INPUT
    assert len(err.strip().splitlines()) == 1 and "--grid" in err


def test_the_backend_registry_holds_every_choice():
    from lagrangian.ensemble.choices import BACKENDS
    from lagrangian.ensemble.core import ENSEMBLE_BACKENDS

    assert tuple(ENSEMBLE_BACKENDS) == BACKENDS
    assert {name for name, kind in ENSEMBLE_BACKENDS.items() if "float32" in kind.precisions} == {
        "jax",
        "cuda",
    }

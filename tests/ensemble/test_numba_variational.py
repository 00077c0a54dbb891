"""The numba backend's variational loop equals the numpy backend's (float64, to rounding)."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.codegen import cache as code_cache
from lagrangian.ensemble import run_ensemble
from lagrangian.ensemble.chunk import Chunk
from lagrangian.ensemble.numba_backend import NumbaBackend
from lagrangian.errors import ModelError
from lagrangian.integrate.variational import Variational
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")

ALL = ("final_state", "energy_drift", "flip_time")


def _forced_rotating_frame() -> lg.System:
    """Explicit time, gyroscopic terms, Rayleigh dissipation and a generalized force."""
    return lg.System.from_lagrangian(
        "m*((x_dot - w*y)**2 + (y_dot + w*x)**2)/2 - k*(x**2 + y**2)/2 + e*x*y*cos(t)",
        coordinates=["x", "y"],
        dissipation="b*(x_dot**2 + y_dot**2)/2",
        forces={"x": "F*cos(w*t)"},
        # w real, not positive: one member runs without rotation (w = 0)
        parameters={
            "m": 1.0,
            "w": {"value": 0.7, "sign": "real"},
            "k": 2.0,
            "b": 0.3,
            "F": 0.5,
            "e": 0.2,
        },
    )


# separable, a constant coupled mass matrix: Stormer-Verlet with M^-1 of a 3 x 3 matrix
CHAIN = """
name = "Anharmonic chain"
coordinates = ["x1", "x2", "x3"]
kinetic = "m*(x1_dot^2 + x2_dot^2 + x3_dot^2)/2 + mu*(x1_dot*x2_dot + x2_dot*x3_dot)"
potential = "k*(x1^2 + (x2-x1)^2 + (x3-x2)^2 + x3^2)/2 + a*(x1^4 + x2^4 + x3^4)/4 + s*sin(x1)*x3"
[parameters]
m = 1.0
mu = {value = 0.3, sign = "real"}  # one member without coupling (mu = 0)
k = 2.0
a = 0.5
s = 0.4
"""

# (system, scheme the variational method picks, initial values, parameters per member)
SYSTEMS = {
    "double_pendulum": (
        lambda: lg.load("double_pendulum"),
        "midpoint",
        {"theta1": np.linspace(-2.5, 2.5, 6), "theta2": 1.0, "theta2_dot": 0.5},
        {"m2": [1.0, 2.0, 0.5, 1.0, 1.5, 0.8]},
    ),
    "forced_rotating_frame": (
        _forced_rotating_frame,
        "midpoint",
        {"x": np.linspace(-1, 1, 5), "y": 0.5, "x_dot": 0.2, "y_dot": -0.4},
        {"w": [0.7, 0.1, 1.5, 0.0, 2.0]},
    ),
    "simple_pendulum": (
        lambda: lg.load("simple_pendulum"),
        "stormer-verlet",
        {"theta": np.linspace(-3.5, 3.0, 6), "theta_dot": 0.5},
        {"l": [1.0, 0.5, 2.0, 1.0, 1.5, 0.8]},
    ),
    "chain": (
        lambda: lg.loads(CHAIN),
        "stormer-verlet",
        {"x1": np.linspace(-1, 1, 4), "x2": 0.5, "x3_dot": -0.7},
        {"mu": [0.3, 0.1, 0.0, 0.45]},
    ),
}


@pytest.fixture(scope="module")
def compiled_systems():
    return {
        name: compile_equations(load().equations_of_motion())
        for name, (load, _, _, _) in SYSTEMS.items()
    }


def _both(compiled, **options):
    expected = run_ensemble(compiled, method="variational", **options)
    actual = run_ensemble(compiled, method="variational", backend="numba", **options)
    assert actual.attrs["backend"] == "numba" and actual.attrs["method"] == "variational"
    assert expected.dataset.data_vars.keys() == actual.dataset.data_vars.keys()
    for name in expected.dataset.data_vars:
        np.testing.assert_allclose(
            actual[name], expected[name], rtol=1e-12, atol=1e-12, equal_nan=True, err_msg=name
        )
    return expected


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SYSTEMS))
def test_equals_numpy_with_per_member_parameters(compiled_systems, name):
    compiled = compiled_systems[name]
    _, scheme, initial, params = SYSTEMS[name]
    assert Variational(dt=0.01).scheme(compiled) == scheme
    options = dict(initial=initial, params=params, t_end=2.0, dt=0.01, observables=ALL)
    expected = _both(compiled, **options)
    assert np.all(expected["energy_drift"] > 0)
    _both(compiled, chunk_size=4, **options)  # a member's parameters follow it into its chunk


@pytest.mark.slow
def test_flip_times_stop_early_and_equal_numpy(compiled_systems):
    compiled = compiled_systems["double_pendulum"]
    initial = {"theta1": [3.5, 0.0, 3.0, 2.0], "theta1_dot": [0.0, 0.0, 3.0, 1.0]}
    flips = _both(compiled, initial=initial, t_end=3.0, dt=0.01, observables="flip_time")
    flip = flips["flip_time"]
    assert flip[0] == 0.0 and np.isnan(flip[1]) and np.all(flip[2:] > 0)


@pytest.mark.slow
def test_saved_paths_equal_numpy(compiled_systems):
    compiled = compiled_systems["double_pendulum"]
    _, _, initial, params = SYSTEMS["double_pendulum"]
    paths = _both(compiled, initial=initial, params=params, t_end=0.5, dt=0.01, save_every=7)
    assert paths["path_theta1"].shape == (6, 8)  # 50 steps, saved after 0, 7, ..., 49


def test_the_loop_is_built_once_per_system_and_scheme(compiled_systems):
    compiled = compiled_systems["simple_pendulum"]
    y0, params = np.array([[0.5, 1.0], [0.0, 0.1]]), compiled.parameter_vector()
    NumbaBackend().integrate(
        Chunk(compiled, Variational(dt=0.1), y0, params, 0.5, ("final_state",))
    )
    built = _loops(compiled)
    assert "stormer-verlet" in built
    NumbaBackend().integrate(
        Chunk(compiled, Variational(dt=0.05), y0, params, 0.3, ("final_state",))
    )
    assert _loops(compiled) == built  # dt and t_end are arguments


def _loops(compiled):
    """scheme -> the loop of ``compiled`` in the in-memory code cache."""
    return {
        key[2]: value
        for key, value in code_cache._BUILT.items()
        if key[:2] == (compiled.forms.fingerprint, "numba-loop")
    }


def test_newton_failure_is_one_line(compiled_systems):
    compiled = compiled_systems["double_pendulum"]
    y0 = np.array([[0.5, 2.0], [1.0, -1.0], [0.3, 2.0], [0.0, 1.0]])
    with pytest.raises(ModelError) as caught:
        chunk = Chunk(
            compiled, Variational(dt=0.05, max_newton=1), y0, compiled.parameter_vector(), 0.2,
            ("final_state",),
        )  # fmt: skip
        NumbaBackend().integrate(chunk)
    assert str(caught.value) == (
        "the ensemble integration failed: Newton's method of the variational step did not "
        "converge in 1 iterations at t = 0"
    )


def test_constraints_are_refused_by_the_variational_method():
    # rk4 takes them on this backend: tests/ensemble/test_numba_constrained.py
    disc = compile_equations(lg.load("rolling_disc").equations_of_motion())
    with pytest.raises(ModelError, match=r"^the variational integrator does not handle constr"):
        run_ensemble(disc, t_end=0.1, method="variational", backend="numba")


@pytest.mark.slow
def test_a_second_process_loads_the_compiled_loop_from_the_cache(tmp_path):
    import os
    import subprocess
    import sys

    script = (
        "import lagrangian as lg\n"
        "from lagrangian.ensemble import run_ensemble\n"
        "from lagrangian.ensemble.numba_backend import tabulated_kernel\n"
        "from lagrangian.numeric import compile_equations\n"
        "c = compile_equations(lg.load('harmonic_oscillator').equations_of_motion())\n"
        "run_ensemble(c, initial={'x': [0.1, 0.2]}, t_end=0.1, dt=0.01, backend='numba')\n"
        "loop = tabulated_kernel(c, range(len(c.parameter_names)))\n"
        "s = loop.system\n"
        "stats = [loop.loops.run.stats, s.rk4_table_step.stats, s.tabulate.stats]\n"
        "hits = sum(sum(s.cache_hits.values()) for s in stats)\n"
        "misses = sum(sum(s.cache_misses.values()) for s in stats)\n"
        "print(hits, misses)\n"
    )
    environment = {**os.environ, "LAGRANGIAN_CACHE": str(tmp_path)}
    command = [sys.executable, "-c", script]
    outputs = [
        subprocess.run(
            command, env=environment, capture_output=True, text=True, check=True
        ).stdout.split()
        for _ in range(2)
    ]
    # rk4 on numba runs the tabulated loop (codegen/time_terms.py): the loop shared by
    # every system, and the system's step and table
    assert outputs[0] == ["0", "3"]  # compiled and written
    assert outputs[1] == ["3", "0"]  # read back, nothing compiled

"""The numba backend: jitted single-state functions equal to NumPy's, cached on disk."""

from __future__ import annotations

import sys
import warnings

import numpy as np
import pytest

from helpers import slow_where
from lagrangian.errors import MissingDependencyError
from lagrangian.integrate import simulate
from lagrangian.numeric import compile_equations

from .cases import (
    CONSTRAINED,
    DEFINITIONS,
    EXAMPLES,
    arguments,
    assert_arrays_close,
    compiled,
    equations,
    point,
)

pytest.importorskip("numba")

UNCONSTRAINED = tuple(name for name in EXAMPLES if name not in CONSTRAINED)
#: One system in the quick tier; each other one is a numba compile of seconds (slow tier).
QUICK = {"simple_pendulum"}


def jitted(name: str):
    return compile_equations(equations(name), backend="numba", definitions=DEFINITIONS.get(name))


@pytest.mark.parametrize(
    "name",
    slow_where(UNCONSTRAINED, lambda name: name not in QUICK),
)
def test_numba_equals_numpy(name, rng):
    reference, fast = compiled(name), jitted(name)
    assert fast.backend == "numba"
    t, y, params = arguments(reference, point(name, rng))
    n = reference.n
    q, v = y[:n], y[n:]
    assert_arrays_close(fast.rhs(t, y, params), reference.rhs(t, y, params), 1e-12, name)
    assert_arrays_close(
        fast.accelerations(t, q, v, params), reference.accelerations(t, q, v, params), 1e-12, name
    )
    assert_arrays_close(
        fast.mass_matrix(t, q, v, params), reference.mass_matrix(t, q, v, params), 1e-12, name
    )
    assert_arrays_close(fast.forcing(t, q, v, params), reference.forcing(t, q, v, params), 1e-12)
    energy = fast.energy(t, y, params)
    assert np.shape(energy) == ()
    assert_arrays_close(energy, reference.energy(t, y, params), 1e-12, name)


def test_batch_equals_loop_of_single_states(rng):
    fast = jitted("double_pendulum")
    states = np.array([arguments(fast, point("double_pendulum", rng))[1] for _ in range(3)]).T
    params = fast.parameter_vector({"m1": 1.3, "m2": 0.7, "l1": 1.1, "l2": 0.9, "g": 9.81})
    batch = fast.rhs(0.0, states, params)
    assert batch.shape == states.shape
    for k in range(states.shape[1]):
        assert_arrays_close(batch[:, k], fast.rhs(0.0, states[:, k], params), 1e-12)


def test_wrong_state_is_reported_as_by_numpy():
    fast = jitted("double_pendulum")
    params = fast.parameter_vector({"m1": 1.0, "m2": 1.0, "l1": 1.0, "l2": 1.0, "g": 9.81})
    with pytest.raises(ValueError, match="the state has 2n = 4 rows"):
        fast.rhs(0.0, np.zeros(3), params)


@pytest.mark.slow
def test_generated_code_is_cached_on_disk(tmp_path, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(tmp_path))
    eom = equations("harmonic_oscillator")
    first = compile_equations(eom, backend="numba")
    params = first.parameter_vector({name: 1.5 for name in first.parameter_names})
    first.rhs(0.0, np.array([0.5, 0.1]), params)
    files = sorted((tmp_path / "numba").glob("*.py"))
    assert len(files) == 2  # the system's module, and the solve for n = 1 it imports
    written = files[0].stat().st_mtime_ns
    second = compile_equations(eom, backend="numba")
    np.testing.assert_array_equal(
        second.rhs(0.0, np.array([0.5, 0.1]), params), first.rhs(0.0, np.array([0.5, 0.1]), params)
    )
    assert sorted((tmp_path / "numba").glob("*.py")) == files
    assert files[0].stat().st_mtime_ns == written


@pytest.mark.slow
@pytest.mark.parametrize("name", ["double_pendulum", "velocity_dependent_potential"])
def test_simulate_with_numba_equals_numpy(name, rng):
    reference, fast = compiled(name), jitted(name)
    values = point(name, rng)
    _, y, params = arguments(reference, values)
    overrides = dict(zip(reference.parameter_names, params, strict=True))
    names = [*reference.coordinate_names, *(f"{c}_dot" for c in reference.coordinate_names)]
    initial = dict(zip(names, y, strict=True))
    runs = [
        simulate(c, t_end=1.0, initial=initial, params=overrides, method="dop853", rtol=1e-10)
        for c in (reference, fast)
    ]
    for coordinate in names:
        assert abs(runs[1].final_state[coordinate] - runs[0].final_state[coordinate]) <= 1e-10


def test_constrained_systems_keep_the_numpy_functions_without_a_warning():
    # their dop853 runs in the compiled loop (tests/integrate/test_constrained_compiled.py)
    name = CONSTRAINED[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fast = jitted(name)
    assert fast.backend == "numba"
    assert fast.rhs is not compiled(name).rhs


def test_missing_numba_is_an_error_naming_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba raises ImportError
    with pytest.raises(MissingDependencyError) as error:
        compile_equations(equations("harmonic_oscillator"), backend="numba")
    assert str(error.value) == (
        "backend 'numba' needs numba: pip install \".[numba]\" in a clone of lagrangian"
    )

"""The jax backend equals the numpy backend: the same single-run methods, one jitted loop."""

from __future__ import annotations

import builtins

import numpy as np
import pytest

import lagrangian as lg
from helpers import slow_where
from lagrangian.codegen import cache as code_cache
from lagrangian.ensemble.chunk import Chunk
from lagrangian.ensemble.jax_backend import JaxBackend
from lagrangian.ensemble.numpy_backend import NumpyBackend
from lagrangian.errors import MissingDependencyError, ModelError
from lagrangian.integrate import method_class
from lagrangian.integrate.variational import Variational
from lagrangian.numeric import compile_equations

jax = pytest.importorskip("jax")

ALL = ("final_state", "energy_drift", "flip_time")


def integrate_chunk(*chunk, **options):
    return NumpyBackend().integrate(Chunk(*chunk, **options))


def integrate_jax(*chunk, **options):
    return JaxBackend().integrate(Chunk(*chunk, **options))


def _forced_rotating_frame() -> lg.System:
    """Explicit time, gyroscopic terms, Rayleigh dissipation and a generalized force."""
    return lg.System.from_lagrangian(
        "m*((x_dot - w*y)**2 + (y_dot + w*x)**2)/2 - k*(x**2 + y**2)/2",
        coordinates=["x", "y"],
        dissipation="b*(x_dot**2 + y_dot**2)/2",
        forces={"x": "F*cos(w*t)"},
        parameters={"m": 1.0, "w": 0.7, "k": 2.0, "b": 0.3, "F": 0.5},
    )


SYSTEMS = {
    "double_pendulum": lambda: lg.load("double_pendulum"),  # M(q): the midpoint scheme
    "rotating_wire_bead": lambda: lg.load("rotating_wire_bead"),  # L depends on t
    "forced_rotating_frame": _forced_rotating_frame,
    "simple_pendulum": lambda: lg.load("simple_pendulum"),  # separable: Stormer-Verlet
}
_COMPILED: dict[str, object] = {}


def compiled(name: str):
    if name not in _COMPILED:
        _COMPILED[name] = compile_equations(SYSTEMS[name]().equations_of_motion())
    return _COMPILED[name]


def members(system, count: int = 6, seed: int = 1) -> np.ndarray:
    """(2n, count) initial states, |q| < 2 and |q'| < 1."""
    rng = np.random.default_rng(seed)
    n = system.n
    return np.vstack([rng.uniform(-2, 2, (n, count)), rng.uniform(-1, 1, (n, count))])


def both(name, method, *, t_end=1.0, dt=0.02, names=ALL, precision="float64", **options):
    system = compiled(name)
    integrator = method_class(method).configure(t_span=(0.0, t_end), dt=dt)
    y0, params = members(system), system.parameter_vector()
    expected = integrate_chunk(system, integrator, y0, params, t_end, names, **options)
    actual = integrate_jax(
        system, integrator, y0, params, t_end, names, precision=precision, **options
    )
    return expected, actual


def assert_same(expected, actual, rtol, atol):
    assert expected.keys() == actual.keys()
    for key, value in expected.items():
        np.testing.assert_allclose(actual[key], value, rtol=rtol, atol=atol, err_msg=key)


@pytest.mark.parametrize(
    "name",
    # the pendulums in the quick tier (the midpoint scheme, Stormer-Verlet); the others slow
    slow_where(SYSTEMS, lambda name: "pendulum" not in name),
)
@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_float64_equals_numpy(name, method):
    expected, actual = both(name, method)
    tolerance = 1e-12 if method == "rk4" else 1e-10
    assert_same(expected, actual, tolerance, tolerance)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_float32_is_close_to_float64(method):
    expected, actual = both("forced_rotating_frame", method, precision="float32")
    assert_same(expected, actual, 1e-4, 1e-4)


def test_precision_is_scoped_not_global():
    previous = jax.config.read("jax_enable_x64")
    jax.config.update("jax_enable_x64", True)  # float32 must hold even so
    try:
        expected, actual = both("simple_pendulum", "rk4", precision="float32")
    finally:
        jax.config.update("jax_enable_x64", previous)
    error = np.max(np.abs(actual["final_theta"] - expected["final_theta"]))
    assert 1e-10 < error < 1e-5
    assert jax.config.read("jax_enable_x64") == previous


@pytest.mark.slow
def test_double_pendulum_in_float32_with_the_midpoint_scheme():
    expected, actual = both("double_pendulum", "variational", t_end=0.5, precision="float32")
    assert_same(expected, actual, 1e-3, 1e-4)


def test_flip_times_equal_numpy_on_a_grid():
    system = compiled("simple_pendulum")
    grid = np.meshgrid(np.linspace(-3.3, 3.3, 5), np.linspace(0.0, 7.0, 4))
    y0 = np.vstack([grid[0].ravel(), grid[1].ravel()])
    params = system.parameter_vector()
    integrator = method_class("rk4").configure(t_span=(0.0, 2.0), dt=0.01)
    expected = integrate_chunk(system, integrator, y0, params, 2.0, ("flip_time",))
    actual = integrate_jax(system, integrator, y0, params, 2.0, ("flip_time",))
    flips = expected["flip_time"]
    assert np.any(flips == 0.0) and np.any(np.isnan(flips)) and np.any(flips > 0.0)
    np.testing.assert_array_equal(actual["flip_time"], flips)  # the same grid times
    for precision in ("float32",):
        single = integrate_jax(
            system, integrator, y0, params, 2.0, ("flip_time",), precision=precision
        )
        np.testing.assert_allclose(single["flip_time"], flips, atol=0.011)  # a step at most


@pytest.mark.slow
@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_saved_paths_equal_numpy(method):
    expected, actual = both(
        "double_pendulum", method, t_end=0.3, names=("final_state",), save_every=4
    )
    assert actual["paths"].shape == (4, 6, 4)  # 15 steps, saved after 0, 4, 8, 12
    assert_same(expected, actual, 1e-12, 1e-12)


@pytest.mark.slow
def test_per_member_parameters_and_a_constrained_system():
    system = compile_equations(lg.load("cartesian_pendulum").equations_of_motion())
    angle = np.linspace(-1.0, 1.0, 4)
    y0 = np.vstack([np.sin(angle), -np.cos(angle), 0.3 * np.cos(angle), 0.3 * np.sin(angle)])
    params = np.repeat(system.parameter_vector()[:, None], 4, axis=1)
    params[system.parameter_names.index("g")] = [9.81, 1.0, 3.0, 5.0]
    integrator = method_class("rk4").configure(t_span=(0.0, 0.5), dt=0.01)
    expected = integrate_chunk(system, integrator, y0, params, 0.5, ("final_state",))
    actual = integrate_jax(system, integrator, y0, params, 0.5, ("final_state",))
    assert_same(expected, actual, 1e-11, 1e-11)
    with pytest.raises(ModelError, match="does not handle constraints"):
        integrate_jax(system, Variational(dt=0.01), y0, params, 0.5, ("final_state",))


def test_the_loop_is_built_once_per_system_and_settings():
    system = compiled("simple_pendulum")
    y0, params = members(system, 3), system.parameter_vector()
    integrate_jax(system, Variational(dt=0.1), y0, params, 0.5, ("final_state",))
    built = _loops(system)
    integrate_jax(system, Variational(dt=0.05), y0, params, 0.3, ("final_state",))
    assert _loops(system) == built  # dt and t_end are arguments of the same loop
    integrate_jax(system, Variational(dt=0.05, max_newton=5), y0, params, 0.3, ("final_state",))
    assert len(_loops(system)) == len(built) + 1


def _loops(system):
    """The jitted loops of ``system`` in the in-memory code cache (its twin left out)."""
    return {
        key: value
        for key, value in code_cache._BUILT.items()
        if key[:2] == (system.forms.fingerprint, "jax") and len(key) > 3
    }


@pytest.mark.slow
def test_newton_failure_is_one_line():
    system = compiled("double_pendulum")
    y0, params = members(system, 3), system.parameter_vector()
    with pytest.raises(
        ModelError, match=r"^the ensemble integration failed: .* 1 iterations at t = 0$"
    ):
        integrate_jax(system, Variational(dt=0.05, max_newton=1), y0, params, 0.2, ("final_state",))


def test_unknown_precision_lists_the_valid_ones():
    system = compiled("simple_pendulum")
    with pytest.raises(ModelError, match=r"precisions: float64, float32\)$"):
        integrate_jax(
            system, Variational(dt=0.1), members(system), [9.81, 1.0], 1.0, ALL, precision="f16"
        )


def test_without_jax_the_error_names_the_extra(monkeypatch):
    real_import = builtins.__import__

    def no_jax(name, *args, **kwargs):
        if name == "jax" or name.startswith("jax."):
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_jax)
    system = compiled("simple_pendulum")
    with pytest.raises(MissingDependencyError) as error:
        integrate_jax(system, Variational(dt=0.1), members(system), [9.81, 1.0], 1.0, ALL)
    assert str(error.value) == (
        "backend 'jax' needs JAX: pip install \".[jax]\" in a clone of lagrangian"
    )

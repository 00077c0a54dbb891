"""The JAX backend: the same functions as NumPy's, under jit, vmap and autodiff."""

from __future__ import annotations

import numpy as np
import pytest

from helpers import slow_where
from lagrangian.numeric import compile_equations

from .cases import DEFINITIONS, arguments, assert_arrays_close, compiled, equations, point

jax = pytest.importorskip("jax")


@pytest.fixture(autouse=True)
def _double_precision():
    previous = jax.config.read("jax_enable_x64")
    jax.config.update("jax_enable_x64", True)
    yield
    jax.config.update("jax_enable_x64", previous)


#: Constant entries, explicit time, definitions, holonomic and nonholonomic constraints.
JAX_EXAMPLES = (
    "harmonic_oscillator",
    "rotating_wire_bead",
    "double_pendulum",
    "velocity_dependent_potential",
    "cartesian_pendulum",
    "rolling_disc",
)


@pytest.mark.parametrize(
    "name",
    # one system in the quick tier; each other one is a JAX trace and compile of seconds
    slow_where(JAX_EXAMPLES, lambda name: name != "double_pendulum"),
)
def test_jax_equals_numpy(name, rng):
    reference = compiled(name)
    traced = compile_equations(equations(name), backend="jax", definitions=DEFINITIONS.get(name))
    assert traced.backend == "jax"
    t, y, params = arguments(reference, point(name, rng))
    assert_arrays_close(jax.jit(traced.rhs)(t, y, params), reference.rhs(t, y, params), 1e-12, name)
    assert_arrays_close(
        jax.jit(traced.rhs_jacobian)(t, y, params),
        reference.rhs_jacobian(t, y, params),
        1e-12,
        name,
    )
    autodiff = jax.jit(jax.jacfwd(traced.rhs, argnums=1))(t, y, params)
    assert_arrays_close(autodiff, reference.rhs_jacobian(t, y, params), 1e-10, name, floor=1.0)
    energy = jax.jit(traced.energy)(t, y, params)
    assert_arrays_close(energy, reference.energy(t, y, params), 1e-12, name)
    if reference.has_constraints:
        for function in ("multipliers", "constraint_residual", "project"):
            actual = jax.jit(getattr(traced, function))(t, y, params)
            assert_arrays_close(actual, getattr(reference, function)(t, y, params), 1e-10, function)


def test_vmap_and_trailing_batch_equal_numpy(rng):
    name = "double_pendulum"
    reference = compiled(name)
    traced = compile_equations(equations(name), backend="jax")
    states = np.stack([arguments(reference, point(name, rng))[1] for _ in range(7)], axis=-1)
    params = reference.parameter_vector()
    expected = reference.rhs(0.0, states, params)
    mapped = jax.jit(jax.vmap(traced.rhs, in_axes=(None, 1, None), out_axes=1))(0.0, states, params)
    assert_arrays_close(mapped, expected, 1e-12, "vmap")
    batched = jax.jit(traced.rhs)(0.0, states, params)
    assert_arrays_close(batched, expected, 1e-12, "trailing batch")

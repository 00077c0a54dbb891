"""The ``llvm`` backend (numeric/llvm_functions.py) against the NumPy backend's functions."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.codegen.llvm import llvm_available
from lagrangian.errors import SingularMassMatrixError
from lagrangian.numeric import compile_equations, default_backend

pytestmark = pytest.mark.skipif(not llvm_available(), reason="SymEngine without LLVM")


def chain(n: int) -> lg.System:
    particles, x, y = [], "0", "0"
    for i in range(1, n + 1):
        x += f" + l{i}*sin(theta{i})"
        y += f" - l{i}*cos(theta{i})"
        particles.append(lg.Particle(f"bob{i}", mass=f"m{i}", position=[x, y]))
    parameters = {f"m{i}": 1.0 + i / 7 for i in range(1, n + 1)}
    parameters |= {f"l{i}": 1.0 - i / 50 for i in range(1, n + 1)} | {"g": 9.81}
    return lg.System.from_particles(
        coordinates=[f"theta{i}" for i in range(1, n + 1)],
        particles=particles,
        gravity=lg.Gravity(g="g", direction=(0, -1)),
        parameters=parameters,
    )


@pytest.mark.slow
@pytest.mark.parametrize(
    "make",
    [
        lambda: lg.load("double_pendulum"),
        lambda: chain(8),
        lambda: lg.load("driven_damped_pendulum"),
    ],
)
def test_rhs_equals_the_numpy_rhs_at_random_states(make):
    eom = make().equations_of_motion()
    ours, numpy = compile_equations(eom, backend="llvm"), compile_equations(eom)
    assert ours.backend == "llvm"
    rng = np.random.default_rng(12)
    params = ours.parameter_vector()
    for _ in range(5):
        y = rng.uniform(-2, 2, 2 * ours.n)
        t = float(rng.uniform(0, 3))
        np.testing.assert_allclose(ours.rhs(t, y, params), numpy.rhs(t, y, params), rtol=1e-12)
        q, v = y[: ours.n], y[ours.n :]
        np.testing.assert_allclose(
            ours.accelerations(t, q, v, params), numpy.accelerations(t, q, v, params), rtol=1e-12
        )
        np.testing.assert_allclose(
            ours.rhs_jacobian(t, y, params), numpy.rhs_jacobian(t, y, params), rtol=1e-10,
            atol=1e-12,
        )  # fmt: skip
    batch = rng.uniform(-2, 2, (2 * ours.n, 4))  # a batch: the NumPy function answers
    np.testing.assert_allclose(ours.rhs(0.0, batch, params), numpy.rhs(0.0, batch, params))


def test_equations_symengine_cannot_hold_use_the_numpy_functions():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 - V(x)", coordinates=["x"], parameters={"m": 2.0}, functions={"V": ["x"]}
    )
    eom = system.equations_of_motion()
    definitions = {"V": "x**4/4"}
    ours = compile_equations(eom, backend="llvm", definitions=definitions)
    numpy = compile_equations(eom, definitions=definitions)
    y, params = np.array([0.7, 0.1]), ours.parameter_vector()
    np.testing.assert_allclose(ours.rhs(0.0, y, params), numpy.rhs(0.0, y, params), rtol=1e-14)


def test_singular_state_is_reported_as_by_numpy():
    system = lg.System.from_lagrangian(
        "x**2*x_dot**2/2 + y_dot**2/2 - y**2/2", coordinates=["x", "y"], parameters={}
    )
    eom = system.equations_of_motion()
    ours, numpy = compile_equations(eom, backend="llvm"), compile_equations(eom)
    y = np.array([0.0, 1.0, 0.5, 0.0])  # M = diag(x^2, 1) is singular at x = 0
    with pytest.raises(SingularMassMatrixError) as expected:
        numpy.rhs(0.0, y, np.array([]))
    with pytest.raises(SingularMassMatrixError) as got:
        ours.rhs(0.0, y, np.array([]))
    assert str(got.value) == str(expected.value)


def test_a_single_run_uses_llvm_by_default():
    assert default_backend() == "llvm"
    system = lg.load("double_pendulum")
    default = system.simulate(t_end=1.0)
    numpy = system.simulate(t_end=1.0, backend="numpy")
    np.testing.assert_allclose(
        default.dataset["theta1"].values, numpy.dataset["theta1"].values, rtol=0, atol=1e-9
    )

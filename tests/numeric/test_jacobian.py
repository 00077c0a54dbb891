"""The compiled Jacobians against central finite differences of the compiled functions.

rhs_jacobian is a symbolic derivative (d q''/dz = M^-1 (df/dz - dM/dz q''));
a central difference with step h has error O(h^2), far below the tolerance.
The derivatives of L for variational integrators are checked the same way.
"""

from __future__ import annotations

import numpy as np
import pytest

from .cases import EXAMPLES, arguments, assert_arrays_close, compiled, point

RTOL = 1e-6
STEP = 1e-5


def central_difference(function, x: np.ndarray) -> np.ndarray:
    """d function / d x, one column per component of x (function values first)."""
    columns = []
    for k in range(x.size):
        h = STEP * (1 + abs(x[k]))
        up, down = x.copy(), x.copy()
        up[k] += h
        down[k] -= h
        columns.append((np.asarray(function(up)) - np.asarray(function(down))) / (2 * h))
    return np.stack(columns, axis=-1)


@pytest.mark.parametrize("name", EXAMPLES)
def test_rhs_jacobian_equals_a_central_difference(name, rng):
    system = compiled(name)
    for _ in range(3):
        t, y, params = arguments(system, point(name, rng))
        expected = central_difference(lambda z, t=t, p=params: system.rhs(t, z, p), y)
        assert_arrays_close(system.rhs_jacobian(t, y, params), expected, RTOL, name, floor=1.0)


@pytest.mark.parametrize("name", EXAMPLES)
def test_derivatives_of_the_lagrangian(name, rng):
    system = compiled(name)
    t, y, params = arguments(system, point(name, rng))
    n = system.n
    q, v = y[:n], y[n:]

    def in_q(function):
        return central_difference(lambda z: function(t, z, v, params), q)

    def in_v(function):
        return central_difference(lambda z: function(t, q, z, params), v)

    checks = {
        "momenta": (system.momenta(t, q, v, params), in_v(system.lagrangian)),
        "lagrangian_gradient": (
            system.lagrangian_gradient(t, q, v, params),
            in_q(system.lagrangian),
        ),
        "momenta_jacobian_q": (system.momenta_jacobian_q(t, q, v, params), in_q(system.momenta)),
        "lagrangian_hessian_q": (
            system.lagrangian_hessian_q(t, q, v, params),
            in_q(system.lagrangian_gradient),
        ),
        "mass_matrix": (system.mass_matrix(t, q, v, params), in_v(system.momenta)),
        "nonconservative_forces_jacobian_v": (
            system.nonconservative_forces_jacobian_v(t, q, v, params),
            in_v(system.nonconservative_forces),
        ),
        "nonconservative_forces_jacobian_q": (
            system.nonconservative_forces_jacobian_q(t, q, v, params),
            in_q(system.nonconservative_forces),
        ),
    }
    for what, (actual, expected) in checks.items():
        assert_arrays_close(actual, expected, RTOL, f"{name}: {what}", floor=1.0)


def test_damped_forces_and_their_jacobians():
    """Q = -b x' - c x^3 and F = k x'^2 y / 2 give Q - dF/dq' = (-b x' - c x^3 - k x' y, 0)."""
    import lagrangian as lg
    from lagrangian.numeric import compile_equations

    system = lg.System.from_lagrangian(
        "(x_dot^2 + y_dot^2)/2 - (x^2 + y^2)/2",
        coordinates=["x", "y"],
        forces={"x": "-b*x_dot - c*x^3"},
        dissipation="k*x_dot^2*y/2",
        parameters={"b": 0.3, "c": 0.2, "k": 0.1},
    )
    compiled_system = compile_equations(system.equations_of_motion())
    assert not compiled_system.separable
    b, c, k = 0.3, 0.2, 0.1
    params = compiled_system.parameter_vector()
    x, y, vx, vy = 0.7, -0.4, 1.1, 0.5
    q, v = np.array([x, y]), np.array([vx, vy])
    assert_arrays_close(
        compiled_system.nonconservative_forces(0.0, q, v, params),
        [-b * vx - c * x**3 - k * vx * y, 0.0],
        1e-14,
    )
    assert_arrays_close(
        compiled_system.nonconservative_forces_jacobian_v(0.0, q, v, params),
        [[-b - k * y, 0.0], [0.0, 0.0]],
        1e-14,
    )
    assert_arrays_close(
        compiled_system.nonconservative_forces_jacobian_q(0.0, q, v, params),
        [[-3 * c * x**2, -k * vx], [0.0, 0.0]],
        1e-14,
    )
    assert "energy" not in compiled_system.invariants


def test_a_mass_matrix_that_depends_on_the_velocity():
    """Relativistic oscillator: M = m gamma^3, so dq''/dq' needs dM/dq' q''."""
    import lagrangian as lg
    from lagrangian.numeric import compile_equations

    system = lg.System.from_lagrangian(
        "-m*c^2*sqrt(1 - x_dot^2/c^2) - k*x^2/2",
        coordinates=["x"],
        parameters={"m": 1.0, "c": 2.0, "k": 3.0},
    )
    result = compile_equations(system.equations_of_motion())
    assert not result.constant_mass_matrix
    params = result.parameter_vector()
    y = np.array([0.4, 1.1])
    gamma = 1 / np.sqrt(1 - 1.1**2 / 4)
    assert_arrays_close(result.rhs(0.0, y, params), [1.1, -3 * 0.4 / gamma**3], 1e-14)
    expected = central_difference(lambda z: result.rhs(0.0, z, params), y)
    assert_arrays_close(result.rhs_jacobian(0.0, y, params), expected, RTOL, floor=1.0)

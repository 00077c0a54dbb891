"""The numba backend reports what the NumPy backend reports: a singular mass matrix by the
same error, a division by zero as inf (then the integrators' failure), never ZeroDivisionError."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import SingularMassMatrixError
from lagrangian.integrate import simulate
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")


def both(lagrangian: str, coordinates: list[str]):
    eom = lg.System.from_lagrangian(lagrangian, coordinates=coordinates).equations_of_motion()
    return compile_equations(eom), compile_equations(eom, backend="numba")


def test_a_singular_mass_matrix_is_the_same_error_on_both_backends():
    # M = diag(x^2, 1): singular at x = 0, where the numba kernel's pivot is 0
    reference, fast = both("x**2*x_dot**2/2 + y_dot**2/2 - y**2/2", ["x", "y"])
    y0, params = np.array([0.0, 1.0, 0.0, 0.0]), np.empty(0)
    with pytest.raises(SingularMassMatrixError) as expected:
        reference.rhs(0.0, y0, params)
    with pytest.raises(SingularMassMatrixError) as found:
        fast.rhs(0.0, y0, params)
    assert str(found.value) == str(expected.value)
    assert str(found.value).startswith("the mass matrix is singular at t = 0 (x = 0, y = 1)")
    with pytest.raises(SingularMassMatrixError, match=r"^the mass matrix is singular at t = 0"):
        simulate(fast, t_end=1.0, initial={"x": 0.0, "y": 1.0})


def test_a_division_by_zero_gives_the_numpy_value_and_a_failed_run():
    reference, fast = both("x_dot**2/2 + 1/x", ["x"])  # V = -1/x, infinite at x = 0
    y0, params = np.array([0.0, 0.0]), np.empty(0)
    with np.errstate(divide="ignore", invalid="ignore"):
        expected = reference.rhs(0.0, y0, params)
        found = fast.rhs(0.0, y0, params)
    np.testing.assert_array_equal(found, expected)
    trajectory = simulate(fast, t_end=1.0, initial={"x": 0.0})
    assert trajectory.status == "failed"
    assert trajectory.dataset.attrs["message"].startswith(
        "the right-hand side is not finite at t = 0 (x = 0, x_dot = 0)"
    )

"""Method "taylor" (heyoka, optional) against analytic solutions and against DOP853."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.integrate.taylor import Taylor
from lagrangian.numeric import compile_equations

pytest.importorskip("heyoka")


def test_oscillator_matches_the_exact_solution_to_rounding():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 - k*x**2/2", coordinates=["x"], parameters={"m": 2.0, "k": 8.0}
    )
    compiled = compile_equations(system.equations_of_motion())
    params = compiled.parameter_vector({"k": 18.0})  # omega = 3: the parameters are runtime
    grid = np.linspace(0.0, 20.0, 41)
    result = Taylor(tol=1e-15).solve(compiled, (0.0, 20.0), [1.0, 0.0], params, t_eval=grid)
    assert result.success
    np.testing.assert_allclose(result.y[0], np.cos(3 * grid), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result.y[1], -3 * np.sin(3 * grid), rtol=0, atol=1e-11)


def test_double_pendulum_agrees_with_dop853_and_ends_on_t_end():
    system = lg.load("double_pendulum")
    trajectory = system.simulate(t_end=5.0, method="taylor", rtol=1e-14)
    reference = system.simulate(t_end=5.0, method="dop853", rtol=1e-13, atol=1e-13)
    assert trajectory.dataset.attrs["method"] == "taylor"
    assert float(trajectory.dataset["t"][-1]) == 5.0
    for name in ("theta1", "theta2", "theta1_dot", "theta2_dot"):
        assert abs(trajectory.final_state[name] - reference.final_state[name]) < 1e-9


def test_what_taylor_does_not_handle_is_refused():
    system = lg.load("double_pendulum")
    with pytest.raises(ModelError, match="does not apply to method 'taylor'"):
        system.simulate(t_end=1.0, method="taylor", dt=0.01)

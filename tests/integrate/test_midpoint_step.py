"""The midpoint step of one state against the batch step: the lambdified fillers of the
numpy backend (integrate/midpoint_step.py) and the compiled loop of the numba backend
(integrate/compiled_loop.py, the step printed from codegen/steps.py).

The batch step (``Variational._midpoint`` over the NumPy functions) is the reference:
the same iteration on the same equations, so the two agree to rounding, with the
same count of evaluations, on each backend.
"""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.integrate.compiled_loop import compiled_loop
from lagrangian.integrate.midpoint_step import midpoint_functions
from lagrangian.integrate.variational import Variational
from lagrangian.numeric import compile_equations

BACKENDS = ["numpy", pytest.param("numba", marks=pytest.mark.slow)]

DRIVEN = lg.System.from_lagrangian(
    "m*(x_dot**2 + l**2*phi_dot**2 + 2*l*x_dot*phi_dot*cos(phi))/2 + m*g*l*cos(phi)"
    " - k*x**2/2 + x*cos(w*t)",
    coordinates=["x", "phi"],
    parameters={"m": 1.0, "l": 0.8, "g": 9.81, "k": 3.0, "w": 1.3, "b": 0.2},
    forces={"x": "-b*x_dot"},
)


def _runs(compiled, y0, t_end=2.0, dt=0.01):
    params = compiled.parameter_vector()
    integrator = Variational(dt=dt)
    one = integrator.solve(compiled, (0.0, t_end), y0, params)
    batch = integrator.solve(compiled, (0.0, t_end), y0[:, None], params)  # the NumPy step
    return one, batch


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("model", ["double_pendulum", "driven"])
def test_one_state_step_equals_the_batch_step(backend, model):
    system = lg.load(model) if model == "double_pendulum" else DRIVEN
    compiled = compile_equations(system.equations_of_motion(), backend=backend)
    integrator = Variational(dt=0.01)
    loop = compiled_loop(
        compiled, integrator.printed_scheme(compiled), integrator.newton_settings()
    )
    assert (loop is not None) == (backend == "numba")
    assert (midpoint_functions(compiled) is not None) == (backend == "numpy")
    start = {"theta1": 2.0, "theta2": 0.5} if model == "double_pendulum" else {"x": 0.3, "phi": 1}
    y0 = compiled.state_vector(start)
    one, batch = _runs(compiled, y0)
    assert one.settings["scheme"] == "midpoint"
    assert one.status == batch.status
    np.testing.assert_allclose(one.y, batch.y[:, 0, :], rtol=0, atol=1e-11)
    assert one.rhs_evaluations == batch.rhs_evaluations
    assert one.jacobian_evaluations == batch.jacobian_evaluations


def test_a_failing_value_falls_back_to_the_numpy_step():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 + m*y_dot**2/2 - k/x", coordinates=["x", "y"], parameters={"m": 1.0, "k": 1.0}
    )
    compiled = compile_equations(system.equations_of_motion())
    y0 = compiled.state_vector({"x": 0.0, "y": 1.0})  # 1/x at x = 0: inf for NumPy
    one, batch = _runs(compiled, y0, t_end=0.05)
    assert one.status == batch.status
    assert one.message == batch.message

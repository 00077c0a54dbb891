"""Fixed-step single runs in compiled code (integrate/compiled_loop.py) against the Python loop.

On the numba backend rk4 and variational take their steps in the generated loop module
(the numba ensemble's, a chunk of steps per call); the numpy backend steps in Python.
Both take the same steps on the same equations, so they agree to rounding, with the
same counts of steps and evaluations, the same failures, events and energy check.
"""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.integrate import RK4, Event, Status, Variational, simulate
from lagrangian.integrate.compiled_loop import FIRST_CHUNK, compiled_loop
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")
pytestmark = pytest.mark.slow

START = {"theta1": 2.0, "theta2": 0.5}


@pytest.fixture(scope="module")
def pendulums():
    eom = lg.load("double_pendulum").equations_of_motion()
    return {backend: compile_equations(eom, backend=backend) for backend in ("numpy", "numba")}


@pytest.mark.parametrize("integrator", [RK4(dt=0.01), Variational(dt=0.01)], ids=["rk4", "var"])
def test_the_compiled_run_takes_the_python_loops_steps(pendulums, integrator):
    compiled, reference = pendulums["numba"], pendulums["numpy"]
    newton = integrator.newton_settings()
    assert compiled_loop(compiled, integrator.printed_scheme(compiled), newton) is not None
    assert compiled_loop(reference, integrator.printed_scheme(reference), newton) is None
    y0, params = compiled.state_vector(START), compiled.parameter_vector()
    got = integrator.solve(compiled, (0.0, 3.0), y0, params)
    expected = integrator.solve(reference, (0.0, 3.0), y0, params)
    assert got.status == expected.status == Status.SUCCESS
    np.testing.assert_array_equal(got.t, expected.t)
    np.testing.assert_allclose(got.y, expected.y, rtol=0, atol=1e-10)
    assert (got.steps, got.rhs_evaluations, got.jacobian_evaluations) == (
        expected.steps, expected.rhs_evaluations, expected.jacobian_evaluations,
    )  # fmt: skip


def test_progress_is_told_per_chunk_not_per_step(pendulums):
    compiled = pendulums["numba"]
    told = []
    RK4(dt=1e-3).solve(compiled, (0.0, 10.0), compiled.state_vector(START),
                       compiled.parameter_vector(), watch=told.append)  # fmt: skip
    assert told[-1] == 10.0 and told == sorted(told)
    assert len(told) <= 10_000 // FIRST_CHUNK + 1  # 10,000 steps, chunks of 256 or more


def test_a_terminal_event_stops_the_compiled_run_where_the_python_run_stops(pendulums):
    runs = {}
    for backend, compiled in pendulums.items():
        event = Event(lambda t, y, p: y[0], terminal=True, name="theta1_zero")
        runs[backend] = simulate(compiled, t_end=5.0, initial=START, method="rk4", dt=0.01,
                                 events=[event])  # fmt: skip
    got, expected = runs["numba"], runs["numpy"]
    assert got.status == expected.status == "event"
    assert got.t[-1] == pytest.approx(expected.t[-1], abs=1e-12)
    times = [run.events["theta1_zero"].times for run in (got, expected)]
    np.testing.assert_allclose(*times, atol=1e-12)


def test_a_newton_failure_reads_as_in_the_python_loop(pendulums):
    messages = {}
    for backend, compiled in pendulums.items():
        result = Variational(dt=0.05, max_newton=1).solve(
            compiled, (0.0, 1.0), compiled.state_vector(START), compiled.parameter_vector()
        )
        assert result.status == Status.FAILED
        messages[backend] = result.message
    assert messages["numba"] == messages["numpy"]  # both the printed step's
    assert messages["numba"].startswith("Newton's method for the midpoint velocity did not")


def test_a_value_numba_cannot_evaluate_sends_the_run_to_the_python_loop():
    # sqrt(x) of x < 0: numba's math raises where NumPy gives NaN (a state not finite)
    system = lg.System.from_lagrangian("x_dot**2/2 + sqrt(x)", coordinates=["x"])
    eom = system.equations_of_motion()
    results = {}
    for backend in ("numpy", "numba"):
        compiled = compile_equations(eom, backend=backend)
        y0 = compiled.state_vector({"x": 0.01, "x_dot": -1.0})
        results[backend] = RK4(dt=0.004).solve(compiled, (0.0, 0.1), y0,
                                               compiled.parameter_vector())  # fmt: skip
    assert results["numba"].status == results["numpy"].status == Status.FAILED
    assert results["numba"].message == results["numpy"].message
    assert results["numba"].message.startswith("the state is not finite after t = ")

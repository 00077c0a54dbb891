"""Output times of a fixed-step single run (issue 36 item 5): the cubic Hermite
interpolant of the steps, its slopes evaluated in one batched call."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.integrate.registry import method_class
from lagrangian.numeric import compile_equations

DT = 0.05
ERROR = {"rk4": 2e-5, "variational": 2e-2}  # (omega dt)^4 and (omega dt)^2 over 10 s


def forced_oscillator():
    """x'' = -4 x + cos(t): time in the equations, so each slope needs its own time."""
    system = lg.System.from_lagrangian(
        "x_dot**2/2 - 2*x**2", coordinates=["x"], forces={"x": "cos(t)"}
    )
    return compile_equations(system.equations_of_motion(), backend="numpy")


def hermite_by_hand(compiled, result_steps, t):
    """The cubic Hermite interpolant written out from the steps and y' at both ends."""
    times, states = result_steps.t, result_steps.y
    k = min(int(np.searchsorted(times, t, side="right")) - 1, len(times) - 2)
    ta, tb, ya, yb = times[k], times[k + 1], states[:, k], states[:, k + 1]
    fa = compiled.rhs(ta, ya, compiled.parameter_vector())
    fb = compiled.rhs(tb, yb, compiled.parameter_vector())
    h, s = tb - ta, (t - ta) / (tb - ta)
    return (
        (2 * s**3 - 3 * s**2 + 1) * ya + (s**3 - 2 * s**2 + s) * h * fa
        + (-2 * s**3 + 3 * s**2) * yb + (s**3 - s**2) * h * fb
    )  # fmt: skip


@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_outputs_are_the_interpolant_of_the_steps(method):
    compiled = forced_oscillator()
    params, y0 = compiled.parameter_vector(), np.array([1.0, 0.0])
    integrator = method_class(method)(dt=DT)
    steps = integrator.solve(compiled, (0.0, 10.0), y0, params)
    grid = np.array([0.0, 0.012, 0.05, 1.0, 3.3333, 7.77, 9.99, 10.0])
    result = integrator.solve(compiled, (0.0, 10.0), y0, params, t_eval=grid)
    np.testing.assert_array_equal(result.t, grid)
    for j, t in enumerate(grid):
        on_step = np.flatnonzero(steps.t == t)
        if on_step.size:  # a step's own state, not interpolated
            np.testing.assert_array_equal(result.y[:, j], steps.y[:, on_step[0]])
        else:
            expected = hermite_by_hand(compiled, steps, t)
            np.testing.assert_allclose(result.y[:, j], expected, rtol=0, atol=1e-14)
    # and the motion, x = cos(t)/3 + 2 cos(2t)/3, to the method's error (order 4, 2)
    exact = np.cos(grid) / 3 + 2 * np.cos(2 * grid) / 3
    np.testing.assert_allclose(result.y[0], exact, rtol=0, atol=ERROR[method])


def test_the_slopes_of_all_output_times_come_from_one_call():
    compiled = forced_oscillator()
    calls = []

    def rhs(t, y, params):
        calls.append(np.shape(y))
        return compiled.rhs(t, y, params)

    counted = dataclasses.replace(compiled, rhs=rhs)
    grid = np.linspace(0.0, 10.0, 301)
    integrator = method_class("rk4")(dt=DT)
    params = compiled.parameter_vector()
    steps = integrator.solve(counted, (0.0, 10.0), np.array([1.0, 0.0]), params)
    before = len(calls)
    result = integrator.solve(counted, (0.0, 10.0), np.array([1.0, 0.0]), params, t_eval=grid)
    # the same steps again, then every output time between two steps (each of the 200
    # steps holds some): y' at the 201 step ends in one call, 90 us an output time before
    assert calls[2 * before :] == [(2, 201)]
    assert result.rhs_evaluations == steps.rhs_evaluations + 201

"""Terms of L in t alone (f(t) = dF/dt) move nothing: a run and its energy ignore them, also
where they are singular at t = 0 (issue 37 item 10: ``x_dot^2/2 + 1/t`` raised
ZeroDivisionError, ``+ log(t)`` reported the energy "changed by nan")."""

from __future__ import annotations

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis.conserved import energy_function, time_only_terms

OSCILLATOR = "x_dot**2/2 - x**2/2"


@pytest.mark.parametrize("extra", ["1/t", "log(t)", "exp(-t)*k + t**2", "1/t - log(t)/k"])
def test_terms_in_t_alone_leave_the_energy_of_the_oscillator(extra):
    system = lg.System.from_lagrangian(f"{OSCILLATOR} + {extra}", coordinates=["x"])
    x, x_dot = sympy.symbols("x x_dot", real=True)
    h = energy_function(system).subs({c.q: x for c in system.coordinates})
    h = h.subs({c.q_dot: x_dot for c in system.coordinates})
    assert sympy.simplify(h - (x_dot**2 / 2 + x**2 / 2)) == 0
    assert "energy" in [q.name for q in system.conserved_quantities().conserved]


def test_only_the_terms_free_of_the_state_are_left_out():
    system = lg.System.from_lagrangian("x_dot**2/2 + x/t + log(t) + t*x_dot", coordinates=["x"])
    assert time_only_terms(system) == sympy.log(system.time)


@pytest.mark.parametrize("method", ["dop853", "rk4", "variational"])
@pytest.mark.parametrize("extra", ["1/t", "log(t)"])
def test_a_run_from_t_0_is_the_oscillators(method, extra):
    # x = cos t, x' = -sin t: the energy (x^2 + x'^2)/2 = 1/2 all along, finite at t = 0
    system = lg.System.from_lagrangian(f"{OSCILLATOR} + {extra}", coordinates=["x"])
    trajectory = system.simulate(t_end=2.0, initial={"x": 1.0}, method=method)
    t = trajectory.t
    np.testing.assert_allclose(trajectory["x"], np.cos(t), atol=1e-3)
    np.testing.assert_allclose(trajectory["energy"], 0.5, atol=1e-4)
    assert trajectory.energy_not_conserved == ""
    assert trajectory.drift("energy") < 1e-4


@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_a_singular_term_that_reaches_the_equations_fails_the_run_with_its_reason(method):
    # x/t gives x'' = 1/t: infinite at t = 0; Python's 0.0**-1 raised ZeroDivisionError
    system = lg.System.from_lagrangian("x_dot**2/2 + x/t", coordinates=["x"])
    trajectory = system.simulate(t_end=1.0, method=method)
    assert trajectory.status == "failed"
    message = trajectory.dataset.attrs["message"]
    assert message.startswith("the right-hand side is not finite at t = 0 (x = 0, x_dot = 0)")

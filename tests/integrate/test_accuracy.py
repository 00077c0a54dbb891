"""Accuracy against exact solutions, and convergence orders by log-log slope."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ellipk

from lagrangian.integrate import RK4, RK38, Dop853, Event, Variational, simulate

from . import systems

# (method, settings, system, maximum error over t in [0, 10]); measured errors are
# about 10x below each bound (dop853 4e-10, radau 2e-9, rk4 5e-8, variational 2.5e-5 / 5e-5)
OSCILLATOR_CASES = [
    ("dop853", {}, systems.oscillator, 4e-9),
    ("radau", {}, systems.oscillator, 2e-8),
    ("rk4", {"dt": 0.01}, systems.oscillator, 5e-7),
    ("variational", {"dt": 2e-3}, systems.oscillator, 2.5e-4),  # Stormer-Verlet
    ("variational", {"dt": 2e-3}, lambda: systems.oscillator(separable=False), 5e-4),  # midpoint
]


@pytest.mark.slow
@pytest.mark.parametrize(
    ("method", "settings", "build", "bound"),
    OSCILLATOR_CASES,
    ids=["dop853", "radau", "rk4", "verlet", "midpoint"],
)
def test_harmonic_oscillator_follows_the_exact_solution(method, settings, build, bound):
    trajectory = simulate(build(), t_end=10.0, method=method, n_out=101, **settings)
    exact = systems.oscillator_exact(trajectory.t)
    error = np.max(np.abs(np.array([trajectory["x"], trajectory["x_dot"]]) - exact))
    assert error < bound
    assert trajectory.t[-1] == 10.0
    assert trajectory.dataset.attrs["method"] == method


def test_pendulum_period_from_upward_zero_crossings_matches_the_elliptic_integral():
    theta0, length, g = 1.0, 2.0, 9.81
    period = 4 * np.sqrt(length / g) * ellipk(np.sin(theta0 / 2) ** 2)
    upward = Event(lambda t, y, p: y[0], direction=+1, name="upward")
    trajectory = simulate(
        systems.pendulum(theta0=theta0),
        t_end=5.5 * period,
        method="dop853",
        rtol=1e-12,
        atol=1e-12,
        events=[upward],
    )
    times = trajectory.events["upward"].times
    assert len(times) == 5  # released at rest at theta0 > 0: first upward pass at 3T/4
    assert times[0] == pytest.approx(0.75 * period, rel=1e-9)
    np.testing.assert_allclose(np.diff(times), period, rtol=1e-9)


def test_kepler_orbit_returns_to_its_start_after_one_period():
    compiled = systems.kepler()  # e = 0.5, a = 1, mu = 1, started at perihelion
    a, mu = 1.0, 1.0
    period = 2 * np.pi * a**1.5 / np.sqrt(mu)
    trajectory = simulate(compiled, t_end=period, method="dop853", rtol=1e-12, atol=1e-12)
    final = np.array(list(trajectory.final_state.values()))
    np.testing.assert_allclose(final, compiled.state_vector(), atol=1e-8)
    # halfway round: at aphelion, r = a (1 + e) on the negative x axis
    half = simulate(compiled, t_end=period / 2, method="dop853", rtol=1e-12, atol=1e-12)
    assert half.final_state["x"] == pytest.approx(-1.5, abs=1e-9)
    assert half.final_state["y"] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("method", "orbits", "phase_error"),
    [
        (Variational(dt=2e-3), 10, 0.02),  # Stormer-Verlet
        (Variational(dt=4e-3, explicit_when_separable=False), 2, 0.02),  # midpoint
    ],
    ids=["verlet", "midpoint"],
)
def test_variational_kepler_keeps_angular_momentum_to_rounding(method, orbits, phase_error):
    # discrete Noether: both discrete Lagrangians are invariant under rotations
    compiled = systems.kepler()
    trajectory = simulate(compiled, t_end=orbits * 2 * np.pi, method=method)
    assert trajectory.drift("angular_momentum") < 1e-13
    assert trajectory.drift("energy") < 2e-4  # O(h^2), bounded (no secular growth)
    final = np.array(list(trajectory.final_state.values()))
    np.testing.assert_allclose(final, compiled.state_vector(), atol=phase_error)


# -- convergence orders --------------------------------------------------------------
def _slope(steps, errors) -> float:
    return float(np.polyfit(np.log(steps), np.log(errors), 1)[0])


def _final(method, compiled, t_end):
    result = method.solve(
        compiled, (0.0, t_end), compiled.state_vector(), compiled.parameter_vector()
    )
    assert result.t[-1] == t_end
    return result.y[:, -1]


def _reference(compiled, t_end):
    return _final(Dop853(rtol=1e-13, atol=1e-14), compiled, t_end)


STEPS = np.array([0.1, 0.05, 0.025, 0.0125])


@pytest.mark.parametrize("method", [RK4, RK38], ids=["rk4", "rk38"])
def test_explicit_runge_kutta_converges_with_order_four(method):
    compiled = systems.pendulum()
    reference = _reference(compiled, 2.0)
    errors = [np.max(np.abs(_final(method(dt=h), compiled, 2.0) - reference)) for h in STEPS]
    assert _slope(STEPS, errors) == pytest.approx(4.0, abs=0.2)  # measured 4.08 / 4.09


@pytest.mark.parametrize(
    ("build", "explicit"),
    [
        (systems.pendulum, True),  # Stormer-Verlet
        (lambda: systems.pendulum(separable=False), True),  # midpoint, via the flag
        (systems.pendulum, False),  # midpoint, explicit scheme disabled
        (systems.spherical_pendulum, True),  # midpoint, position-dependent mass matrix
    ],
    ids=["verlet", "midpoint-nonseparable", "midpoint-forced", "spherical"],
)
def test_variational_converges_with_order_two(build, explicit):
    compiled = build()
    reference = _reference(compiled, 2.0)
    steps = STEPS / 2.5 if compiled.n == 2 else STEPS
    errors = [
        np.max(
            np.abs(
                _final(Variational(dt=h, explicit_when_separable=explicit), compiled, 2.0)
                - reference
            )
        )
        for h in steps
    ]
    assert _slope(steps, errors) == pytest.approx(2.0, abs=0.2)  # measured 1.99 to 2.00


def test_variational_with_damping_converges_with_order_two_to_the_exact_solution():
    # the discrete Lagrange-d'Alembert principle with midpoint forces
    compiled = systems.oscillator(damping=0.3)
    exact = systems.oscillator_exact(2.0, b=0.3)
    errors = [np.max(np.abs(_final(Variational(dt=h), compiled, 2.0) - exact)) for h in STEPS]
    assert _slope(STEPS, errors) == pytest.approx(2.0, abs=0.2)  # measured 2.00


def test_a_final_partial_step_lands_exactly_on_t_end():
    compiled = systems.oscillator()
    result = RK4(dt=0.3).solve(
        compiled, (0.0, 1.0), compiled.state_vector(), compiled.parameter_vector()
    )
    np.testing.assert_allclose(np.diff(result.t), [0.3, 0.3, 0.3, 0.1])
    assert result.t[-1] == 1.0
    assert result.steps == 4
    assert result.rhs_evaluations == 16  # work counted: 4 stages per step, nothing else

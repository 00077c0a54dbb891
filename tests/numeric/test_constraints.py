"""Constrained systems: multipliers as physical forces, residuals, projection, drift.

Cartesian pendulum, x^2 + y^2 - l^2 = 0 with multiplier lambda: the constraint
force on the bob is lambda (2x, 2y), the string pulls inward with the tension
T = m (g cos(theta) + l w^2) (theta from the downward vertical, w = theta'),
so lambda = -T / (2 l).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.numeric import compile_equations

from .cases import arguments, assert_arrays_close, compiled, point


@pytest.fixture(scope="module")
def pendulum():
    return compile_equations(lg.load("cartesian_pendulum").equations_of_motion())


def on_circle(l: float, theta: float, w: float) -> np.ndarray:
    return np.array(
        [
            l * math.sin(theta),
            -l * math.cos(theta),
            l * w * math.cos(theta),
            l * w * math.sin(theta),
        ]
    )


def test_multiplier_is_the_string_tension(pendulum, rng):
    assert pendulum.constraint_names == ("lambda1",)
    assert pendulum.constraint_holonomic == (True,)
    for _ in range(5):
        m, l, g = rng.uniform(0.5, 2), rng.uniform(0.5, 2), rng.uniform(1, 10)
        theta, w = rng.uniform(-3, 3), rng.uniform(-2, 2)
        params = pendulum.parameter_vector({"m": m, "l": l, "g": g})
        tension = m * (g * math.cos(theta) + l * w**2)
        lam = pendulum.multipliers(0.0, on_circle(l, theta, w), params)
        assert_arrays_close(lam, [-tension / (2 * l)], 1e-12, "lambda")
        # and the accelerations are those of the pendulum: theta'' = -g sin(theta) / l
        x_ddot, y_ddot = pendulum.rhs(0.0, on_circle(l, theta, w), params)[2:]
        alpha = -g * math.sin(theta) / l
        expected = [
            l * (alpha * math.cos(theta) - w**2 * math.sin(theta)),
            l * (alpha * math.sin(theta) + w**2 * math.cos(theta)),
        ]
        assert_arrays_close([x_ddot, y_ddot], expected, 1e-12, "accelerations")


def test_residual_is_position_level_for_holonomic_constraints(pendulum):
    params = pendulum.parameter_vector({"l": 1.0})
    y = np.array([0.6, -0.9, 0.3, 0.1])
    assert_arrays_close(pendulum.constraint_residual(0.0, y, params), [0.6**2 + 0.9**2 - 1], 1e-15)
    assert_arrays_close(
        pendulum.constraint_velocity_residual(0.0, y, params), [2 * (0.6 * 0.3 - 0.9 * 0.1)], 1e-15
    )


def test_project_is_radial_and_tangent_for_the_pendulum(pendulum, rng):
    """With M = m I the M-weighted correction is the Euclidean one: q -> l q / |q|."""
    for _ in range(5):
        l = rng.uniform(0.5, 2)
        params = pendulum.parameter_vector({"l": l})
        y = np.array([rng.uniform(-2, 2) for _ in range(4)])
        projected = pendulum.project(0.0, y, params)
        assert abs(pendulum.constraint_residual(0.0, projected, params)[0]) < 1e-12
        assert abs(pendulum.constraint_velocity_residual(0.0, projected, params)[0]) < 1e-12
        q = y[:2] * l / np.linalg.norm(y[:2])
        u = q / l
        v = y[2:] - (y[2:] @ u) * u
        assert_arrays_close(projected, [*q, *v], 1e-12, "projection")


@pytest.mark.parametrize("name", ["cartesian_pendulum", "rolling_disc"])
def test_project_lands_on_the_manifold(name, rng):
    system = compiled(name)
    states = [arguments(system, point(name, rng)) for _ in range(4)]
    for t, y, params in states:
        projected = system.project(t, y, params)
        assert np.max(np.abs(system.constraint_residual(t, projected, params))) < 1e-12
        assert np.max(np.abs(system.constraint_velocity_residual(t, projected, params))) < 1e-12
        again = system.project(t, projected, params)
        assert_arrays_close(again, projected, 1e-13, "a projected state stays")
    batch = np.stack([y for _, y, _ in states], axis=-1)
    params = np.stack([p for _, _, p in states], axis=-1)
    projected = system.project(0.0, batch, params)
    assert np.max(np.abs(system.constraint_residual(0.0, projected, params))) < 1e-12
    single = system.project(0.0, batch[:, 0], params)  # one state, a batch of parameters
    assert single.shape == batch.shape
    assert np.max(np.abs(system.constraint_residual(0.0, single, params))) < 1e-12


def test_nonholonomic_residual_is_velocity_level():
    system = compiled("rolling_disc")
    assert system.constraint_holonomic == (False, False)
    params = system.parameter_vector({"R": 0.5})
    # x, y, phi, theta, then velocities
    y = np.array([0.0, 0.0, 0.3, 0.0, 1.0, 0.2, 0.5, 2.0])
    expected = [1.0 - 0.5 * math.cos(0.3) * 2.0, 0.2 - 0.5 * math.sin(0.3) * 2.0]
    assert_arrays_close(system.constraint_residual(0.0, y, params), expected, 1e-15)
    projected = system.project(0.0, y, params)
    assert_arrays_close(projected[:4], y[:4], 0.0, "positions untouched")


def test_baumgarte_keeps_the_drift_small(pendulum):
    """Over 10 s of DOP853 the residual stays small with stabilisation, and projecting
    the final state brings it to rounding level."""
    params = pendulum.parameter_vector()
    y0 = pendulum.state_vector()
    solution = solve_ivp(
        lambda t, y: pendulum.rhs(t, y, params),
        (0.0, 10.0),
        y0,
        method="DOP853",
        rtol=1e-9,
        atol=1e-9,
    )
    assert solution.success
    drift = np.abs(pendulum.constraint_residual(0.0, solution.y, params)).max()
    assert drift < 1e-9  # about 4e-8 without stabilisation
    energy = pendulum.energy(0.0, solution.y, params)
    assert np.ptp(energy) < 1e-5 * abs(energy[0]) + 1e-6
    final = pendulum.project(0.0, solution.y[:, -1], params)
    assert abs(pendulum.constraint_residual(0.0, final, params)[0]) < 1e-12


def test_unconstrained_systems_have_no_constraint_functions():
    system = compiled("double_pendulum")
    assert not system.has_constraints
    assert system.multipliers is None and system.project is None
    assert system.constraint_residual is None and system.constraint_names == ()


def test_a_moving_constraint():
    """A bead on a wire turning at rate w, in Cartesian coordinates: -x sin(wt) + y cos(wt) = 0.

    Along the wire r'' = w^2 r, so the Cartesian acceleration is the Coriolis
    term 2 r' w e_phi; the residuals depend on t explicitly."""
    w = 1.5
    system = lg.System.from_particles(
        coordinates=["x", "y"],
        particles=[lg.Particle("bead", "m", ["x", "y"])],
        constraints=["-x*sin(w*t) + y*cos(w*t)"],
        parameters={"m": 1.0, "w": w},
    )
    result = compile_equations(system.equations_of_motion())
    params = result.parameter_vector()
    t, r, r_dot = 0.7, 1.2, 0.4
    c, s = math.cos(w * t), math.sin(w * t)
    y = np.array([r * c, r * s, r_dot * c - r * w * s, r_dot * s + r * w * c])
    assert_arrays_close(
        result.rhs(t, y, params)[2:], [-2 * r_dot * w * s, 2 * r_dot * w * c], 1e-12
    )
    assert abs(result.constraint_velocity_residual(t, y, params)[0]) < 1e-14
    projected = result.project(t, y + 0.1, params)
    assert abs(result.constraint_residual(t, projected, params)[0]) < 1e-12
    assert abs(result.constraint_velocity_residual(t, projected, params)[0]) < 1e-12
    assert "energy" not in result.invariants  # the wire does work

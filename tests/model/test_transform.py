"""Point transformations: the physics does not depend on the coordinates."""

from __future__ import annotations

import random

import pytest
import sympy

import lagrangian as lg


def kepler_cartesian():
    return lg.System.from_energies(
        "m*(x_dot^2 + y_dot^2)/2",
        "-mu*m/sqrt(x^2 + y^2)",
        ["x", "y"],
        forces={"x": "-b*x_dot", "y": "-b*y_dot"},
    )


def test_cartesian_to_polar_gives_the_polar_equations():
    polar = kepler_cartesian().change_coordinates(
        ["r", "theta"], {"x": "r*cos(theta)", "y": "r*sin(theta)"}
    )
    eom = polar.equations_of_motion()
    r, r_dot, theta_dot, mu, b, m = (
        polar.symbol(n) for n in ("r", "r_dot", "theta_dot", "mu", "b", "m")
    )
    at_positive_r = {r: sympy.Symbol("r", positive=True)}
    expected_r = r * theta_dot**2 - mu / r**2 - b * r_dot / m
    assert sympy.simplify((eom.accelerations["r"] - expected_r).xreplace(at_positive_r)) == 0
    expected_theta = -2 * r_dot * theta_dot / r - b * theta_dot / m
    assert sympy.simplify(eom.accelerations["theta"] - expected_theta) == 0


def test_rotating_frame_shows_coriolis_and_centrifugal_terms():
    frame = kepler_cartesian().change_coordinates(
        ["u", "v"], {"x": "u*cos(w*t) - v*sin(w*t)", "y": "u*sin(w*t) + v*cos(w*t)"}
    )
    assert "w" in frame.parameter_names
    eom = frame.equations_of_motion()
    u, v, u_dot, v_dot, w, mu, b, m = (
        frame.symbol(n) for n in ("u", "v", "u_dot", "v_dot", "w", "mu", "b", "m")
    )
    # a damped force in the inertial frame, -b v_inertial, seen in the rotating frame
    expected_u = (
        2 * w * v_dot
        + w**2 * u
        - mu * u / (u**2 + v**2) ** sympy.Rational(3, 2)
        - b * (u_dot - w * v) / m
    )
    assert sympy.simplify(eom.accelerations["u"] - expected_u) == 0


def test_same_motion_in_both_coordinates():
    cartesian = lg.load("double_pendulum")
    # theta1 = a + b, theta2 = a - b
    mixed = cartesian.change_coordinates(["a", "b"], {"theta1": "a + b", "theta2": "a - b"})
    eom_c, eom_m = cartesian.equations_of_motion(), mixed.equations_of_motion()
    rng = random.Random(11)
    values = {n: rng.uniform(0.5, 2) for n in cartesian.parameter_names}
    for _ in range(3):
        a, b, a_dot, b_dot = (rng.uniform(-1, 1) for _ in range(4))
        point_m = {
            mixed.symbol(k): v for k, v in {"a": a, "b": b, "a_dot": a_dot, "b_dot": b_dot}.items()
        }
        point_m |= {mixed.symbol(k): v for k, v in values.items()}
        point_c = {
            cartesian.symbol("theta1"): a + b,
            cartesian.symbol("theta2"): a - b,
            cartesian.symbol("theta1_dot"): a_dot + b_dot,
            cartesian.symbol("theta2_dot"): a_dot - b_dot,
        } | {cartesian.symbol(k): v for k, v in values.items()}
        a_ddot = float(eom_m.accelerations["a"].xreplace(point_m))
        b_ddot = float(eom_m.accelerations["b"].xreplace(point_m))
        assert a_ddot + b_ddot == pytest.approx(
            float(eom_c.accelerations["theta1"].xreplace(point_c))
        )
        assert a_ddot - b_ddot == pytest.approx(
            float(eom_c.accelerations["theta2"].xreplace(point_c))
        )


def test_bad_transformations():
    system = kepler_cartesian()
    with pytest.raises(lg.ModelError, match="every old coordinate"):
        system.change_coordinates(["r", "theta"], {"x": "r*cos(theta)"})
    with pytest.raises(lg.ModelError, match="not invertible"):
        system.change_coordinates(["r", "theta"], {"x": "r", "y": "2*r"})


def test_particles_without_a_potential_change_coordinates():
    """A free particle (no potential given) in polar coordinates: V stays 0, T = m (r'^2 +
    r^2 theta'^2)/2."""
    system = lg.System.from_particles(["x", "y"], [lg.Particle("p", "m", ("x", "y"))])
    polar = system.change_coordinates(["r", "theta"], {"x": "r*cos(theta)", "y": "r*sin(theta)"})
    m, r = polar.symbol("m"), polar.symbol("r")
    r_dot, theta_dot = polar.symbol("r_dot"), polar.symbol("theta_dot")
    assert polar.potential == 0
    assert sympy.simplify(polar.kinetic - m * (r_dot**2 + r**2 * theta_dot**2) / 2) == 0

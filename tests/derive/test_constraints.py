"""Constraints by Lagrange multipliers: the multipliers are the constraint forces."""

from __future__ import annotations

import random

import pytest
import sympy

import lagrangian as lg


def cartesian_pendulum():
    return lg.System.from_particles(
        ["x", "y"],
        [lg.Particle("bob", "m", ("x", "y"))],
        gravity=lg.Gravity("g"),
        constraints=["x^2 + y^2 - l^2"],
    )


def test_cartesian_pendulum_multiplier_is_the_tension():
    system = cartesian_pendulum()
    eom = system.equations_of_motion()
    m, g, l = (system.symbol(n) for n in ("m", "g", "l"))
    rng = random.Random(5)
    for _ in range(5):
        theta, omega = rng.uniform(-2, 2), rng.uniform(-2, 2)
        values = {m: 1.3, g: 9.81, l: 0.8}
        state = {
            system.symbol("x"): 0.8 * sympy.sin(theta),
            system.symbol("y"): -0.8 * sympy.cos(theta),
            system.symbol("x_dot"): 0.8 * omega * sympy.cos(theta),
            system.symbol("y_dot"): 0.8 * omega * sympy.sin(theta),
        }
        tension = 1.3 * (9.81 * sympy.cos(theta) + 0.8 * omega**2)  # m (g cos + l w^2)
        lam = eom.multipliers["lambda1"].xreplace(values | state)
        # force on the bob: lambda * grad(x^2 + y^2 - l^2) = 2 lambda r, pointing inward
        assert float(-2 * lam * 0.8) == pytest.approx(float(tension), rel=1e-12)
        # and the accelerations agree with the pendulum's theta'' = -g/l sin(theta)
        x_ddot = eom.accelerations["x"].xreplace(values | state)
        theta_ddot = -9.81 / 0.8 * sympy.sin(theta)
        expected = 0.8 * (theta_ddot * sympy.cos(theta) - omega**2 * sympy.sin(theta))
        assert float(x_ddot) == pytest.approx(float(expected), rel=1e-12, abs=1e-12)


def test_rolling_disc_on_a_plane():
    system = lg.System.from_energies(
        "m*(x_dot^2 + y_dot^2)/2 + I1*phi_dot^2/2 + I3*theta_dot^2/2",
        0,
        ["x", "y", "phi", "theta"],
        constraints=["x_dot - R*cos(phi)*theta_dot", "y_dot - R*sin(phi)*theta_dot"],
    )
    eom = system.equations_of_motion()
    R, phi, phi_dot, theta_dot, m = (
        system.symbol(n) for n in ("R", "phi", "phi_dot", "theta_dot", "m")
    )
    assert sympy.simplify(eom.accelerations["x"] + R * phi_dot * theta_dot * sympy.sin(phi)) == 0
    assert eom.accelerations["theta"] == 0 and eom.accelerations["phi"] == 0
    lam1 = eom.multipliers["lambda1"]
    assert sympy.simplify(lam1 + R * m * phi_dot * theta_dot * sympy.sin(phi)) == 0


def test_constraint_errors():
    with pytest.raises(lg.ModelError, match="linear in the velocities"):
        lg.System.from_energies(
            "m*x_dot^2/2 + m*y_dot^2/2", 0, ["x", "y"], constraints=["x_dot^2 - y_dot"]
        ).equations_of_motion()
    with pytest.raises(lg.ModelError, match="not independent"):
        lg.System.from_energies(
            "m*x_dot^2/2 + m*y_dot^2/2", 0, ["x", "y"], constraints=["x - y", "2*x - 2*y"]
        ).equations_of_motion()


def test_json_reports_multipliers():
    from lagrangian.output import derive_document

    document = derive_document(cartesian_pendulum().equations_of_motion())
    assert document["constraints"] == ["-l**2 + x**2 + y**2"]
    assert set(document["multipliers"]) == {"lambda1"}

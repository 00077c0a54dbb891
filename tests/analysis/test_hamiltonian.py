"""Legendre transform: H and Hamilton's equations against hand results."""

from __future__ import annotations

import sympy

import lagrangian as lg
from lagrangian.analysis.hamiltonian import hamiltonian


def same(a, b):
    return sympy.simplify(a - b) == 0


def test_spherical_pendulum_hamiltonian():
    system = lg.load("spherical_pendulum")
    h = hamiltonian(system.equations_of_motion())
    m, l, g, theta = (system.symbol(n) for n in ("m", "l", "g", "theta"))
    p_theta, p_phi = h.momenta["theta"], h.momenta["phi"]
    expected = (
        p_theta**2 / (2 * m * l**2)
        + p_phi**2 / (2 * m * l**2 * sympy.sin(theta) ** 2)
        - m * g * l * sympy.cos(theta)
    )
    assert same(h.expression, expected)


def test_charged_particle_uses_canonical_momentum():
    system = lg.System.from_lagrangian(
        "m*(x_dot^2 + y_dot^2)/2 + q*B*(x*y_dot - y*x_dot)/2", ["x", "y"]
    )
    h = hamiltonian(system.equations_of_motion())
    m, q, B, x, y = (system.symbol(n) for n in ("m", "q", "B", "x", "y"))
    px, py = h.momenta["x"], h.momenta["y"]
    expected = ((px + q * B * y / 2) ** 2 + (py - q * B * x / 2) ** 2) / (2 * m)
    assert same(h.expression, expected)


def test_hamilton_equations_reproduce_lagrange():
    system = lg.load("double_pendulum")
    eom = system.equations_of_motion()
    h = hamiltonian(eom)
    # q' from Hamilton's equations equals the velocity used to build H
    for name, (q_rate, _) in h.equations.items():
        assert same(q_rate, h.velocities[name])
    # p' = -dH/dq equals d/dt(dL/dq') along the motion, at a sample point
    point = {
        system.symbol("theta1"): 0.3,
        system.symbol("theta2"): -0.7,
        system.symbol("theta1_dot"): 0.4,
        system.symbol("theta2_dot"): 1.1,
    }
    point |= {
        p.symbol: v for p, v in zip(system.parameters, [1.0, 2.0, 1.5, 0.7, 9.81], strict=True)
    }
    momenta = {h.momenta[s.coordinate.name]: s.momentum.xreplace(point) for s in eom.steps}
    for step in eom.steps:
        rate = sum(
            (
                sympy.diff(step.momentum, c.q) * c.q_dot
                + sympy.diff(step.momentum, c.q_dot) * eom.accelerations[c.name]
                for c in system.coordinates
            ),
            sympy.Integer(0),
        )
        _, p_rate = h.equations[step.coordinate.name]
        assert (
            abs(float(rate.xreplace(point)) - float(p_rate.xreplace(point).xreplace(momenta)))
            < 1e-9
        )

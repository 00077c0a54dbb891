"""Steady motions for given cyclic momenta, and the small oscillations about them.

Closed forms: the conical pendulum (Omega^2 = g/(l cos theta0), radial
omega^2 = Omega^2 (1 + 3 cos^2 theta0)) and the circular Kepler orbit
(r0 = p^2/mu, omega^2 = mu^4/p^6 = the orbital angular velocity squared).
"""

from __future__ import annotations

import math

import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis import SteadyMotion


@pytest.mark.parametrize("p_phi", [0.3, 1.0, 4.0])
def test_conical_pendulum(p_phi):
    system = lg.load("spherical_pendulum")
    motions = system.steady_motions(momenta={"p_phi": p_phi})
    assert motions and all(isinstance(s, SteadyMotion) for s in motions)
    g, l, m = 9.81, 1.0, 1.0
    for steady in motions:
        theta0 = float(steady.point["theta"])
        spin = float(steady.velocities["phi"])
        # the momentum is the one asked for: p = m l^2 sin^2(theta0) phi'
        assert m * l**2 * math.sin(theta0) ** 2 * spin == pytest.approx(p_phi, rel=1e-9)
        assert spin**2 == pytest.approx(g / (l * math.cos(theta0)), rel=1e-9)
        (omega_squared,) = (float(w) for w in steady.omega_squared)
        expected = g / (l * math.cos(theta0)) * (1 + 3 * math.cos(theta0) ** 2)
        assert omega_squared == pytest.approx(expected, rel=1e-8)
        assert steady.stable


def test_kepler_circular_orbit_symbolic_and_for_a_given_momentum():
    system = lg.load("central_force")
    mu = system.symbol("mu")
    (orbit,) = system.steady_motions()
    p = orbit.momenta["p_theta"]
    assert sympy.simplify(orbit.point["r"] - p**2 / mu) == 0
    assert sympy.simplify(orbit.velocities["theta"] - mu**2 / p**3) == 0
    (omega_squared,) = orbit.omega_squared
    assert sympy.simplify(omega_squared - orbit.velocities["theta"] ** 2) == 0
    (given,) = system.steady_motions(momenta={"p_theta": 2.0})
    assert float(given.momenta["p_theta"]) == 2.0
    r0 = given.point["r"].xreplace({p: 2.0, mu: 1.0})
    assert float(r0) == pytest.approx(4.0)


def test_analyze_reports_the_steady_motion_with_its_turning_rate():
    from lagrangian.output.analysis import analysis_document, format_analysis

    analysis = lg.load("central_force").analyze(timeout=None)
    assert "turning at θ̇ = " in format_analysis(analysis)
    (steady,) = analysis_document(analysis)["steady_motions"]
    assert set(steady["cyclic_velocities"]) == {"theta"}


def test_constrained_systems_have_equilibria_through_the_system():
    system = lg.load("cartesian_pendulum")
    g, l = system.symbol("g"), system.symbol("l")
    found = {e.point["y"]: e for e in system.equilibria()}
    assert set(found) == {-l, l}
    assert found[-l].omega_squared == (g / l,) and found[-l].stable
    assert not found[l].stable


@pytest.mark.slow
def test_analyze_takes_values_of_the_cyclic_momenta(capsys):
    from lagrangian.cli import ExitStatus, main

    analysis = lg.load("spherical_pendulum").analyze(momenta={"p_phi": 1.0}, timeout=None)
    assert len(analysis.steady_motions) == 2
    for steady in analysis.steady_motions:
        theta0 = float(steady.point["theta"])
        assert float(steady.velocities["phi"]) ** 2 == pytest.approx(9.81 / math.cos(theta0))
    argv = ["analyze", "spherical_pendulum", "--momentum", "p_phi=1", "--json", "--timeout", "600"]
    assert main(argv) == 0
    assert "cyclic_velocities" in capsys.readouterr().out
    status = main(["analyze", "spherical_pendulum", "--momentum", "p_x=1"])
    assert status == ExitStatus.BAD_INPUT
    err = capsys.readouterr().err
    assert err == (
        "lagrangian: error: not momenta of cyclic coordinates: p_x (cyclic momenta: p_phi)\n"
    )

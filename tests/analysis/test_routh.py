"""Routhian reduction: effective potentials, steady motions (Kepler orbits, conical pendulum)."""

from __future__ import annotations

import math

import pytest
import sympy

import lagrangian as lg
from lagrangian.algebra import squares_combined
from lagrangian.analysis.linear import Stability
from lagrangian.analysis.routh import reduce, steady_motions


def same(a, b):
    return sympy.simplify(a - b) == 0


def test_central_force_routhian_and_effective_potential():
    eom = lg.load("central_force").equations_of_motion()
    reduction = reduce(eom)
    s = reduction.system.symbol
    r, r_dot, mu, p = s("r"), s("r_dot"), s("mu"), s("p_theta")
    assert reduction.cyclic == ("theta",)
    assert reduction.momenta == {"theta": p}
    assert same(reduction.velocities["theta"], p / r**2)
    assert same(reduction.routhian, r_dot**2 / 2 - p**2 / (2 * r**2) + mu / r)
    assert same(reduction.effective_potential, p**2 / (2 * r**2) - mu / r)
    assert reduction.system.coordinate_names == ("r",)
    momentum = next(q for q in reduction.system.parameters if q.name == "p_theta")
    assert momentum.default is None and momentum.sign == "real"


def test_reduced_equation_is_the_radial_equation_with_theta_dot_eliminated():
    eom = lg.load("central_force").equations_of_motion()
    reduction = reduce(eom)
    reduced = reduction.system.equations_of_motion()
    original = eom.acceleration("r").xreplace(
        {eom.system.symbol("theta_dot"): reduction.velocities["theta"]}
    )
    assert same(reduced.acceleration("r"), original)


def test_kepler_circular_orbit_and_its_radial_frequency():
    (orbit,) = steady_motions(lg.load("central_force").equations_of_motion())
    reduced = reduce(lg.load("central_force").equations_of_motion()).system
    mu, p = reduced.symbol("mu"), reduced.symbol("p_theta")
    r0 = orbit.point["r"]
    assert same(r0, p**2 / mu)
    assert same(orbit.omega_squared[0], mu / r0**3)  # = the orbital frequency squared
    assert orbit.modes.stability is Stability.STABLE


def test_spherical_pendulum_effective_potential():
    system = lg.load("spherical_pendulum")
    reduction = reduce(system.equations_of_motion())
    s = reduction.system.symbol
    m, l, g, theta, p = s("m"), s("l"), s("g"), s("theta"), s("p_phi")
    by_hand = p**2 / (2 * m * l**2 * sympy.sin(theta) ** 2) + m * g * l * (1 - sympy.cos(theta))
    difference = reduction.effective_potential - by_hand
    assert sympy.simplify(sympy.diff(difference, theta)) == 0  # equal up to a constant
    assert reduction.system.coordinate_names == ("theta",)


def test_conical_pendulum_steady_motion_and_stability():
    eom = lg.load("spherical_pendulum").equations_of_motion()
    motions = steady_motions(eom, momenta={"p_phi": 2.0})
    assert len(motions) == 2  # theta0 and its mirror image -theta0
    m = l = 1.0
    g = 9.81
    for motion in motions:
        assert motion.numeric and motion.modes.stability is Stability.STABLE
        theta0 = float(motion.point["theta"])
        spin_squared = (2.0 / (m * l**2 * math.sin(theta0) ** 2)) ** 2  # phi_dot^2
        assert abs(spin_squared * math.cos(theta0) - g / l) < 1e-9 * g
        expected = spin_squared * (1 + 3 * math.cos(theta0) ** 2)
        assert abs(float(motion.omega_squared[0]) - expected) < 1e-9 * expected
    assert sorted(float(e.point["theta"]) for e in motions)[0] < 0


def test_steady_motions_of_a_spherical_pendulum_need_a_momentum_value():
    # SymPy finds no closed form for p^2 cos(theta) = m^2 l^3 g sin^4(theta)
    with pytest.raises(lg.ModelError, match="default values for p_phi"):
        steady_motions(lg.load("spherical_pendulum").equations_of_motion())


def test_free_particle_has_no_steady_motion_at_fixed_r_and_theta():
    eom = lg.load("free_particle_spherical").equations_of_motion()
    reduction = reduce(eom)
    assert reduction.cyclic == ("phi",)
    assert reduction.system.coordinate_names == ("r", "theta")
    assert steady_motions(eom) == ()


def test_forces_on_the_remaining_coordinates_are_kept():
    system = lg.System.from_lagrangian(
        "(r_dot**2 + r**2*theta_dot**2)/2 + mu/r",
        coordinates=["r", "theta"],
        forces={"r": "-b*r_dot*theta_dot**2"},
    )
    reduction = reduce(system.equations_of_motion())
    s = reduction.system.symbol
    r, r_dot, b, p = s("r"), s("r_dot"), s("b"), s("p_theta")
    assert same(reduction.system.forces["r"], -b * r_dot * p**2 / r**4)


def test_nothing_to_reduce():
    with pytest.raises(lg.ModelError, match="no cyclic coordinate"):
        reduce(lg.load("simple_pendulum").equations_of_motion())
    drag = lg.System.from_lagrangian(
        "(r_dot**2 + r**2*theta_dot**2)/2 + mu/r",
        coordinates=["r", "theta"],
        dissipation="b*theta_dot**2/2",
    )
    with pytest.raises(lg.ModelError, match="no cyclic coordinate"):
        reduce(drag.equations_of_motion())
    free = lg.System.from_lagrangian("m*x_dot**2/2", coordinates=["x"])
    with pytest.raises(lg.ModelError, match="every coordinate is cyclic"):
        reduce(free.equations_of_motion())
    with pytest.raises(lg.ModelError, match="p_r"):
        reduce(lg.load("central_force").equations_of_motion(), momenta={"p_r": 1.0})


@pytest.mark.slow
def test_heavy_top_routhian_is_tidy():
    # (I1 + M l^2) sin^2 θ, not I1 sin^2 - I3 sin^2 - I3 cos^2 + I3 + M l^2 sin^2 (issue 22):
    # R = ½ (I1 + M l²) θ'² - (p_φ - p_ψ cos θ)²/(2 (I1 + M l²) sin² θ) - p_ψ²/(2 I3) - M g l cos θ
    system = lg.load("heavy_top")
    reduction = reduce(system.equations_of_motion())
    I1, I3, M, g, l = (system.symbol(n) for n in ("I1", "I3", "M", "g", "l"))
    theta, theta_dot = system.symbol("theta"), system.symbol("theta_dot")
    named = {s.name: s for s in reduction.routhian.free_symbols}
    p_phi, p_psi = named["p_phi"], named["p_psi"]
    textbook = (
        (I1 + M * l**2) * theta_dot**2 / 2
        - (p_phi - p_psi * sympy.cos(theta)) ** 2 / (2 * (I1 + M * l**2) * sympy.sin(theta) ** 2)
        - p_psi**2 / (2 * I3)
        - M * g * l * sympy.cos(theta)
    )
    assert sympy.simplify(reduction.routhian - textbook) == 0
    assert len(str(reduction.routhian)) < 250 and len(str(reduction.effective_potential)) < 250
    assert "cos(theta)**2" not in str(reduction.routhian).split("/")[-1]  # the denominator


def test_squares_of_sines_and_cosines_combined():
    a, b, x = sympy.symbols("a b x", positive=True)
    s, c = sympy.sin(x), sympy.cos(x)
    assert squares_combined(a * s**2 - b * s**2 - b * c**2 + b) == a * s**2
    assert squares_combined(a * s**2 + b * c**2) == a * s**2 + b * c**2  # nothing shorter
    assert squares_combined(1 / (a * s**2 + a * c**2 + b)) == 1 / (a + b)

"""Symbolic omega^2: the verdict is said to hold at the defaults, and the condition is given.

The condition is checked against the closed form's sign at random parameter
values (both sides of the boundary), not against its printed text alone.
"""

from __future__ import annotations

import json
import random

import sympy

import lagrangian as lg
from lagrangian.analysis import analyze
from lagrangian.model import Gravity, Particle
from lagrangian.output.analysis import analysis_document, format_analysis, latex_analysis


def turning(position, coordinate, **parameters):
    bead = Particle("bead", "m", position)
    return lg.System.from_particles(
        [coordinate],
        [bead],
        gravity=Gravity(g="g", direction=(0, 0, -1)),
        parameters={"m": 1.0, "g": 9.81, "omega": 2.0} | parameters,
    )


def parabola():
    """A bead on the parabola z = a r^2 turning at omega about its axis."""
    return turning(("r*cos(omega*t)", "r*sin(omega*t)", "a*r**2"), "r", a=1.0)


def hoop():
    """A bead on a hoop of radius R turning at omega about the vertical."""
    return turning(
        ("R*sin(theta)*cos(omega*t)", "R*sin(theta)*sin(omega*t)", "-R*cos(theta)"), "theta", R=1.0
    )


def agrees(condition, closed_form, system, rng, samples=40):
    """condition holds exactly where closed_form > 0, at random positive parameter values."""
    for _ in range(samples):
        values = {p.symbol: sympy.Rational(rng.randint(1, 400), 37) for p in system.parameters}
        if closed_form.xreplace(values) == 0:
            continue
        if bool(condition.xreplace(values)) != bool(closed_form.xreplace(values) > 0):
            return False
    return True


def test_bead_on_a_rotating_parabola_is_stable_iff_2ag_exceeds_omega_squared(rng):
    system = parabola()
    a, g, w = (system.symbol(n) for n in ("a", "g", "omega"))
    (bottom,) = system.equilibria()
    assert sympy.simplify(bottom.omega_squared[0] - (2 * a * g - w**2)) == 0
    assert bottom.stable and bottom.at_defaults
    assert agrees(bottom.stability_condition, 2 * a * g - w**2, system, rng)
    text = format_analysis(analyze(system.equations_of_motion(), timeout=None))
    assert "stable at the default parameter values; stable iff 2 a g > ω²" in text


def test_rotating_hoop_bottom_is_stable_iff_omega_squared_r_below_g(rng):
    system = hoop()
    g, R, w = (system.symbol(n) for n in ("g", "R", "omega"))
    bottom = next(e for e in system.equilibria() if e.point["theta"] == 0)
    assert bottom.at_defaults
    assert agrees(bottom.stability_condition, g - w**2 * R, system, rng)
    analysis = analyze(system.equations_of_motion(), timeout=None)
    document = analysis_document(analysis)
    (first, *_) = [e for e in document["equilibria"] if e["point"] == {"theta": "0"}]
    assert first["stability_at_defaults"] == first["stability"] == "stable"
    names = {s.name: s for s in system.parameters}
    condition = sympy.parse_expr(
        first["stability_condition"], {n: p.symbol for n, p in names.items()}
    )
    assert agrees(condition, g - w**2 * R, system, rng)
    json.dumps(document)
    assert r"\text{; stable iff }" in latex_analysis(analysis)


def test_a_verdict_that_holds_for_every_parameter_value_has_no_condition():
    (down, up) = lg.load("simple_pendulum").equilibria()
    assert not down.at_defaults and down.stability_condition is None
    assert not up.at_defaults and up.stability_condition is None


def test_a_stiffness_of_unknown_sign_is_judged_at_the_defaults_with_its_condition(rng):
    # V = (a - b) x^2/2 + c x^4: omega^2 = (a - b)/m at x = 0, stable iff a > b
    system = lg.System.from_energies(
        "m*x_dot**2/2",
        "(a - b)*x**2/2 + c*x**4",
        coordinates=["x"],
        parameters={"m": 1.0, "a": 2.0, "b": 1.0, "c": 1.0},
    )
    a, b = system.symbol("a"), system.symbol("b")
    origin = next(e for e in system.equilibria() if e.point["x"] == 0)
    assert origin.at_defaults and origin.stable
    assert agrees(origin.stability_condition, a - b, system, random.Random(3))


def test_constrained_parabola_has_the_same_condition(rng):
    # the bead on the turning parabola in (r, z) with the holonomic constraint z = a r^2
    bead = lg.Particle("bead", "m", ("r*cos(omega*t)", "r*sin(omega*t)", "z"))
    system = lg.System.from_particles(
        ["r", "z"],
        [bead],
        gravity=lg.Gravity("g", direction=(0, 0, -1)),
        constraints=["z - a*r**2"],
        parameters={"m": 1.0, "a": 1.0, "g": 9.81, "omega": 2.0},
    )
    a, g, w = (system.symbol(n) for n in ("a", "g", "omega"))
    (bottom,) = system.equilibria()
    assert dict(bottom.point) == {"r": 0, "z": 0}
    assert sympy.simplify(bottom.omega_squared[0] - (2 * a * g - w**2)) == 0
    assert bottom.at_defaults
    assert agrees(bottom.stability_condition, 2 * a * g - w**2, system, rng)


def test_penning_trap_is_stable_iff_the_magnetic_field_beats_the_radial_hill(rng):
    # V = k (z^2 - (x^2 + y^2)/2) pushes the charge out radially; the field B along z holds
    # it when the cyclotron frequency exceeds twice the axial one squared: q^2 B^2 > 4 k m
    system = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2 + z_dot**2)/2 + q*B*(x*y_dot - y*x_dot)/2"
        " - k*(z**2 - (x**2 + y**2)/2)",
        coordinates=["x", "y", "z"],
        parameters={"m": 1.0, "q": 1.0, "B": 3.0, "k": 1.0},
    )
    m, q, B, k = (system.symbol(n) for n in ("m", "q", "B", "k"))
    (centre,) = system.equilibria()
    assert centre.stable and centre.at_defaults
    assert agrees(centre.stability_condition, q**2 * B**2 - 4 * k * m, system, rng, samples=80)


def test_an_unstable_point_says_unstable_at_the_defaults():
    # x = 0 of x'' = -a x - x^3 with a = -1: unstable (stable iff a > 0), and the numbers
    system = lg.System.from_lagrangian(
        "x_dot^2/2 - a*x^2/2 - x^4/4",
        coordinates=["x"],
        parameters={"a": {"value": -1.0, "sign": "real"}},
    )
    document = analysis_document(analyze(system.equations_of_motion(), timeout=None))
    (origin,) = [e for e in document["equilibria"] if e["point"] == {"x": "0"}]
    assert origin["stability_at_defaults"] == "unstable"
    assert origin["at_parameter_values"] == {
        "parameters": {"a": -1.0},
        "omega_squared": [-1.0],
        "omega": [None],
        "periods": [None],
    }

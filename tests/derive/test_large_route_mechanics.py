"""The large route against sympy.physics.mechanics on systems the project does not ship.

The large route (SymEngine term tables, M and f made in SymPy when read, L taken from
the build's SymEngine assembly, the model's terms parsed once) is checked at random
points against ``LagrangesMethod`` of the same geometry, written independently with
dynamic symbols: a 4-link chain of unequal links with a spring, a bead on a hoop
turning at a rate that changes in time (a constraint that moves), a 3-D spherical
pendulum, and two of them joined by a spring, each forced onto the large route (its
7-coordinate threshold set to 1).
"""

from __future__ import annotations

import importlib

import pytest
import sympy
from sympy.physics import mechanics as me

import lagrangian as lg
from helpers import assert_close, evaluate, random_point


def _on_large_route(monkeypatch, build):
    """``build()`` and its equations with the large route taken from 1 coordinate up."""
    euler_lagrange = importlib.import_module("lagrangian.derive.euler_lagrange")
    energy = importlib.import_module("lagrangian.model.energy")
    monkeypatch.setattr(euler_lagrange, "FAST_MIN_COORDINATES", 1)
    monkeypatch.setattr(energy, "FAST_MIN_COORDINATES", 1)
    system = build()
    return system, system.equations_of_motion()


def _reference(names, positions, masses, potential, params):
    """M and f of LagrangesMethod for points ``positions`` (functions of the q(t) and t)."""
    t = me.dynamicsymbols._t
    q = me.dynamicsymbols(" ".join(names)) if len(names) > 1 else [me.dynamicsymbols(names[0])]
    given = dict(zip(names, q, strict=True)) | params | {"t": t}
    velocities = [[sympy.diff(x(given), t) for x in r] for r in positions]
    kinetic = sum(
        m(given) * sum(v**2 for v in vel) / 2 for m, vel in zip(masses, velocities, strict=True)
    )
    method = me.LagrangesMethod(kinetic - potential(given), q)
    method.form_lagranges_equations()
    return q, method.mass_matrix, method.forcing


def _compare(system, eom, reference, rng, count=2):
    q, matrix, forcing = reference
    t = me.dynamicsymbols._t
    n = len(q)
    for _ in range(count):
        point = random_point(system, rng)
        at = {qi.diff(t): point[f"{qi.func.__name__}_dot"] for qi in q}
        at |= {qi: point[qi.func.__name__] for qi in q}
        for i in range(n):
            for j in range(n):
                expected = _value(matrix[i, j], at, point)
                assert_close(evaluate(eom.mass_matrix[i, j], point), expected, scale=1.0)
            expected = _value(forcing[i], at, point)
            assert_close(evaluate(eom.forcing[i], point), expected, scale=1.0)


def _value(expr, at: dict, point: dict) -> float:
    """``expr`` of LagrangesMethod at ``point``: q(t) and q'(t) by ``at``, the rest by name."""
    expr = expr.xreplace(at)
    return float(expr.xreplace({s: point[s.name] for s in expr.free_symbols}).evalf())


@pytest.mark.slow
def test_a_chain_of_unequal_links_with_a_spring(monkeypatch, rng):
    n = 4
    particles, x_text, y_text = [], "0", "0"
    for i in range(1, n + 1):
        x_text += f" + l{i}*sin(theta{i})"
        y_text += f" - l{i}*cos(theta{i})"
        particles.append(lg.Particle(f"bob{i}", mass=f"m{i}", position=[x_text, y_text]))
    system, eom = _on_large_route(
        monkeypatch,
        lambda: lg.System.from_particles(
            coordinates=[f"theta{i}" for i in range(1, n + 1)],
            particles=particles,
            gravity=lg.Gravity(g="g", direction=(0, -1)),
            springs=[lg.Spring(stiffness="k", ends=("bob3", (0, "-h")), rest_length="r0")],
        ),
    )
    assert eom.symengine is not None

    sym = {name: sympy.Symbol(name, positive=True) for name in ("g", "k", "h", "r0")}
    sym |= {
        f"{p}{i}": sympy.Symbol(f"{p}{i}", positive=True) for p in "lm" for i in range(1, n + 1)
    }

    def bob(k):
        def x(s):
            return sum(s[f"l{i}"] * sympy.sin(s[f"theta{i}"]) for i in range(1, k + 1))

        def y(s):
            return -sum(s[f"l{i}"] * sympy.cos(s[f"theta{i}"]) for i in range(1, k + 1))

        return [x, y]

    def potential(s):
        heights = sum(s[f"m{k}"] * bob(k)[1](s) for k in range(1, n + 1))
        x3, y3 = (c(s) for c in bob(3))
        stretch = sympy.sqrt(x3**2 + (y3 + s["h"]) ** 2) - s["r0"]
        return s["g"] * heights + s["k"] * stretch**2 / 2

    names = [f"theta{i}" for i in range(1, n + 1)]
    masses = [lambda s, k=k: s[f"m{k}"] for k in range(1, n + 1)]
    reference = _reference(names, [bob(k) for k in range(1, n + 1)], masses, potential, sym)
    _compare(system, eom, reference, rng)


def test_a_bead_on_a_hoop_turning_at_a_changing_rate(monkeypatch, rng):
    """The hoop (radius R) turns about the vertical at angle w t + a t^2 / 2: r(theta, t)."""
    angle = "(w*t + a*t**2/2)"
    position = [
        f"R*sin(theta)*cos{angle}",
        f"R*sin(theta)*sin{angle}",
        "-R*cos(theta)",
    ]
    system, eom = _on_large_route(
        monkeypatch,
        lambda: lg.System.from_particles(
            coordinates=["theta"],
            particles=[lg.Particle("bead", mass="m", position=position)],
            gravity=lg.Gravity(g="g"),
        ),
    )
    assert eom.symengine is not None
    sym = {name: sympy.Symbol(name, positive=True) for name in ("R", "m", "g", "w", "a")}

    def turned(s):
        return s["w"] * s["t"] + s["a"] * s["t"] ** 2 / 2

    r = [
        lambda s: s["R"] * sympy.sin(s["theta"]) * sympy.cos(turned(s)),
        lambda s: s["R"] * sympy.sin(s["theta"]) * sympy.sin(turned(s)),
        lambda s: -s["R"] * sympy.cos(s["theta"]),
    ]
    reference = _reference(
        ["theta"], [r], [lambda s: s["m"]], lambda s: s["m"] * s["g"] * r[2](s), sym
    )
    _compare(system, eom, reference, rng, count=3)


def test_a_spherical_pendulum_in_3d(monkeypatch, rng):
    position = ["l*sin(theta)*cos(phi)", "l*sin(theta)*sin(phi)", "-l*cos(theta)"]
    system, eom = _on_large_route(
        monkeypatch,
        lambda: lg.System.from_particles(
            coordinates=["theta", "phi"],
            particles=[lg.Particle("bob", mass="m", position=position)],
            gravity=lg.Gravity(g="g"),
        ),
    )
    assert eom.symengine is not None
    sym = {name: sympy.Symbol(name, positive=True) for name in ("l", "m", "g")}
    r = [
        lambda s: s["l"] * sympy.sin(s["theta"]) * sympy.cos(s["phi"]),
        lambda s: s["l"] * sympy.sin(s["theta"]) * sympy.sin(s["phi"]),
        lambda s: -s["l"] * sympy.cos(s["theta"]),
    ]
    reference = _reference(
        ["theta", "phi"], [r], [lambda s: s["m"]], lambda s: s["m"] * s["g"] * r[2](s), sym
    )
    _compare(system, eom, reference, rng, count=3)


@pytest.mark.slow
def test_two_spherical_pendulums_joined_by_a_spring(monkeypatch, rng):
    """Two 3-D pendulums hung a apart and joined by a spring of rest length r0: the
    spring's length is a power of a sum (differentiated whole), the rest products of
    sines and cosines (the product rule, factor by factor)."""
    names = ["theta1", "phi1", "theta2", "phi2"]

    def bob(k, shift):
        return [
            f"{shift}l{k}*sin(theta{k})*cos(phi{k})",
            f"l{k}*sin(theta{k})*sin(phi{k})",
            f"-l{k}*cos(theta{k})",
        ]

    system, eom = _on_large_route(
        monkeypatch,
        lambda: lg.System.from_particles(
            coordinates=names,
            particles=[
                lg.Particle("bob1", mass="m1", position=bob(1, "")),
                lg.Particle("bob2", mass="m2", position=bob(2, "a + ")),
            ],
            gravity=lg.Gravity(g="g"),
            springs=[lg.Spring(stiffness="k", ends=("bob1", "bob2"), rest_length="r0")],
        ),
    )
    assert eom.symengine is not None
    sym = {s: sympy.Symbol(s, positive=True) for s in ("g", "k", "a", "r0", "l1", "l2", "m1", "m2")}

    def position(k, shifted):
        def r(s):
            theta, phi, length = s[f"theta{k}"], s[f"phi{k}"], s[f"l{k}"]
            return [
                (s["a"] if shifted else 0) + length * sympy.sin(theta) * sympy.cos(phi),
                length * sympy.sin(theta) * sympy.sin(phi),
                -length * sympy.cos(theta),
            ]

        return [lambda s, c=c: r(s)[c] for c in range(3)]

    bobs = [position(1, False), position(2, True)]

    def potential(s):
        heights = sum(s[f"m{k}"] * bobs[k - 1][2](s) for k in (1, 2))
        gap = [bobs[1][c](s) - bobs[0][c](s) for c in range(3)]
        stretch = sympy.sqrt(sum(d**2 for d in gap)) - s["r0"]
        return s["g"] * heights + s["k"] * stretch**2 / 2

    masses = [lambda s: s["m1"], lambda s: s["m2"]]
    _compare(system, eom, _reference(names, bobs, masses, potential, sym), rng)

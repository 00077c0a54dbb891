"""The right answers an answer is checked against (also what the exercise page embeds)."""

from __future__ import annotations

import sympy

from ...derive import EquationsOfMotion


def state_symbols(eom: EquationsOfMotion) -> frozenset[sympy.Symbol]:
    """What an answer's terms are keyed by: q, q', q'' and t (the rest are parameters)."""
    coordinates = eom.coordinates
    return frozenset([eom.system.time, *(s for c in coordinates for s in (c.q, c.q_dot, c.q_ddot))])


def right_kinetic(eom: EquationsOfMotion) -> sympy.Expr:
    """The model's T; for a model given by L alone, the part of L of second degree in the
    velocities, q'^T M q' / 2 (the part of first degree is a velocity-dependent potential's)."""
    if eom.system.kinetic is not None:
        return eom.system.kinetic
    velocities = sympy.Matrix([c.q_dot for c in eom.coordinates])
    return sympy.expand((velocities.T * eom.mass_matrix * velocities)[0, 0] / 2)


def right_potential(eom: EquationsOfMotion) -> sympy.Expr:
    """The model's V; for a model given by L alone, -L at rest."""
    system = eom.system
    if system.potential is not None:
        return system.potential
    return -system.lagrangian.xreplace({c.q_dot: 0 for c in system.coordinates})


def raw_equations(eom: EquationsOfMotion) -> list[sympy.Expr]:
    """The Euler-Lagrange expressions (M q'' - f)_i, each = 0, not divided by anything."""
    accelerations = sympy.Matrix([c.q_ddot for c in eom.coordinates])
    return list(eom.mass_matrix * accelerations - eom.forcing)

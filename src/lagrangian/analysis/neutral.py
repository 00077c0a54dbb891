"""Continua of equilibria and the neutral (zero-frequency) directions, named.

When G(q) = f(q, 0) = 0 leaves some coordinates free (a linear triatomic
molecule rests wherever x1 = x2 = x3), the equilibria form a family
parametrized by the free coordinates.  Its modes are computed at one
*representative* member (the free coordinates set to a value where M is
regular), and every direction with omega^2 = 0 (a null vector v of K0) is
named by what it is:

- for a system of particles, a rigid motion of all of them: the displacements
  dr_a = (dr_a/dq) v fit u + w x r_a (u = 0: a rotation, w = 0: a translation);
- a shift along which L is invariant (dL/dq . v = 0 identically): a
  translation of the coordinates it moves;
- a direction along the family of equilibria;
- otherwise a neutral direction (zero stiffness), about which linear theory
  says nothing.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy

from ..algebra import as_expression, is_zero
from ..derive import EquationsOfMotion
from ..model import System

#: Values tried for a free coordinate of a family (the first where M is regular is used).
REPRESENTATIVES = (0, 1, sympy.Rational(1, 2))
#: Relative residual below which displacements count as a rigid motion.
RIGID_TOLERANCE = 1e-8


def free_coordinates(eom: EquationsOfMotion, point: Mapping[str, sympy.Expr]) -> tuple[str, ...]:
    """Coordinates that the equilibrium ``point`` leaves free and the equations need.

    They appear in the values of the point (x1 = x3: x3 is free) or are missing
    from it while M or f depend on them.
    """
    system = eom.system
    free = []
    for c in system.coordinates:
        in_values = any(as_expression(v).has(c.q) for v in point.values())
        needed = c.name not in point and (eom.mass_matrix.has(c.q) or eom.forcing.has(c.q))
        if in_values or needed:
            free.append(c.name)
    return tuple(free)


def representative(
    eom: EquationsOfMotion, point: Mapping[str, sympy.Expr], free: tuple[str, ...]
) -> dict[str, sympy.Expr]:
    """One member of the family: the free coordinates at the first value where M is regular."""
    system = eom.system
    symbols = {c.name: c.q for c in system.coordinates}
    first = None
    for value in REPRESENTATIVES:
        table = {
            symbols[name]: sympy.Integer(value) if isinstance(value, int) else value
            for name in free
        }
        member = {name: as_expression(v).xreplace(table) for name, v in point.items()}
        member |= {name: table[symbols[name]] for name in free if name not in point}
        first = first or member
        if _regular(eom, member):
            return member
    return first


def _regular(eom: EquationsOfMotion, member: Mapping[str, sympy.Expr]) -> bool:
    system = eom.system
    table = {c.q: member[c.name] for c in system.coordinates if c.name in member}
    rng = np.random.default_rng(3)
    table |= {
        p.symbol: p.default if p.default is not None else rng.uniform(0.5, 2)
        for p in system.parameters
    }
    try:
        mass = np.array(eom.mass_matrix.xreplace(table).evalf(), dtype=float)
    except (TypeError, ValueError):
        return False
    return bool(np.all(np.isfinite(mass))) and abs(np.linalg.det(mass)) > 1e-12 * max(
        1.0, np.abs(mass).max()
    ) ** len(mass)


def zero_mode_names(
    eom: EquationsOfMotion,
    stiffness: sympy.Matrix,
    member: Mapping[str, sympy.Expr],
    free: tuple[str, ...],
    family: Mapping[str, sympy.Expr],
    basis: sympy.Matrix | None = None,
) -> tuple[str, ...]:
    """What each null vector of the stiffness K0 is (see the module docstring).

    ``basis``: the directions (columns, over every coordinate) that the rows of
    ``stiffness`` belong to (all coordinates, unless some are degenerate at the point).
    """
    system = eom.system
    n = len(system.coordinates)
    basis = sympy.eye(n) if basis is None else basis
    try:
        null = sympy.Matrix(stiffness).nullspace()
    except (TypeError, ValueError, ZeroDivisionError):
        return ()
    tangent = _family_tangent(system, family, free)
    return tuple(_name(system, list(basis * vector), member, tangent) for vector in null)


def _name(system: System, v: list[sympy.Expr], member, tangent: list[list[sympy.Expr]]) -> str:
    rigid = _rigid_motion(system, v, member)
    if rigid is not None:
        return rigid
    moved = [c.name for c, x in zip(system.coordinates, v, strict=True) if x != 0]
    variation = sum(
        (
            sympy.diff(system.lagrangian, c.q) * x
            for c, x in zip(system.coordinates, v, strict=True)
        ),
        sympy.Integer(0),
    )
    if is_zero(variation):
        nonzero = [x for x in v if x != 0]
        if all(sympy.simplify(x - nonzero[0]) == 0 for x in nonzero):
            return "translation of " + ", ".join(moved) + " together (L is invariant)"
        return "shift along (" + ", ".join(map(str, v)) + ") (L is invariant)"
    if tangent and sympy.Matrix([*tangent, v]).rank() == len(tangent):
        return "along the family of equilibria"
    return "neutral direction (zero stiffness; linear theory undecided)"


def _family_tangent(system: System, family: Mapping[str, sympy.Expr], free) -> list[list]:
    """d(point)/d(free coordinate) for each free coordinate: the directions along the family."""
    rows = []
    for name in free:
        symbol = system.symbol(name)
        rows.append(
            [
                sympy.Integer(1)
                if c.name == name
                else sympy.diff(as_expression(family.get(c.name, 0)), symbol)
                for c in system.coordinates
            ]
        )
    return rows


def _rigid_motion(system: System, v: list[sympy.Expr], member) -> str | None:
    """'translation ...' / 'rotation ...' when the particles move as one rigid body along v."""
    if not system.particles or system.bodies:
        return None
    q = [c.q for c in system.coordinates]
    rng = np.random.default_rng(5)
    table = {c.q: member.get(c.name, 0) for c in system.coordinates}
    table |= {
        p.symbol: p.default if p.default is not None else rng.uniform(0.5, 2)
        for p in system.parameters
    }
    table[system.time] = 0
    try:
        positions = [
            np.array(sympy.Matrix(p.position).xreplace(table).evalf(), dtype=float).ravel()
            for p in system.particles
        ]
        moves = [
            np.array(
                (sympy.Matrix(p.position).jacobian(q) * sympy.Matrix(v)).xreplace(table).evalf(),
                dtype=float,
            ).ravel()
            for p in system.particles
        ]
    except (TypeError, ValueError):
        return None
    dimension = len(positions[0])
    # unknowns: u (d), w (1 in 2-D, 3 in 3-D); rows: dr_a = u + w x r_a
    rows, rhs = [], []
    for r, dr in zip(positions, moves, strict=True):
        if dimension == 2:
            cross = np.array([[-r[1]], [r[0]]])
        else:
            cross = np.array([[0, r[2], -r[1]], [-r[2], 0, r[0]], [r[1], -r[0], 0]])
        rows.append(np.hstack([np.eye(dimension), cross]))
        rhs.append(dr)
    a, b = np.vstack(rows), np.concatenate(rhs)
    solution, *_ = np.linalg.lstsq(a, b, rcond=None)
    scale = max(np.abs(b).max(), 1e-300)
    if np.abs(a @ solution - b).max() > RIGID_TOLERANCE * scale:
        return None
    u, w = solution[:dimension], solution[dimension:]
    small = RIGID_TOLERANCE * scale
    # a rotation of all particles about a point off the origin has u = -w x o: still a rotation
    if np.abs(w).max() <= small:
        return (
            "translation of all particles along ("
            + ", ".join(f"{x / np.abs(u).max():.3g}" for x in u)
            + ")"
        )
    if dimension == 2:
        return "rotation of all particles in the plane"
    axis = w / np.linalg.norm(w)
    return "rotation of all particles about (" + ", ".join(f"{x:.3g}" for x in axis) + ")"

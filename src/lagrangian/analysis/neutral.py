"""Continua of equilibria and the neutral (zero-frequency) directions, named.

When G(q) = f(q, 0) = 0 leaves some coordinates free (a linear triatomic
molecule rests wherever x1 = x2 = x3), the equilibria form a family
parametrized by the free coordinates.  Its modes are computed at one
*representative* member (the free coordinates set to a value where M is
regular), and every direction with omega^2 = 0 (a null vector v of K0) is
named by what it is.  The null space of K0 (in the directions used for the
modes) is compared with the point symmetries of L evaluated at the member
(:func:`lagrangian.analysis.symmetries.generators`: translations, rotations of
particles, shifts, any linear change of coordinates L is invariant under):

- a symmetry inside it names one zero mode ("translation of all particles along
  x", "rotation of all particles about the origin", "translation of x1, x2, x3
  together");
- a combination of symmetries inside it, one more ("shift of phi, psi together"
  for the spin of a top at its pole);
- the rest lies along the family of equilibria (for a member of one), or is a
  neutral direction (zero stiffness), about which linear theory says nothing.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy

from ..algebra import as_expression
from ..derive import EquationsOfMotion
from ..model import System
from .symmetries import generators

#: Values tried for a free coordinate of a family (the first where M is regular is used).
REPRESENTATIVES = (0, 1, sympy.Rational(1, 2))
#: Singular values of K0 below this (relative to the largest) count as zero.
NULL_TOLERANCE = 1e-7


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
    basis: sympy.Matrix,
    member: Mapping[str, sympy.Expr],
    family: int,
) -> tuple[str, ...]:
    """What each direction with omega^2 = 0 is (see the module docstring).

    ``stiffness`` acts on the directions that are the columns of ``basis`` (all
    coordinates, unless some are degenerate at the point); ``family``: the
    dimension of the continuum of equilibria the point belongs to (0: isolated).
    The null space of K0 (numerically, at the default values) is matched first
    against the point symmetries of L evaluated at ``member`` (one name per
    symmetry inside it), then against their combinations; of what is left, up to
    the family's dimension lies along the family, the rest is merely neutral.
    """
    system = eom.system
    table = _numbers_table(system, member)
    try:
        k = np.array(sympy.Matrix(stiffness).xreplace(table).evalf(), dtype=float)
        b = np.array(sympy.Matrix(basis).xreplace(table).evalf(), dtype=float)
    except (TypeError, ValueError):
        return ()
    null = b @ _null_space(k)
    if null.shape[1] == 0:
        return ()
    names, chosen = [], np.zeros((len(system.coordinates), 0))
    candidates = []
    for what, xi in generators(eom):
        try:
            v = np.array([float(as_expression(x).xreplace(table)) for x in xi])
        except (TypeError, ValueError):
            continue
        if np.linalg.norm(v) > 0:
            candidates.append((what, v / np.linalg.norm(v)))
    # rigid motions of the particles first: at one point a rotation about another centre is
    # a rotation about the origin plus a translation, and the plainer names should win
    candidates.sort(key=lambda item: ("all particles" not in item[0], "linear" in item[0]))
    for what, v in candidates:  # single symmetries inside the null space
        if _inside(v, null) and not _inside(v, chosen):
            names.append(what + " (L is invariant)")
            chosen = np.column_stack([chosen, v])
    if candidates and len(names) < null.shape[1]:  # their combinations inside it
        span = np.column_stack([v for _, v in candidates])
        both = _null_space(np.hstack([span, -null]))
        for combination in both.T:
            v = span @ combination[: span.shape[1]]
            if np.linalg.norm(v) > 0 and not _inside(v, chosen):
                names.append(_combination(system, v))
                chosen = np.column_stack([chosen, v / np.linalg.norm(v)])
    # the family's own directions, beyond the symmetries that move along it too
    along = min(max(family - len(names), 0), null.shape[1] - len(names))
    left = null.shape[1] - len(names) - along
    neutral = "neutral direction (zero stiffness; linear theory undecided)"
    return (*names, *["along the family of equilibria"] * along, *[neutral] * left)


def _numbers_table(system: System, member: Mapping[str, sympy.Expr]) -> dict:
    rng = np.random.default_rng(5)
    table = {
        p.symbol: sympy.Float(p.default if p.default is not None else rng.uniform(0.5, 2))
        for p in system.parameters
    }
    table |= {c.q: as_expression(member.get(c.name, 0)).xreplace(table) for c in system.coordinates}
    table[system.time] = sympy.Integer(0)
    return table


def _null_space(matrix: np.ndarray) -> np.ndarray:
    """Orthonormal columns spanning the null space (singular values below 1e-7 of the largest)."""
    if matrix.size == 0:
        return np.zeros((matrix.shape[1], 0))
    _, singular, vt = np.linalg.svd(matrix)
    largest = singular.max() if singular.size else 0.0
    rank = int(np.sum(singular > NULL_TOLERANCE * max(largest, 1e-300)))
    return vt[rank:].T


def _inside(v: np.ndarray, columns: np.ndarray) -> bool:
    """Whether v lies in the span of ``columns`` (to rounding)."""
    if columns.shape[1] == 0:
        return False
    coefficients, *_ = np.linalg.lstsq(columns, v, rcond=None)
    return float(np.linalg.norm(columns @ coefficients - v)) <= 1e-6 * float(np.linalg.norm(v))


def _combination(system: System, v: np.ndarray) -> str:
    v = v / v[np.argmax(np.abs(v))]
    moved = [c.name for c, x in zip(system.coordinates, v, strict=True) if abs(x) > 1e-9]
    if all(abs(x - 1) <= 1e-9 for x in v if abs(x) > 1e-9):
        return "shift of " + ", ".join(moved) + " together (L is invariant)"
    return "shift along (" + ", ".join(f"{x:.3g}" for x in v) + ") (L is invariant)"

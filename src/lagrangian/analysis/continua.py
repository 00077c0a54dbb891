"""Numerical roots of G = 0 that lie on continua of equilibria, grouped into families.

When SymPy cannot solve G(q) = f(q, 0) = 0 and the equilibria form a continuum
(a molecule free to translate and rotate, an arm free to bend), the
multi-start search lands on many different points of the same family.  At such
a root the Jacobian dG/dq = -K0 is singular: its nullity k bounds the dimension
of the family through the point.

Roots are grouped by (k, U) with U = L(q, 0): without forces at rest G is the
gradient of U (f_i = dL/dq_i at q' = 0 for an autonomous L), and a function is
constant along a connected set of its critical points, so every member of one
family has the same U.  Each group is reported once, by its member nearest the
origin, with its dimension.  Two families with equal U and k would be merged
(rare; said in the output as "grouped by the value of V").
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy

from ..distributions import without_distributions
from ..model import System
from ..symbols import Coordinate

#: Singular values of dG/dq below this (relative to the largest) count as zero.
NULL_TOLERANCE = 1e-7
#: Relative difference below which two values of U are the same.
SAME_LEVEL = 1e-7


@dataclass(frozen=True)
class Member:
    """A numerical root: the point, the dimension of the family through it (0: isolated)
    and how many roots found belong to the same family."""

    point: Mapping[str, sympy.Expr]
    dimension: int = 0
    found: int = 1


def grouped(
    system: System,
    equations: Sequence[sympy.Expr],
    unknowns: Sequence[Coordinate],
    points: Sequence[Mapping[str, sympy.Expr]],
) -> list[Member]:
    """``points`` (numerical roots at the default values) with families merged."""
    if not points:
        return []
    q = [c.q for c in unknowns]
    values = {p.symbol: sympy.Float(p.default) for p in system.parameters if p.default is not None}
    rest = {c.q_dot: 0 for c in system.coordinates}
    jacobian = without_distributions(sympy.Matrix(equations).jacobian(q).xreplace(values))
    level = without_distributions(system.lagrangian.xreplace(rest).xreplace(values))
    others = {c.q: 0 for c in system.coordinates if c not in unknowns}
    jacobian_at = sympy.lambdify([q], jacobian.xreplace(others).tolist(), "numpy")
    level_at = sympy.lambdify([q], level.xreplace(others), "numpy")
    isolated, families = [], {}
    for point in points:
        x = np.array([float(point[c.name]) for c in unknowns])
        with np.errstate(all="ignore"):
            matrix = np.array(jacobian_at(list(x)), dtype=float).reshape(len(equations), len(q))
            u = float(level_at(list(x)))
        singular = np.linalg.svd(matrix, compute_uv=False) if matrix.size else np.zeros(0)
        largest = singular.max() if singular.size else 0.0
        rank = int(np.sum(singular > NULL_TOLERANCE * max(largest, 1e-300)))
        nullity = len(q) - rank
        if nullity == 0 or not np.isfinite(u):
            isolated.append(Member(point))
            continue
        key = next(
            (
                k
                for k in families
                if k[0] == nullity and abs(k[1] - u) <= SAME_LEVEL * max(1.0, abs(u), abs(k[1]))
            ),
            (nullity, u),
        )
        families.setdefault(key, []).append((float(np.linalg.norm(x)), point))
    members = list(isolated)
    for (nullity, _), found in families.items():
        _, nearest = min(found, key=lambda item: item[0])
        members.append(Member(nearest, nullity, len(found)))
    return members

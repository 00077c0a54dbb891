"""Rest points on a constraint surface, found numerically from many starts.

The rest points of a system with holonomic constraints c(q) = 0 (A = dc/dq) solve

    F(q, lambda) = [G(q) + A(q)^T lambda ; c(q)] = 0,     G(q) = f(q, 0),

n + m equations for n coordinates and m multipliers.  They are solved numerically first
(SymPy, which cannot solve a four-bar's loop closures, then gives the exact forms of the
points found where it can: :mod:`.surface_exact`): each start q0 in [-pi, pi]^n is first
moved onto the surface by Gauss-Newton steps of least norm (q -= A^+ c: general, not only for
linkages), the multipliers there are the least-squares balance A^T lambda = -G, and
Powell's hybrid method with the exact Jacobian [[dG/dq + d(A^T lambda)/dq, A^T], [A, 0]]
(the bordered Hessian) then finds the root nearest it, polished by Newton's method.
Roots are merged when their configurations agree (angles modulo 2 pi: a coordinate on
which F is 2 pi-periodic); the multipliers follow from the configuration where A has
full rank.  Where it does not (constraints redundant at the point), the multipliers are
not determined by the point and ``rank`` says so.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy

from ..algebra import is_zero
from ..derive import EquationsOfMotion
from ..distributions import without_distributions
from .search import starting_points

#: Gauss-Newton steps at most that move a start onto the surface, the largest turn of an
#: angle in one step, and the halvings of a step that does not close the gap.
PROJECTION_STEPS, PROJECTION_STEP, HALVINGS = 60, 0.5, 30
#: Residual (relative to 1 + the typical size of G) below which a root is accepted.
ROOT_TOLERANCE = 1e-9
#: Largest last Newton step (relative to the point) of an accepted root.
NEWTON_STEP = 1e-6
#: Distance (relative) below which two roots are the same configuration.
DEDUPE_TOLERANCE = 1e-7
#: Singular values of A below this (relative to the largest) count as zero: its rank.
RANK_TOLERANCE = 1e-8
#: A singular value of A on the surface below this times A's size at the starts vanishes
#: there (a gradient that is 0 on the whole surface, as for a constraint written squared).
VANISHING = 1e-4
#: Root coordinates smaller than this are reported as 0.
SNAP_TO_ZERO = 1e-12


@dataclass(frozen=True)
class SurfaceRoot:
    """A rest point found numerically: the configuration, the multipliers (least-squares
    where A is rank-deficient) and the rank of A there."""

    q: np.ndarray
    multipliers: np.ndarray
    rank: int


class SurfaceSearch:
    """Multi-start search for the roots of F (see the module docstring)."""

    def __init__(self, eom: EquationsOfMotion):
        system, forms = eom.system, eom.constraints
        self.system = system
        self.q = [c.q for c in system.coordinates]
        self.lambdas = list(forms.multipliers)
        rest = {c.q_dot: sympy.Integer(0) for c in system.coordinates}
        self.force = without_distributions(eom.forcing.xreplace(rest))
        self.constraints = sympy.Matrix(list(system.constraints))
        self.gradient = self.constraints.jacobian(self.q)
        equations = list(self.force + self.gradient.T * sympy.Matrix(self.lambdas))
        self.equations = sympy.Matrix(equations + list(self.constraints))
        self.angles = [self._periodic(s) for s in self.q]
        self._searched: dict[tuple, list[SurfaceRoot]] = {}
        self._ranks: dict[tuple, int | None] = {}  # the largest rank of A where starts landed

    def _periodic(self, symbol: sympy.Symbol) -> bool:
        shift = {symbol: symbol + 2 * sympy.pi}
        return all(is_zero(e.xreplace(shift) - e) for e in self.equations)

    def roots(self, values: Mapping[str, float]) -> list[SurfaceRoot]:
        """Distinct roots at the parameter ``values`` (by name; searched once for them)."""
        key = tuple(sorted(values.items()))
        if key not in self._searched:
            self._searched[key] = self._search(values, key)
        return self._searched[key]

    def surface_rank(self, values: Mapping[str, float]) -> int | None:
        """The largest rank of A at the points of the surface the starts reached (at
        ``values``; None where none reached it): short of the number of constraints, A
        is rank-deficient all over the surface (a constraint written squared), and the
        multipliers cannot hold anything there."""
        self.roots(values)
        return self._ranks[tuple(sorted(values.items()))]

    def _search(self, values: Mapping[str, float], key: tuple) -> list[SurfaceRoot]:
        import scipy.optimize  # lazily: `lagrangian derive` never needs SciPy

        table = {p.symbol: sympy.Float(values[p.name]) for p in self.system.parameters}
        unknowns = self.q + self.lambdas
        equations = self.equations.xreplace(table)
        functions = _Functions(
            sympy.lambdify([self.q], list(self.constraints.xreplace(table)), "numpy"),
            sympy.lambdify([self.q], self.gradient.xreplace(table).tolist(), "numpy"),
            sympy.lambdify([self.q], list(self.force.xreplace(table)), "numpy"),
            sympy.lambdify([unknowns], list(equations), "numpy"),
            sympy.lambdify([unknowns], equations.jacobian(unknowns).tolist(), "numpy"),
            len(self.q),
        )
        starts = starting_points(len(self.q))
        roots: list[SurfaceRoot] = []
        with np.errstate(all="ignore"):
            begun = [functions.begun(s, self.angles) for s in starts]
            begun = [x for x in begun if x is not None]
            # A's size at the starts, off the surface, is the scale a vanishing gradient on
            # it is told by: (x^2 + y^2 - l^2)^2 has one of ~1e-6 of it at a gap of 1e-12
            sizes = [np.linalg.norm(functions.gradient(x), 2) for x in starts]
            size = float(np.median([x for x in sizes if np.isfinite(x)] or [0.0]))
            ranks = [_rank(functions.gradient(x[: len(self.q)]), size) for x in begun]
            self._ranks[key] = max(ranks, default=None)
            sizes = [np.abs(functions.force(x[: len(self.q)])).max() for x in begun]
            scale = float(np.median(sizes)) if sizes else 1.0
            tolerance = ROOT_TOLERANCE * (1.0 + (scale if np.isfinite(scale) else 0.0))
            for start in begun:
                try:
                    result = scipy.optimize.root(
                        functions.residual, start, jac=functions.jacobian, method="hybr"
                    )
                    x = _polished(functions, result.x)
                except (TypeError, ValueError, ZeroDivisionError, np.linalg.LinAlgError):
                    continue
                if x is None or np.abs(functions.residual(x)).max() > tolerance:
                    continue
                root = self._root(functions, x)
                if not any(self._same(root.q, r.q) for r in roots):
                    roots.append(root)
        return sorted(roots, key=lambda r: tuple(r.q))

    def _root(self, functions: _Functions, x: np.ndarray) -> SurfaceRoot:
        n = len(self.q)
        q = x[:n].copy()
        for i, angle in enumerate(self.angles):
            if angle:
                q[i] = math.remainder(q[i], 2 * math.pi)
                if q[i] <= -math.pi + DEDUPE_TOLERANCE:
                    q[i] = math.pi
        q[np.abs(q) < SNAP_TO_ZERO] = 0.0
        gradient = functions.gradient(q)
        rank = _rank(gradient)
        # the balance A^T lambda = -G at the reduced point (least squares where A is
        # rank-deficient: one of many multipliers that hold it)
        multipliers = np.linalg.lstsq(gradient.T, -functions.force(q), rcond=None)[0]
        multipliers[np.abs(multipliers) < SNAP_TO_ZERO] = 0.0
        return SurfaceRoot(q, multipliers, rank)

    def _same(self, a: np.ndarray, b: np.ndarray) -> bool:
        for x, y, angle in zip(a, b, self.angles, strict=True):
            d = abs(math.remainder(x - y, 2 * math.pi)) if angle else abs(x - y)
            if d > DEDUPE_TOLERANCE * max(1.0, abs(x), abs(y)):
                return False
        return True


@dataclass(frozen=True)
class _Functions:
    """F, its Jacobian and the parts of it, as NumPy functions at fixed parameter values."""

    _constraints: object
    _gradient: object
    _force: object
    _residual: object
    _jacobian: object
    n: int

    def gradient(self, q: np.ndarray) -> np.ndarray:
        return np.array(self._gradient(list(q)), dtype=float).reshape(-1, self.n)

    def force(self, q: np.ndarray) -> np.ndarray:
        return np.array(self._force(list(q)), dtype=float).ravel()

    def residual(self, x: np.ndarray) -> np.ndarray:
        return np.array(self._residual(list(x)), dtype=float).ravel()

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        return np.array(self._jacobian(list(x)), dtype=float).reshape(len(x), len(x))

    def begun(self, start: np.ndarray, angles: list[bool]) -> np.ndarray | None:
        """(q, lambda) to start from: ``start`` moved onto the surface by Gauss-Newton steps
        of least norm, with the least-squares multipliers there; None where it does not get
        there (a start the steps cannot bring onto the surface).

        A step turns no angle by more than PROJECTION_STEP (past a radian it lands anywhere;
        each angle clipped on its own, so that a length is not held back with them) and is
        halved until the gap closes some."""
        q = np.array(start, dtype=float)
        angle = np.array(angles, dtype=bool)
        gap = self.gap(q)
        for _ in range(PROJECTION_STEPS):
            if not np.all(np.isfinite(gap)):
                return None
            if np.abs(gap).max() <= 1e-12 * (1.0 + np.abs(q).max()):
                break
            gradient = self.gradient(q)
            # columns scaled to one size: the least-norm step in mixed units (radians and
            # millimetres) turned a slider-crank's angles by radians and left its slide
            scale = np.linalg.norm(gradient, axis=0)
            scale[scale == 0] = 1.0
            step = np.linalg.lstsq(gradient / scale, gap, rcond=None)[0] / scale
            step[angle] = np.clip(step[angle], -PROJECTION_STEP, PROJECTION_STEP)
            for _ in range(HALVINGS):
                trial = self.gap(q - step)
                if np.all(np.isfinite(trial)) and np.linalg.norm(trial) < np.linalg.norm(gap):
                    break
                step /= 2
            else:
                return None  # no step closes the gap: a point where the gradients drop rank
            q, gap = q - step, trial
        else:
            return None
        multipliers = np.linalg.lstsq(self.gradient(q).T, -self.force(q), rcond=None)[0]
        return np.concatenate([q, multipliers])

    def gap(self, q: np.ndarray) -> np.ndarray:
        return np.array(self._constraints(list(q)), dtype=float).ravel()


def _rank(matrix: np.ndarray, size: float | None = None) -> int:
    """The rank of ``matrix`` by its SVD: singular values above RANK_TOLERANCE times the
    largest (none where every entry is 0); given the ``size`` of the matrix elsewhere, also
    above VANISHING times it."""
    singular = np.linalg.svd(matrix, compute_uv=False)
    largest = singular.max(initial=0.0)
    if largest == 0:
        return 0
    floor = RANK_TOLERANCE * largest
    if size is not None:
        floor = max(floor, VANISHING * size)
    return int(np.sum(singular > floor))


def _polished(functions: _Functions, x: np.ndarray) -> np.ndarray | None:
    """A few Newton steps (least squares where the Jacobian is singular) from ``x``; None
    unless the last step is small (``x`` is near a root, not where F merely decays)."""
    x = np.array(x, dtype=float)
    residual = functions.residual(x)
    step = np.full_like(x, np.inf)
    for _ in range(6):
        if not np.all(np.isfinite(residual)):
            return None
        step = np.linalg.lstsq(functions.jacobian(x), residual, rcond=None)[0]
        candidate = x - step
        candidate_residual = functions.residual(candidate)
        if not np.abs(candidate_residual).max() < np.abs(residual).max():
            break
        x, residual = candidate, candidate_residual
    if not np.abs(step[: functions.n]).max() <= NEWTON_STEP * max(1.0, np.abs(x).max()):
        return None
    return x

"""Solving G(q) = 0 for the equilibria: SymPy (in a child process) and a multi-start search.

SymPy's solutions are kept when they may be real (at the default parameter
values, when every parameter has one) and solve G = 0; they are cross-checked
by a numerical multi-start search (at the defaults, or at random parameter
values).  A coordinate on which G depends 2 pi-periodically is an angle:
numerical roots of it are reduced to (-pi, pi] and compared modulo 2 pi.
"""

from __future__ import annotations

import itertools
import math
import random
from collections.abc import Mapping, Sequence

import numpy as np
import sympy

from ..algebra import is_zero
from ..distributions import without_distributions
from ..errors import ModelError
from ..model import System
from ..symbols import Coordinate
from .linear import vanishes
from .solving import in_child, solve_factored

#: Distance below which two numerical roots are the same point.
DEDUPE_TOLERANCE = 1e-8
#: Residual (relative to the size of G at the starts) below which a root is accepted.
ROOT_TOLERANCE = 1e-9
#: Largest Newton step (relative to the point) from an accepted numerical root.
NEWTON_STEP = 1e-6
#: Numerical root coordinates smaller than this are reported as 0.
SNAP_TO_ZERO = 1e-12
#: Starting points of the numerical search: about this many, in [-pi, pi]^n.
STARTS = 100


def _principal(value: sympy.Expr) -> sympy.Expr:
    """An angle without the whole turns SymPy adds to it: ``-acos(g/(R w^2)) + 2 pi`` is
    ``-acos(g/(R w^2))``, the same configuration written as a teacher writes it."""
    if not isinstance(value, sympy.Add):
        return value
    turns = [t for t in value.args if (t / sympy.pi).is_even and not (t / sympy.pi).is_zero]
    return value - sympy.Add(*turns) if turns else value


class RootSearch:
    """Solve G = 0 for ``unknowns``, symbolically and numerically."""

    def __init__(self, system: System, equations: list[sympy.Expr], unknowns: list[Coordinate]):
        self.system = system
        self.equations = equations
        self.unknowns = unknowns
        self.defaults = dict(system.parameter_values)
        self.complete = all(p.default is not None for p in system.parameters)
        self.angles = []
        self._searched: dict[tuple, list[np.ndarray]] = {}  # the roots at each set of values
        for c in unknowns:
            shift = {c.q: c.q + 2 * sympy.pi}
            self.angles.append(all(is_zero(g.xreplace(shift) - g) for g in equations))

    # -- symbolic ----------------------------------------------------------------
    def symbolic(self, timeout: float) -> list[dict[str, sympy.Expr]] | None:
        """Real solutions by SymPy, or None when it fails or runs out of time.

        While SymPy solves (in a child process), this process searches numerically at
        the values :meth:`confirms` and :meth:`numeric` read, so that the two run side by
        side; either of them then finds the roots searched already.
        """
        solutions = in_child(
            solve_factored,
            (self.equations, [c.q for c in self.unknowns]),
            timeout,
            meanwhile=lambda: self._roots(self._check_values()),
        )
        if solutions is None:
            return None
        points = []
        for solution in solutions:
            point = {
                c.name: _principal(solution[c.q]) if angle else solution[c.q]
                for c, angle in zip(self.unknowns, self.angles, strict=True)
                if c.q in solution
            }
            if self._may_be_real(point) and self._solves(point) and point not in points:
                points.append(point)
        return points

    def _may_be_real(self, point: Mapping[str, sympy.Expr]) -> bool:
        for value in point.values():
            if value.is_extended_real is False or value.has(sympy.zoo, sympy.nan):
                return False
            if value.has(sympy.I) and not self._real_on_family(value):
                return False
            if self.complete and not value.has(*(c.q for c in self.unknowns)):
                number = number_at(value, self.defaults)
                if number is None or abs(number.imag) > 1e-9 * (1 + abs(number.real)):
                    return False
        return True

    def _real_on_family(self, value: sympy.Expr) -> bool:
        """A value in terms of free coordinates (a family) is real for real ones: at two
        random real points (x1 = x2 + I (y1 - y2) is not a real family)."""
        rng = random.Random(17)
        for _ in range(2):
            table = {c.q: sympy.Float(rng.uniform(-1.5, 1.5)) for c in self.system.coordinates}
            table |= {
                p.symbol: sympy.Float(p.default if p.default is not None else rng.uniform(0.5, 2.0))
                for p in self.system.parameters
            }
            number = number_at(value.xreplace(table), {})
            if number is None or abs(number.imag) > 1e-9 * (1 + abs(number.real)):
                return False
        return True

    def _solves(self, point: Mapping[str, sympy.Expr]) -> bool:
        substitution = {c.q: point[c.name] for c in self.unknowns if c.name in point}
        try:
            residuals = [g.xreplace(substitution) for g in self.equations]
        except (ZeroDivisionError, ValueError):
            return False
        if any(r.has(sympy.zoo, sympy.nan) for r in residuals):
            return False
        values = self.defaults if self.complete else {}
        return all(vanishes(r, self.system, values) for r in residuals)

    # -- numeric ---------------------------------------------------------------
    def confirms(self, points: Sequence[Mapping[str, sympy.Expr]]) -> bool:
        """True when each numerical root (at the defaults, else at random values) is a point."""
        values = self._check_values()
        expected = []
        for point in points:
            if len(point) < len(self.unknowns):
                return True  # a continuum of equilibria: nothing to compare
            numbers = [number_at(point[c.name], values) for c in self.unknowns]
            if all(z is not None and abs(z.imag) <= 1e-9 * (1 + abs(z.real)) for z in numbers):
                expected.append(np.array([z.real for z in numbers]))
        found = self._roots(values)
        if all(any(self._same(root, e, 1e-6) for e in expected) for root in found):
            return True
        if not self.complete:
            raise self._defaults_needed("SymPy found only some of the equilibria")
        return False

    def numeric(self) -> list[dict[str, sympy.Expr]]:
        """Roots at the default parameter values; ModelError when some are missing."""
        if not self.complete:
            raise self._defaults_needed("SymPy cannot solve for the equilibria")
        return [
            {c.name: sympy.Float(float(x)) for c, x in zip(self.unknowns, root, strict=True)}
            for root in self._roots(self.defaults)
        ]

    def _defaults_needed(self, problem: str) -> ModelError:
        """``problem``, and the parameters without a default that a numerical search needs."""
        missing = [p.name for p in self.system.parameters if p.default is None]
        return ModelError(
            f"{problem}; give default values for {', '.join(missing)} to locate them numerically"
        )

    def _check_values(self) -> dict[str, float]:
        """The defaults, or random values for the parameters without one."""
        return self.defaults if self.complete else self._random_values()

    def _random_values(self) -> dict[str, float]:
        rng = random.Random(11)
        values = dict(self.defaults)
        for p in self.system.parameters:
            if p.default is None:
                magnitude = rng.uniform(0.5, 2.0)
                values[p.name] = -magnitude if p.sign == "negative" else magnitude
        return values

    def _roots(self, values: Mapping[str, float]) -> list[np.ndarray]:
        """Distinct roots of G from starts on a grid and at random in [-pi, pi]^n (searched
        once for the same values)."""
        key = tuple(sorted(values.items()))
        if key not in self._searched:
            self._searched[key] = self._search(values)
        return self._searched[key]

    def _search(self, values: Mapping[str, float]) -> list[np.ndarray]:
        import scipy.optimize  # lazily: `lagrangian derive` never needs SciPy

        q = [c.q for c in self.unknowns]
        table = {
            s: sympy.Float(values[s.name])
            for g in self.equations
            for s in g.free_symbols
            if s not in q
        }
        system = without_distributions(sympy.Matrix(self.equations).xreplace(table))
        function = sympy.lambdify([q], list(system), "numpy")
        jacobian = sympy.lambdify([q], without_distributions(system.jacobian(q)).tolist(), "numpy")
        n = len(q)
        starts = starting_points(n)
        if n == len(self.equations):
            options = {"method": "hybr", "jac": lambda x: np.array(jacobian(x), dtype=float)}
        else:
            options = {"method": "lm"}
        with np.errstate(all="ignore"):
            scale = np.median([np.abs(_call(function, x)).max() for x in starts])
            tolerance = ROOT_TOLERANCE * (scale if np.isfinite(scale) and scale > 0 else 1.0)
            roots: list[np.ndarray] = []
            for start in starts:
                try:
                    result = scipy.optimize.root(lambda x: _call(function, x), start, **options)
                    root = _polished(function, jacobian, result.x, n)
                except (TypeError, ValueError, ZeroDivisionError, np.linalg.LinAlgError):
                    continue
                if root is None or np.abs(_call(function, root)).max() > tolerance:
                    continue
                root = self._reduced(root)
                if not any(self._same(root, r, DEDUPE_TOLERANCE) for r in roots):
                    roots.append(root)
        return sorted(roots, key=tuple)

    def _reduced(self, x: np.ndarray) -> np.ndarray:
        x = np.array(x, dtype=float)
        for i, angle in enumerate(self.angles):
            if angle:
                x[i] = math.remainder(x[i], 2 * math.pi)
                if x[i] <= -math.pi + DEDUPE_TOLERANCE:
                    x[i] = math.pi
        return x

    def _same(self, a: np.ndarray, b: np.ndarray, tolerance: float) -> bool:
        for x, y, angle in zip(a, b, self.angles, strict=True):
            d = abs(x - y)
            if angle:
                d = abs(math.remainder(x - y, 2 * math.pi))
            if d > tolerance * max(1.0, abs(x), abs(y)):
                return False
        return True


def _polished(function, jacobian, x: np.ndarray, n: int) -> np.ndarray | None:
    """A few Newton (least-squares) steps from ``x``; None unless the last step is
    small, i.e. ``x`` is near a root and not where G merely decays (-mu/r^2, r -> oo)."""
    x = np.array(x, dtype=float)
    residual = _call(function, x)
    for _ in range(6):
        if not np.all(np.isfinite(residual)):
            return None
        gradient = np.array(jacobian(list(x)), dtype=float).reshape(-1, n)
        try:  # solve, not lstsq: a tiny pivot must give a huge step, not none
            step = np.linalg.solve(gradient, residual)
        except np.linalg.LinAlgError:
            step = np.linalg.lstsq(gradient, residual, rcond=None)[0]
        candidate = x - step
        candidate_residual = _call(function, candidate)
        if not np.abs(candidate_residual).max() < np.abs(residual).max():
            break
        x, residual = candidate, candidate_residual
    if not np.abs(step).max() <= NEWTON_STEP * max(1.0, np.abs(x).max()):
        return None
    x[np.abs(x) < SNAP_TO_ZERO] = 0.0
    return x


def _call(function, x: np.ndarray) -> np.ndarray:
    return np.array(function(list(x)), dtype=float).ravel()


def number_at(expr: sympy.Expr, values: Mapping[str, float]) -> complex | None:
    if not {s.name for s in expr.free_symbols} <= set(values):
        return None
    table = {s: sympy.Float(values[s.name], 30) for s in expr.free_symbols}
    try:
        number = complex(sympy.N(expr.xreplace(table), 30))
    except (TypeError, ValueError):
        return None
    return number if np.isfinite(number) else None


def starting_points(n: int) -> list[np.ndarray]:
    """The starts of a search in n angles: a grid of about STARTS points (where it is not
    much larger) and STARTS / 4 random ones, the same at every call."""
    per_axis = max(2, round(STARTS ** (1 / n)))
    grid = np.linspace(-math.pi, math.pi, per_axis + 1)[:-1] + math.pi / (2 * per_axis)
    starts = []
    if per_axis**n <= 4 * STARTS:
        starts = [np.array(p) for p in itertools.product(grid, repeat=n)]
    rng = np.random.default_rng(5)
    return starts + list(rng.uniform(-math.pi, math.pi, size=(max(8, STARTS // 4), n)))

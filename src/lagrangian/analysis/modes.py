"""Normal modes of M0 x'' + C0 x' + K0 x = 0: omega^2, shapes, stability.

The computation behind :meth:`~lagrangian.analysis.linear.LinearizedSystem.normal_modes`;
the mathematics is stated in :mod:`lagrangian.analysis.linear`.
"""

from __future__ import annotations

import enum
import random
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..algebra import tidy
from ..model import System

if TYPE_CHECKING:
    from .linear import LinearizedSystem

#: Relative size below which a number counts as zero (omega^2, residuals, real parts).
ZERO_TOLERANCE = 1e-9
#: Largest polynomial (operation count) handed to ``factor_list``.
FACTOR_MAX_OPS = 2_000
#: Largest mode-shape entry (operation count) kept symbolic.
SHAPE_MAX_OPS = 40


class Stability(enum.Enum):
    """Linear stability of an equilibrium."""

    STABLE = "stable"  # bounded oscillations (every omega^2 > 0, no damping)
    ASYMPTOTICALLY_STABLE = "asymptotically stable"  # damped: every exponent Re < 0
    MARGINAL = "marginal"  # a neutral direction (omega^2 = 0), linear theory undecided
    UNSTABLE = "unstable"  # some omega^2 < 0 or not real, or an exponent with Re > 0
    UNDETERMINED = "undetermined"  # see NormalModes.note


@dataclass(frozen=True)
class NormalModes:
    """The small oscillations about an equilibrium.

    ``omega_squared``: one root s = w^2 of det(K0 - w^2 M0 + i w G) = 0 per
    coordinate (with multiplicity, increasing at the default values);
    ``frequencies`` and ``periods`` (2 pi / w) belong to the positive ones;
    ``shapes``: the mode vectors (null vectors of K0 - s M0, first non-zero entry
    1), given when C0 = 0 and K0 is symmetric; ``closed_form``: whether
    ``omega_squared`` are exact expressions (else numbers at the default
    parameter values); ``note``: why the stability is undetermined.

    >>> import lagrangian as lg
    >>> eom = lg.load("simple_pendulum").equations_of_motion()
    >>> linearize(eom, {"theta": 0}).normal_modes().periods
    (2*pi*sqrt(l)/sqrt(g),)
    """

    omega_squared: tuple[sympy.Expr, ...]
    stability: Stability
    closed_form: bool
    shapes: tuple[sympy.ImmutableMatrix, ...] = ()
    frequencies: tuple[sympy.Expr, ...] = ()
    note: str = ""

    @property
    def periods(self) -> tuple[sympy.Expr, ...]:
        return tuple(2 * sympy.pi / w for w in self.frequencies)

    @property
    def stable(self) -> bool:
        return self.stability in (Stability.STABLE, Stability.ASYMPTOTICALLY_STABLE)

    def __repr__(self) -> str:  # the REPL shows the verdict and the numbers
        squares = ", ".join(map(str, self.omega_squared)) or "none"
        note = f"; {self.note}" if self.note else ""
        return f"<NormalModes {self.stability.value}: omega^2 = {squares}{note}>"

    @classmethod
    def undetermined(cls, note: str) -> NormalModes:
        return cls(omega_squared=(), stability=Stability.UNDETERMINED, closed_form=False, note=note)


def vanishes(expr: sympy.Expr, system: System, values: Mapping[str, float]) -> bool:
    """True when ``expr`` (free of the state) is zero: exactly, or to rounding at ``values``.

    Without values for all its symbols, at three random parameter points.
    """
    expr = tidy(expr, trig=True)
    if expr == 0:
        return True
    if expr.has(AppliedUndef, sympy.Derivative):
        return False
    if {s.name for s in expr.free_symbols} <= set(values):
        return _numerically_zero(expr, _by_name(expr, values))
    rng = random.Random(7)
    for _ in range(3):
        sample = {
            p.name: rng.uniform(0.5, 2.0) * (-1 if p.sign == "negative" else 1)
            for p in system.parameters
        } | dict(values)
        if not _numerically_zero(expr, _by_name(expr, sample)):
            return False
    return True


def _numerically_zero(expr: sympy.Expr, substitution: dict) -> bool:
    terms = sympy.Add.make_args(sympy.expand(expr))
    try:
        numbers = [complex(sympy.N(t.xreplace(substitution), 30)) for t in terms]
    except (TypeError, ValueError):
        return False
    scale = max(abs(n) for n in numbers)
    if not np.isfinite(scale):
        return False
    return abs(sum(numbers)) <= 10 * ZERO_TOLERANCE * max(scale, 1e-300)


def _by_name(expr: sympy.Expr, values: Mapping[str, float]) -> dict:
    return {s: sympy.Float(values[s.name], 30) for s in expr.free_symbols if s.name in values}


def assumed_sign(expr: sympy.Expr) -> str | None:
    """'+', '0', '-' or 'complex' where SymPy's assumptions decide it, for ``expr`` or else
    its :func:`_generic` form; None when they do not."""
    for candidate in (expr, _generic(expr)):
        if candidate.is_zero:
            return "0"
        if candidate.is_positive:
            return "+"
        if candidate.is_negative:
            return "-"
        if candidate.is_extended_real is False:
            return "complex"
    return None


def _generic(expr: sympy.Expr) -> sympy.Expr:
    """Real symbols of unknown sign made non-zero: sign decisions for generic values."""
    return expr.xreplace(
        {
            s: sympy.Dummy(s.name, real=True, nonzero=True)
            for s in expr.free_symbols
            if s.is_real and s.is_zero is None and s.is_positive is None
        }
    )


class ModeAnalysis:
    """The computation behind :meth:`LinearizedSystem.normal_modes`."""

    def __init__(self, linear: LinearizedSystem):
        self.linear, self.values, self.n = linear, linear.values, linear.mass.rows
        self.matrices = (linear.mass, linear.stiffness, linear.gyroscopic, linear.dissipative)
        _, stiffness, gyro, damp = self.matrices
        self.undamped, self.gyro_free = bool(damp.is_zero_matrix), bool(gyro.is_zero_matrix)
        # Symmetric M0, K0 and no velocity terms: repeated roots are harmless.
        self.plain = self.gyro_free and _symmetric(stiffness)
        symbols = {s.name for m in self.matrices for s in m.free_symbols}
        self.exact = bool(symbols)
        missing = sorted(symbols - set(self.values))
        self.why = "no closed form; numbers need default values for " + ", ".join(missing)
        self.numbers = None if missing else [self._evaluate(m) for m in self.matrices]
        if self.numbers is not None and not all(np.isfinite(a).all() for a in self.numbers):
            self.numbers = None  # exact but beyond float64, e.g. exp(exp(exp(e)))
            self.why = "the linearized matrices overflow double precision at the default values"
        self.tol = ZERO_TOLERANCE
        if self.numbers is not None:
            m, k, g, d = self.numbers
            try:
                inverse = np.linalg.inv(m)
            except np.linalg.LinAlgError:
                self.numbers, self.why = None, "the mass matrix is singular at the default values"
            else:
                scale = max(np.abs(inverse @ k).max(), np.abs(inverse @ (g + d)).max() ** 2)
                self.tol *= scale if scale > 0 else 1.0

    def compute(self) -> NormalModes:
        roots = self._exact_roots() if self.exact and not self._beyond_quadratics() else None
        closed = roots is not None
        if roots is None:
            if self.numbers is None:
                return NormalModes.undetermined(self.why)
            roots = self._numeric_roots()
        roots.sort(key=lambda item: self._sort_key(item[0]))
        signs = [self._sign(r) for r, _ in roots]
        omega_squared = tuple(r for r, m in roots for _ in range(m))
        spread = [sign for sign, (_, m) in zip(signs, roots, strict=True) for _ in range(m)]
        if not self.undamped:
            stability, note = self._damped()
        elif "-" in signs or "complex" in signs:
            stability, note = Stability.UNSTABLE, ""
        elif None in signs:
            stability, note = (
                Stability.UNDETERMINED,
                "the sign of some omega^2 depends on parameters",
            )
        elif "0" in signs or any(
            m > 1 and sign == "+" and not self.plain
            for (_, m), sign in zip(roots, signs, strict=True)
        ):
            stability, note = Stability.MARGINAL, ""
        else:
            stability, note = Stability.STABLE, ""
        shapes = ()
        if self.undamped and self.plain:
            shapes = (closed and self._exact_shapes(roots)) or self._numeric_shapes()
        return NormalModes(
            omega_squared=omega_squared,
            stability=stability,
            closed_form=closed,
            shapes=shapes,
            frequencies=tuple(
                sympy.sqrt(r) for r, sign in zip(omega_squared, spread, strict=True) if sign == "+"
            ),
            note=note,
        )

    # -- exact -----------------------------------------------------------------
    def _exact_roots(self) -> list[tuple[sympy.Expr, int]] | None:
        """Roots s of det(K0 - w^2 M0 + i w G) (even in w), when its factors have degree <= 2."""
        mass, stiffness, gyro, _ = self.matrices
        w, s = sympy.Dummy("w"), sympy.Dummy("s")
        matrix = stiffness - w**2 * mass + sympy.I * w * gyro
        terms = sympy.Poly(sympy.expand(matrix.det(method="berkowitz")), w).terms()
        if any(k % 2 and tidy(c, trig=True) != 0 for (k,), c in terms):
            return None  # not even in w (circulatory and gyroscopic forces together)
        in_s = sum((c * s ** (k // 2) for (k,), c in terms if k % 2 == 0), sympy.Integer(0))
        in_s = sympy.fraction(sympy.together(in_s))[0]  # parameters in denominators: same roots
        factors = [(in_s, 1)]
        if sympy.degree(in_s, s) > 2:
            if sympy.count_ops(in_s) > FACTOR_MAX_OPS:
                return None
            factors = sympy.factor_list(in_s)[1]
        roots: list[tuple[sympy.Expr, int]] = []
        for factor, multiplicity in factors:
            if not 0 < sympy.degree(factor, s) <= 2:
                if factor.has(s):
                    return None
                continue
            for root, m in sympy.roots(sympy.Poly(factor, s)).items():
                roots.append((_tidy_root(root), m * multiplicity))
        return roots if sum(m for _, m in roots) == self.n else None

    def _beyond_quadratics(self) -> bool:
        """Whether det(K0 - s M0) has a factor of degree > 2 that does not split, seen at
        random rational values of its symbols (no gyroscopic terms): then
        :meth:`_exact_roots` finds no closed form, after a symbolic determinant and
        factorization that cost a 3-link chain 0.35 s an equilibrium; this takes
        milliseconds.  Sound one way: a split into factors of degree <= 2 stays one under
        any substitution that keeps the degree.  False decides nothing."""
        mass, stiffness, gyro, _ = self.matrices
        if self.n <= 2 or not gyro.is_zero_matrix:
            return False
        rng = random.Random(3)
        symbols = sorted(mass.free_symbols | stiffness.free_symbols, key=str)
        values = {x: sympy.Rational(rng.randint(2, 40), rng.randint(2, 40)) for x in symbols}
        mass, stiffness = mass.xreplace(values), stiffness.xreplace(values)
        if not all(entry.is_Rational for entry in (*mass, *stiffness)):
            return False  # an irrational or a function of a symbol: no factorisation over Q
        s = sympy.Dummy("s")
        polynomial = sympy.Poly((stiffness - s * mass).det(method="berkowitz"), s)
        if polynomial.degree() != self.n:
            return False  # the values made M0 singular: the degree is not the generic one
        return any(factor.degree() > 2 for factor, _ in polynomial.factor_list()[1])

    def _exact_shapes(self, roots) -> tuple[sympy.ImmutableMatrix, ...] | None:
        """Null vectors of K0 - s M0 from a non-zero column of its adjugate (simple roots)."""
        if any(m > 1 for _, m in roots):
            return None
        s = sympy.Dummy("s")
        adjugate = (self.matrices[1] - s * self.matrices[0]).adjugate(method="berkowitz")
        shapes = []
        for root, _ in roots:
            for column in range(self.n):
                vector = [tidy(adjugate[i, column].xreplace({s: root})) for i in range(self.n)]
                system = self.linear.system
                lead = next((v for v in vector if not vanishes(v, system, self.values)), None)
                if lead is not None:
                    break
            else:
                return None
            if sum(sympy.count_ops(v) for v in vector) > 4 * SHAPE_MAX_OPS:
                return None
            entries = [_shorter(sympy.cancel(v / lead), v / lead) for v in vector]
            if any(sympy.count_ops(e) > SHAPE_MAX_OPS for e in entries):
                return None
            entries = [_shorter(tidy(sympy.radsimp(e)), e) for e in entries]
            shapes.append(sympy.ImmutableMatrix(entries))
        return tuple(shapes)

    # -- numeric ---------------------------------------------------------------
    def _evaluate(self, matrix: sympy.Matrix) -> np.ndarray:
        table = {s: sympy.Float(self.values[s.name]) for s in matrix.free_symbols}
        return np.array(matrix.xreplace(table).evalf(), dtype=complex).real

    def _exponents(self) -> np.ndarray:
        """lambda with det(M0 lambda^2 + C0 lambda + K0) = 0, from the first-order form."""
        m, k, g, d = self.numbers
        n = self.n
        block = np.block(
            [[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, np.hstack([k, g + d]))]]
        )
        return np.linalg.eigvals(block)

    def _numeric_roots(self) -> list[tuple[sympy.Expr, int]]:
        m, k, g, _ = self.numbers
        if self.plain:
            import scipy.linalg  # lazily: `lagrangian derive` never needs SciPy

            values = scipy.linalg.eigvals(k, m)
        else:  # s = -lambda^2 of the undamped system; the exponents come as +-lambda
            n = self.n
            block = np.block(
                [[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(m, np.hstack([k, g]))]]
            )
            values = _pairs(-(np.linalg.eigvals(block) ** 2))
        merged: list[list] = []
        for z in sorted((complex(v) for v in values), key=lambda z: (z.real, z.imag)):
            if merged and abs(z - merged[-1][0]) <= 1e-7 * abs(z) + self.tol:
                merged[-1][1] += 1
            else:
                merged.append([z, 1])
        return [(_number(z, self.tol), count) for z, count in merged]

    def _numeric_shapes(self) -> tuple[sympy.ImmutableMatrix, ...]:
        if self.numbers is None:
            return ()
        try:
            import scipy.linalg

            vectors = scipy.linalg.eigh(self.numbers[1], self.numbers[0])[1]
        except np.linalg.LinAlgError:  # M0 not positive definite at the defaults
            return ()
        return tuple(_normalized(vectors[:, i]) for i in range(self.n))

    # -- decisions -------------------------------------------------------------
    def _damped(self) -> tuple[Stability, str]:
        lam = sympy.Dummy("lambda")
        mass, stiffness, gyro, damp = self.matrices
        matrix = mass * lam**2 + (gyro + damp) * lam + stiffness
        poly = sympy.Poly(sympy.expand(matrix.det(method="berkowitz")), lam)
        if poly.degree() <= 4 and _hurwitz_positive([_generic(a) for a in poly.all_coeffs()]):
            return Stability.ASYMPTOTICALLY_STABLE, ""
        if self.numbers is None:
            return Stability.UNDETERMINED, self.why
        exponents = self._exponents()
        tol = ZERO_TOLERANCE * np.sqrt(self.tol / ZERO_TOLERANCE)  # lambda ~ sqrt(omega^2)
        if exponents.real.max() > tol:
            return Stability.UNSTABLE, ""
        if exponents.real.max() < -tol:
            return Stability.ASYMPTOTICALLY_STABLE, ""
        if np.abs(exponents).min() <= tol:
            return Stability.MARGINAL, ""
        return Stability.STABLE, ""

    def _sign(self, expr: sympy.Expr) -> str | None:
        """'+', '0', '-', 'complex', or None when undecidable."""
        if not expr.free_symbols:
            return _numeric_sign(complex(sympy.N(expr)), self.tol)
        sign = assumed_sign(expr)
        if sign is not None:
            return sign
        number = self._at_defaults(expr)
        return None if number is None else _numeric_sign(number, self.tol)

    def _at_defaults(self, expr: sympy.Expr) -> complex | None:
        if not {s.name for s in expr.free_symbols} <= set(self.values):
            return None
        try:
            return complex(sympy.N(expr.xreplace(_by_name(expr, self.values)), 30))
        except (TypeError, ValueError):
            return None

    def _sort_key(self, expr: sympy.Expr) -> tuple[float, float]:
        """Order by value at the defaults (1, or -1 if negative, where there is none)."""
        unit = {
            p.name: -1.0 if p.sign == "negative" else 1.0 for p in self.linear.system.parameters
        }
        try:
            number = complex(sympy.N(expr.xreplace(_by_name(expr, unit | dict(self.values)))))
        except (TypeError, ValueError):
            return (0.0, 0.0)
        return (number.real, number.imag)


def _tidy_root(root: sympy.Expr) -> sympy.Expr:
    cleaned = tidy(root)
    if sympy.count_ops(cleaned) <= 60:
        cleaned = sympy.factor_terms(sympy.cancel(cleaned))
    return _shorter(cleaned, root)


def _shorter(a: sympy.Expr, b: sympy.Expr) -> sympy.Expr:
    return a if sympy.count_ops(a) <= sympy.count_ops(b) else b


def _number(z: complex, tol: float) -> sympy.Expr:
    if abs(z.imag) <= tol:
        return sympy.Float(0) if abs(z.real) <= tol else sympy.Float(z.real)
    return sympy.Float(z.real) + sympy.I * sympy.Float(z.imag)


def _numeric_sign(z: complex, tol: float) -> str:
    if abs(z.imag) > max(tol, 1e-7 * abs(z)):
        return "complex"
    if abs(z.real) <= tol:
        return "0"
    return "+" if z.real > 0 else "-"


def _symmetric(matrix: sympy.Matrix) -> bool:
    """K0 = K0^T exactly, or to rounding when K0 holds numbers (a numerical equilibrium)."""
    difference = matrix - matrix.T
    if difference.is_zero_matrix is True:
        return True
    if not all(entry.is_number for entry in matrix):
        return False
    scale = max((abs(complex(entry)) for entry in matrix), default=0.0)
    return max(abs(complex(entry)) for entry in difference) <= 1e-9 * max(scale, 1e-300)


def _pairs(values: np.ndarray) -> list[complex]:
    """The n values of s = -lambda^2 from 2n exponents, which come in pairs (lambda, -lambda)."""
    remaining = sorted((complex(v) for v in values), key=lambda z: (z.real, z.imag))
    paired = []
    while remaining:
        first = remaining.pop(0)
        partner = min(range(len(remaining)), key=lambda i: abs(remaining[i] - first))
        paired.append((first + remaining.pop(partner)) / 2)
    return paired


def _normalized(vector: np.ndarray) -> sympy.ImmutableMatrix:
    lead = next(v for v in vector if abs(v) > 1e-9 * np.abs(vector).max())
    return sympy.ImmutableMatrix([sympy.Float(float(np.real(v / lead))) for v in vector])


def _hurwitz_positive(coefficients: list[sympy.Expr]) -> bool:
    """True when a_0 lambda^d + ... + a_d provably has every root with Re < 0 (a_0 > 0)."""
    d = len(coefficients) - 1
    if not all(sympy.expand(a).is_positive for a in coefficients):
        return False
    hurwitz = sympy.Matrix(
        d, d, lambda i, j: coefficients[2 * j - i + 1] if 0 <= 2 * j - i + 1 <= d else 0
    )
    minors = (hurwitz[:k, :k].det(method="berkowitz") for k in range(2, d))
    return all(sympy.expand(minor).is_positive for minor in minors)

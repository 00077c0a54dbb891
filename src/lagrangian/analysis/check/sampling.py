"""Expressions evaluated at seeded random points: the numerical identity test of ``check``.

Two expressions are taken as equal when they agree at random points to a relative
tolerance (Schwartz-Zippel for polynomials; for the analytic functions of mechanics a
coincidence at a dozen random points is as unlikely).  The points come in ``PARAMETER_SETS``
sets of parameter values with ``STATES`` states each, so that a quantity can be tested for
depending on the state (q, q', q'', p, t) at all: equal across the states of each set.
The page's checker (``page_assets/exercise.js``) follows the same rules in the browser.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy

from ...algebra import as_expression

PARAMETER_SETS = 3
STATES = 5
#: Relative tolerance of every numerical comparison (values are computed in double
#: precision from expressions of a few dozen operations).
TOLERANCE = 1e-7
SEED = 20261129
#: How many compiled expressions are kept (a check of the cart-pole's equations evaluates
#: about 150 distinct terms, each many times).
COMPILED_KEPT = 2048


@dataclass(frozen=True)
class Points:
    """Values of ``symbols`` at ``PARAMETER_SETS`` x ``STATES`` points (arrays of that shape)."""

    symbols: tuple[sympy.Symbol, ...]
    values: tuple[np.ndarray, ...]

    def evaluate(self, expr: sympy.Expr) -> np.ndarray:
        """``expr`` at every point (NaN where it is not a finite real number)."""
        expr = as_expression(expr)
        unknown = expr.free_symbols - set(self.symbols)
        if unknown:
            raise ValueError(f"no values for {sorted(map(str, unknown))}")
        function = _compiled(self.symbols, expr)
        with np.errstate(all="ignore"):
            result = np.asarray(function(*self.values), dtype=complex)
        result = np.broadcast_to(result, self.values[0].shape)
        real = np.where(
            np.abs(result.imag) <= 1e-12 * (1 + np.abs(result.real)), result.real, np.nan
        )
        return np.where(np.isfinite(real), real, np.nan)


@lru_cache(maxsize=COMPILED_KEPT)
def _compiled(symbols: tuple[sympy.Symbol, ...], expr: sympy.Expr):
    """``expr`` as a NumPy function of ``symbols``, made once: a check evaluates the same
    terms again and again (each term of the right answer against each of the student's,
    every answer against the same right one), and lambdify, not the arithmetic, was most
    of its time (the cart-pole's 79 usual slips: 2231 evaluations of 149 expressions,
    5.7 s of CPU, 2.6 s made once)."""
    return sympy.lambdify(symbols, expr, modules="numpy")


def points(state: Iterable[sympy.Symbol], parameters: Iterable[sympy.Symbol]) -> Points:
    """Seeded random points: parameters in [0.5, 2] (positive) or +-[0.5, 2] (real), the
    state in +-[0.2, 1.4], both away from 0 where a factor could vanish by chance."""
    rng = np.random.default_rng(SEED)
    shape = (PARAMETER_SETS, STATES)
    symbols, values = [], []
    for symbol in sorted(set(parameters), key=str):
        base = rng.uniform(0.5, 2.0, size=(PARAMETER_SETS, 1))
        if not symbol.is_positive:
            base = base * rng.choice([-1.0, 1.0], size=base.shape)
        symbols.append(symbol)
        values.append(np.broadcast_to(base, shape).copy())
    for symbol in sorted(set(state), key=str):
        magnitude = rng.uniform(0.2, 1.4, size=shape)
        symbols.append(symbol)
        values.append(magnitude * rng.choice([-1.0, 1.0], size=shape))
    return Points(tuple(symbols), tuple(values))


def close(a: np.ndarray, b: np.ndarray, scale: np.ndarray | float = 0.0) -> bool:
    """a = b at every point where both are finite (at least two per parameter set, or the
    one value of a set)."""
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    bound = TOLERANCE * (np.abs(a) + np.abs(b) + np.abs(scale)) + 1e-300
    finite = np.isfinite(a) & np.isfinite(b)
    if not _enough(finite):
        return False
    return bool(np.all(np.abs(a - b)[finite] <= np.broadcast_to(bound, a.shape)[finite]))


def state_free(values: np.ndarray, scale: np.ndarray | float = 0.0) -> bool:
    """The values are the same at every state of each parameter set (a function of the
    parameters only)."""
    values = np.asarray(values, float)
    if values.ndim < 2:
        return True
    first = np.nanmedian(values, axis=1, keepdims=True)
    return close(values, np.broadcast_to(first, values.shape), scale)


def per_set(values: np.ndarray) -> np.ndarray:
    """One value per parameter set (the median over its states), shape (PARAMETER_SETS, 1)."""
    values = np.asarray(values, float)
    if values.ndim < 2:
        return np.broadcast_to(values, (PARAMETER_SETS, 1))
    return np.nanmedian(values, axis=1, keepdims=True)


def _enough(finite: np.ndarray) -> bool:
    if finite.ndim < 2:
        return bool(finite.any())
    return bool(np.all(finite.sum(axis=1) >= min(2, finite.shape[1])))


def magnitude(parts: Sequence[np.ndarray]) -> np.ndarray:
    """sum |part|: the scale that rounding errors of a sum of these parts are measured in."""
    total = np.zeros((PARAMETER_SETS, STATES))
    for part in parts:
        total = total + np.abs(np.nan_to_num(np.asarray(part, float)))
    return total

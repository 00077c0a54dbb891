"""SymPy expressions evaluated at one numeric point, in double precision.

The symbolic stages check their claims at random sample points (a mass matrix
is regular, dC/dt vanishes along the motion).  Substituting SymPy Floats makes
SymPy evaluate every function at arbitrary precision as it goes, and a tower
such as exp(exp(exp(exp(exp(x))))) then asks mpmath for a number with 10^17
digits: minutes, or an OverflowError.  SymEngine evaluates in double
precision, where such a value is inf, which the callers read as "no verdict
from this point" and draw another; it is also ten times faster than SymPy's
substitution for a small mass matrix.
"""

from __future__ import annotations

import random
from collections.abc import Mapping

import numpy as np
import symengine
import sympy

from .algebra import to_symengine


def evaluate(expr: sympy.Basic, values: Mapping[sympy.Basic, float]) -> np.ndarray | None:
    """``expr`` (an expression or a matrix) at ``values`` as a float array, or None.

    Keys of ``values`` are symbols or whole subexpressions such as f(x) or
    Derivative(f(x), x) (each replaced as a unit).  None when something of
    ``expr`` has no value, when the result is complex or not finite (overflow,
    a pole, the root of a negative number) or cannot be evaluated at all (a
    function SymEngine lacks).
    """
    standing_in = {key: sympy.Dummy() for key in values if not isinstance(key, sympy.Symbol)}
    if standing_in:  # Dummies, not numbers: SymPy must not evaluate anything here
        expr = expr.xreplace(standing_in)
    if expr.has(sympy.DiracDelta):  # d|u|/du^2 and the like: 0 but on a set of measure zero
        expr = expr.replace(sympy.DiracDelta, lambda *arguments: sympy.Integer(0))
    numbers = {
        symengine.Symbol(standing_in.get(key, key).name): symengine.RealDouble(float(value))
        for key, value in values.items()
    }
    is_matrix = isinstance(expr, sympy.MatrixBase)
    entries, shape = (list(expr), expr.shape) if is_matrix else ([expr], ())
    cache: dict = {}
    result = []
    for entry in entries:
        converted = to_symengine(entry, cache)
        if converted is None:
            return None
        try:
            result.append(float(converted.subs(numbers).n(53, real=True)))
        except (RuntimeError, TypeError, ValueError, ZeroDivisionError, OverflowError):
            return None  # a symbol left over, or a complex result
    array = np.array(result, dtype=float).reshape(shape)
    return array if np.all(np.isfinite(array)) else None


def surely_nonzero(expr: sympy.Expr, *, seed: int = 7) -> bool:
    """True when ``expr`` is clearly not 0 at a random point (symbols by their signs).

    A quick answer before a symbolic test: ``is_zero`` tidies the expression, which
    for a large dL/dq takes seconds.  "Clearly": larger than 1e-8 of its largest
    term, far above the rounding of an identity that cancels.  False when the point
    cannot be evaluated (declared functions, overflow): the symbolic test decides.
    """
    rng = random.Random(seed)
    values = {}
    for s in expr.free_symbols:
        value = rng.uniform(0.3, 1.3)
        values[s] = -value if s.is_negative else value
    terms = sympy.Add.make_args(expr)
    numbers = [evaluate(term, values) for term in terms]
    if any(n is None for n in numbers):
        return False
    scale = max(abs(float(n)) for n in numbers)
    return abs(sum(float(n) for n in numbers)) > 1e-8 * scale

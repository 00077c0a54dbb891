"""Size limits of the parser, and the estimates that enforce them before SymPy computes.

Every limit is checked *before* the work it bounds: the length before tokenizing,
tokens while tokenizing, nesting while parsing, and the size of an exact number
before SymPy is asked to build it.  An exact power ``b**e`` has about
``|e| * log10|b|`` digits, so ``9**9**9`` is refused from that estimate, not after
a long computation.

Two costs are bounded by internal constants rather than by :class:`ParseLimits`:

* SymPy extracts roots of numbers by trial factoring, which costs about a second
  for a 2,000-digit number (measured: 1 ms at 100 digits, 5 ms at 200).  Roots of
  numbers longer than :data:`ROOT_DIGITS_LIMIT` are refused, and the estimated
  time of all root extractions in one expression is capped by
  :data:`ROOT_WORK_BUDGET_US`.
* Python refuses to print an integer of more than 4,300 digits, so
  ``max_result_digits`` may not exceed :data:`PRINTABLE_DIGITS`.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import sympy

LITERAL_EXPONENT_LIMIT = 400
"""Largest ``|n|`` in a literal such as ``1e300``."""

ROOT_DIGITS_LIMIT = 200
"""Largest number (digits) whose non-integer power SymPy is asked to evaluate."""

ROOT_WORK_BUDGET_US = 300_000
"""Estimated microseconds of root extraction allowed in one expression."""

PRINTABLE_DIGITS = 4_000
"""Upper bound of ``max_result_digits``: Python cannot print longer integers."""

_MAX_DEPTH_CAP = 200  # deeper nesting would approach Python's recursion limit
_MAX_NUMBER_DIGITS_CAP = 4_000  # int() refuses strings over 4,300 digits


@dataclass(frozen=True)
class ParseLimits:
    """Bounds on the input and on the numbers built from it.

    ``max_length``: characters of input.  ``max_depth``: nesting of parentheses,
    braces, calls, unary signs and exponents.  ``max_nodes``: tokens.
    ``max_exponent``: ``|e|`` of a numeric exponent (numerator and, for a power
    of a number, denominator).  ``max_number_digits``: digits of one literal.
    ``max_result_digits``: estimated digits of an exact number built by the
    arithmetic in the expression.
    """

    max_length: int = 20_000
    max_depth: int = 64
    max_nodes: int = 20_000
    max_exponent: int = 1_000
    max_number_digits: int = 100
    max_result_digits: int = PRINTABLE_DIGITS

    def __post_init__(self) -> None:
        for item in fields(self):
            value = getattr(self, item.name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"ParseLimits.{item.name} must be a positive integer: {value!r}")
        caps = {
            "max_depth": _MAX_DEPTH_CAP,
            "max_number_digits": _MAX_NUMBER_DIGITS_CAP,
            "max_result_digits": PRINTABLE_DIGITS,
        }
        for name, cap in caps.items():
            if getattr(self, name) > cap:
                raise ValueError(f"ParseLimits.{name} may not exceed {cap}")


DEFAULT_LIMITS = ParseLimits()


def int_digits(value: int) -> int:
    """Decimal digits of ``value`` (an upper bound, exact to within one)."""
    return abs(value).bit_length() * 30103 // 100000 + 1


def rational_digits(value: sympy.Rational) -> int:
    """Digits of the numerator plus those of the denominator (if not 1)."""
    digits = int_digits(value.p)
    if value.q != 1:
        digits += int_digits(value.q)
    return digits


def numeric_size(expr: sympy.Expr) -> float:
    """Estimated digits of the exact numbers SymPy would carry along with ``expr``.

    A rational counts its digits; ``b**r`` (both rational) counts
    ``digits(b) * |r|``; a product counts the sum over its factors; a sum its
    largest term (SymPy may pull a common numeric factor out of it).  Anything
    else (symbols, functions) counts 0.  Looks only one level into products
    and sums, which is where SymPy combines numbers.
    """
    if expr.is_Rational:
        return rational_digits(expr)
    if expr.is_Pow:
        return _power_size(expr)
    if expr.is_Mul:
        return sum(_factor_size(arg) for arg in expr.args)
    if expr.is_Add:
        return max((_term_size(arg) for arg in expr.args), default=0)
    return 0


def root_base_digits(expr: sympy.Expr) -> int:
    """Digits of the numbers under non-integer powers in ``expr`` (one level deep).

    SymPy merges ``sqrt(a)*sqrt(b)`` into ``sqrt(a*b)``, so the roots in one
    product count together.
    """
    args = expr.args if expr.is_Mul else (expr,)
    total = 0
    for arg in args:
        if arg.is_Pow and arg.base.is_Rational and arg.exp.is_Rational and arg.exp.q != 1:
            total += rational_digits(arg.base)
    return total


def root_work_us(digits: float) -> float:
    """Estimated microseconds SymPy takes for a root of a number with ``digits`` digits."""
    return 200 + digits * digits / 10


def _power_size(expr: sympy.Pow) -> float:
    base, exp = expr.args
    if base.is_Rational and exp.is_Rational:
        return rational_digits(base) * abs(float(exp))
    return 0


def _factor_size(expr: sympy.Expr) -> float:
    if expr.is_Rational:
        return rational_digits(expr)
    if expr.is_Pow:
        return _power_size(expr)
    return 0


def _term_size(expr: sympy.Expr) -> float:
    if expr.is_Mul:
        return sum(_factor_size(arg) for arg in expr.args)
    return _factor_size(expr)

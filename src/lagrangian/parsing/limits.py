"""Size limits of the parser, and the estimates that enforce them before SymPy computes.

Every limit is checked *before* the work it bounds: the length before tokenizing,
tokens while tokenizing, nesting while parsing, and the size of an exact number
before SymPy is asked to build it.  An exact power ``b**e`` has about
``|e| * log10|b|`` digits, so ``9**9**9`` is refused from that estimate, not after
a long computation.

Three costs are bounded by internal constants rather than by :class:`ParseLimits`:

* SymPy extracts roots of numbers by trial factoring, which costs about a second
  for a 2,000-digit number (measured: 1 ms at 100 digits, 5 ms at 200).  Roots of
  numbers longer than :data:`ROOT_DIGITS_LIMIT` are refused, and the estimated
  time of all root extractions in one expression is capped by
  :data:`ROOT_WORK_BUDGET_US`.
* SymPy asks every argument of ``sin``, ``exp``, ``Abs``... (and every symbolic
  exponent) about its sign, parity and reality, at up to 0.8 ms a compound node,
  so those arguments are limited to :data:`ARGUMENT_NODE_BUDGET` nodes in all.
* Python refuses to print an integer of more than 4,300 digits, so
  ``max_result_digits`` may not exceed :data:`PRINTABLE_DIGITS`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields

import sympy

LITERAL_EXPONENT_LIMIT = 400
"""Largest ``|n|`` in a literal such as ``1e300``."""

ROOT_DIGITS_LIMIT = 200
"""Largest number (digits) whose non-integer power SymPy is asked to evaluate."""

ROOT_WORK_BUDGET_US = 150_000
"""Estimated microseconds of root extraction allowed in one expression."""

ARGUMENT_NODE_BUDGET = 400
"""Compound nodes of SymPy expressions given, in all, as arguments of built-in functions
and as symbolic exponents: SymPy queries their assumptions at 0.1 to 0.8 ms a node."""

PRINTABLE_DIGITS = 4_000
"""Upper bound of ``max_result_digits``: Python cannot print longer integers."""

_MAX_DEPTH_CAP = 64  # the parser takes up to 8 Python frames a level
_MAX_NUMBER_DIGITS_CAP = 4_000  # int() refuses strings over 4,300 digits
_HUGE = 1e300
_HUGE_DIGITS = 290


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


def log_size(value: int) -> float:
    """``log10|value|`` (0 for 0): a number has ``floor(log_size) + 1`` digits."""
    return math.log10(abs(value)) if value else 0.0


def rational_size(value: sympy.Rational) -> float:
    """The size of an exact rational: ``log10|p| + log10(q)``."""
    return log_size(value.p) + log_size(value.q)


def magnitude(expr: sympy.Expr) -> float:
    """An upper bound of how much ``expr`` scales an exponent it appears in.

    The absolute value of a rational; sums add and products multiply the bounds
    of their arguments; anything else counts 1.  SymPy merges ``b**e1 * b**e2``
    into ``b**(e1 + e2)``, so ``2**(10**300*x)`` must be refused although it is
    not yet a number.
    """
    if expr.is_Rational:
        if log_size(expr.p) - log_size(expr.q) > _HUGE_DIGITS:
            return _HUGE
        return abs(expr.p) / expr.q
    if expr.is_Add:
        return min(sum(magnitude(arg) for arg in expr.args), _HUGE)
    if expr.is_Mul:
        bound = 1.0
        for arg in expr.args:
            bound = min(bound * magnitude(arg), _HUGE)
        return bound
    return 1.0


def numeric_size(expr: sympy.Expr) -> float:
    """Estimated digits of the exact numbers SymPy would carry along with ``expr``.

    A rational counts its digits; ``b**e`` counts ``size(b) * magnitude(e)``
    (also for a symbolic ``e``, which a product may merge into a number);
    ``exp(c*log(b))`` counts as ``b**c``; a product counts the sum over its
    factors and a sum its largest term (SymPy may pull a common numeric factor
    out of it).  Symbols and other functions count 0.
    """
    if expr.is_Rational:
        return rational_size(expr)
    if expr.is_Pow:
        size = numeric_size(expr.base)
        return size * magnitude(expr.exp) if size else 0
    if isinstance(expr, sympy.exp):
        return exp_size(expr.args[0])
    if expr.is_Mul:
        return sum(numeric_size(arg) for arg in expr.args if not arg.is_Add)
    if expr.is_Add:
        return max(numeric_size(arg) for arg in expr.args)
    return 0


def root_sizes(expr: sympy.Expr) -> list[float]:
    """Sizes of the numbers that the factors of ``expr`` may take roots of.

    SymPy merges ``sqrt(a)*sqrt(b)`` into ``sqrt(a*b)``, and ``2**(x + 1/2)*2**(-x)``
    into ``sqrt(2)``, so the roots in one product count together.
    """
    sizes = []
    for arg in sympy.Mul.make_args(expr):
        if arg.is_Pow and not arg.exp.is_Integer:
            sizes.append(numeric_size(arg.base))
        elif isinstance(arg, sympy.exp):
            sizes.append(exp_size(arg.args[0]))
    return [size for size in sizes if size]


def count_new_nodes(expr: sympy.Basic, seen: set[sympy.Basic], limit: int) -> int:
    """The number of compound nodes of ``expr`` not in ``seen`` (which they are added to).

    Atoms (symbols, numbers) cost SymPy next to nothing and are not counted.
    Counting stops a little past ``limit``.  SymPy remembers what it learnt
    about an expression, so a subexpression seen before costs nothing again.
    """
    count = 0
    stack = [expr]
    while stack and count <= limit:
        node = stack.pop()
        if not node.args or node in seen:
            continue
        seen.add(node)
        count += 1
        stack.extend(node.args)
    return count


def root_work_us(size: float) -> float:
    """Estimated microseconds SymPy takes for a root of a number of ``size`` digits."""
    return 300 + size * size / 8


def exp_size(argument: sympy.Expr) -> float:
    size = 0.0
    for term in sympy.Add.make_args(argument):
        for factor in sympy.Mul.make_args(term):
            if isinstance(factor, sympy.log):
                size += numeric_size(factor.args[0]) * magnitude(term)
    return size


def sum_size(terms: Sequence[sympy.Expr], limit: int, known: dict | None = None) -> float:
    """Estimated size of the numbers in a sum: a common denominator makes them grow.

    ``log10`` of the least common multiple of the denominators (computed until
    it passes ``limit`` digits) plus the size of the largest term.  ``known`` keeps each
    term's (size, denominators) for the next sums (a model's sums share their terms).
    """
    largest = 0.0
    common = 1
    for term in terms:
        found = None if known is None else known.get(term)
        if found is None:
            found = _term_numbers(term)
            if known is not None:
                known[term] = found
        size, denominators = found
        largest = max(largest, size)
        for q in denominators:
            if log_size(common) <= limit:
                common = math.lcm(common, q)
    return largest + log_size(common) + log_size(len(terms))


def _term_numbers(term: sympy.Expr) -> tuple[float, tuple[int, ...]]:
    """(the largest numeric size of ``term``'s parts, their coefficients' denominators)."""
    largest = 0.0
    denominators = []
    for part in sympy.Add.make_args(term):
        largest = max(largest, numeric_size(part))
        coefficient = part.as_coeff_Mul()[0]
        if coefficient.is_Rational and coefficient.q != 1:
            denominators.append(coefficient.q)
    return largest, tuple(denominators)

"""Constant subexpressions must be real and finite: decided by interval arithmetic, in bounded time.

SymPy accepts ``sqrt(-1)``, ``acos(2)``, ``log(-1)`` or ``(-8)**(1/3)`` and
carries them along as complex constants (``I``, ``acos(2)``, ``2*(-1)**(1/3)``);
a model holding one is not a real mechanical system, and the symbolic stages
spend minutes simplifying it.  So every constant is enclosed in an interval
(``mpmath``'s outward-rounded interval arithmetic at :data:`PRECISION_BITS`)
as it is built, and one is refused when it is certainly not real: a negative
base under a non-integer power, the logarithm of a negative number, ``asin`` /
``acos`` outside [-1, 1], or SymPy's ``I`` itself (which also catches
``sqrt(-m)`` for a positive parameter ``m``, which SymPy turns into ``I*sqrt(m)``).

A decision that rounding could change is not made: an interval that straddles
a boundary (``sqrt(sin(1)**2 + cos(1)**2 - 1)``, zero but not simplified)
leaves the constant unknown, and unknown constants are accepted.  Every node
is evaluated once (the enclosures are remembered), each operation at a fixed
precision, and arguments so large that ``exp`` of them would need huge working
precision (:data:`EXP_ARGUMENT_LIMIT`) are left unknown, so the check costs
microseconds a node whatever the input.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence

import sympy
from mpmath.ctx_iv import MPIntervalContext
from mpmath.ctx_mp import MPContext

PRECISION_BITS = 80
"""Bits of the interval endpoints: rounding noise far below any real domain error."""

EXP_ARGUMENT_LIMIT = 100_000
"""Largest ``|x|`` whose ``exp`` (and ``sinh``, ``cosh``, ``b**x``) is enclosed; beyond it
the value is left unknown (mpmath would work at about ``|x|`` bits of precision)."""

_NON_FINITE = (sympy.S.ComplexInfinity, sympy.S.NaN, sympy.S.Infinity, sympy.S.NegativeInfinity)


class NotRealError(Exception):
    """``subexpression`` is a constant that is not a real number (``reason`` says which way)."""

    def __init__(self, subexpression: sympy.Basic, reason: str = "is not a real number"):
        self.subexpression = subexpression
        self.reason = reason
        super().__init__(f"{subexpression} {reason}")


class _OutsideDomain(Exception):
    """A function met an argument outside its real domain (the node is named by the caller)."""


class RealConstants:
    """Enclosures of the constant subexpressions seen so far (``None``: not constant or unknown).

    >>> checker = RealConstants()
    >>> checker.check(sympy.sqrt(2) + sympy.pi)
    >>> checker.check(sympy.acos(2))
    Traceback (most recent call last):
    ...
    lagrangian.parsing.constants.NotRealError: acos(2) is not a real number
    """

    def __init__(self) -> None:
        self.known: dict[sympy.Basic, object] = {}

    # mpmath's contexts and the table of functions, made on the first constant met: a
    # checker is made per expression parsed, and most meet none (sin(q), l*q_dot**2)
    @functools.cached_property
    def iv(self) -> MPIntervalContext:
        return _contexts()[0]

    @functools.cached_property
    def mp(self) -> MPContext:
        return _contexts()[1]

    @functools.cached_property
    def functions(self) -> dict[type, Callable[[object], object]]:
        mp = self.mp
        return {
            sympy.exp: self._exp,
            sympy.log: self._log,
            sympy.sin: self.iv.sin,
            sympy.cos: self.iv.cos,
            sympy.tan: self.iv.tan,
            sympy.cot: self.iv.cot,
            sympy.sec: self.iv.sec,
            sympy.csc: self.iv.csc,
            sympy.asin: lambda x: self._monotone(self._unit(x), mp.asin),
            sympy.acos: lambda x: self._monotone(self._unit(x), mp.acos),
            sympy.atan: lambda x: self._monotone(x, mp.atan),
            sympy.tanh: lambda x: self._monotone(x, mp.tanh),
            sympy.sinh: lambda x: self._monotone(self._moderate(x), mp.sinh),
            sympy.cosh: lambda x: self._monotone(self._moderate(self._abs(x)), mp.cosh),
            sympy.Abs: self._abs,
            sympy.sign: self._sign,
            sympy.atan2: self._atan2,
        }

    def check(self, expr: sympy.Basic) -> None:
        """Raise :class:`NotRealError` naming the first constant of ``expr`` that is not real."""
        self.enclosure(expr)

    def enclosure(self, expr: sympy.Basic):
        """An interval holding the value of ``expr``, or ``None`` (not constant, or unknown).

        Post-order without recursion (adopted SymPy expressions may be deep);
        nodes already enclosed are not visited again.
        """
        known = self.known
        stack: list[tuple[sympy.Basic, bool]] = [(expr, False)]
        while stack:
            node, ready = stack.pop()
            if node in known:
                continue
            if not ready:
                stack.append((node, True))
                stack.extend((arg, False) for arg in node.args if arg not in known)
                continue
            try:
                value = self._evaluate(node, [known[arg] for arg in node.args])
            except _OutsideDomain:
                raise NotRealError(node) from None
            known[node] = value if value is None or self._finite(value) else None
        return known[expr]

    def bounds(self, expr: sympy.Basic) -> tuple[float, float] | None:
        """The ends of the enclosure of ``expr`` as floats (beyond double: +-inf), or ``None``."""
        value = self.enclosure(expr)
        if value is None:
            return None
        low, high = self._ends(value)
        return float(low), float(high)

    # -- one node from the enclosures of its arguments ----------------------------------

    def _evaluate(self, node: sympy.Basic, values: Sequence[object]):
        if node is sympy.I:
            raise _OutsideDomain
        if any(node is special for special in _NON_FINITE):
            raise NotRealError(node, "is infinite or undefined")
        if node.is_Rational:
            return self.iv.mpf(node.p) / self.iv.mpf(node.q)
        if node.is_Float:
            return self.iv.mpf(self.mp.make_mpf(node._mpf_))
        if node is sympy.pi:
            return self.iv.pi
        if node is sympy.E:
            return self.iv.e
        if not values or any(value is None for value in values):
            return None  # a symbol, an unknown atom, or an argument that is not constant
        if node.is_Add:
            return _fold(values, lambda a, b: a + b)
        if node.is_Mul:
            return _fold(values, lambda a, b: a * b)
        if node.is_Pow:
            return self._power(node.exp, *values)
        function = self.functions.get(type(node))
        return None if function is None else function(*values)

    def _power(self, exact_exponent: sympy.Expr, base, exponent):
        if exact_exponent.is_Integer:
            return base ** int(exact_exponent)
        low, high = self._ends(base)
        if low > 0:
            return self._exp(exponent * self.iv.log(base))
        if high < 0 and (exact_exponent.is_Rational or self._holds_no_integer(exponent)):
            raise _OutsideDomain
        return None  # a base that may be zero, or an exponent that may be an integer

    def _exp(self, x):
        return None if self._moderate(x) is None else self.iv.exp(x)

    def _log(self, x):
        low, high = self._ends(x)
        if low > 0:
            return self.iv.log(x)
        if high < 0:
            raise _OutsideDomain
        return None

    def _unit(self, x):
        """``x`` when it lies in [-1, 1] (the domain of asin, acos); refused when wholly outside."""
        if x is None:
            return None
        low, high = self._ends(x)
        if low > 1 or high < -1:
            raise _OutsideDomain
        return x if low >= -1 and high <= 1 else None

    def _moderate(self, x):
        """``x`` when ``exp`` of it is cheap to enclose, else ``None`` (left unknown)."""
        if x is None:
            return None
        low, high = self._ends(x)
        return x if max(abs(low), abs(high)) <= EXP_ARGUMENT_LIMIT else None

    def _monotone(self, x, function):
        """``function`` (monotone) at both ends, widened outward past its rounding."""
        if x is None:
            return None
        mp = self.mp
        ends = sorted(function(end) for end in self._ends(x))
        slack = [abs(end) * mp.ldexp(1, -PRECISION_BITS) for end in ends]
        return self.iv.mpf([ends[0] - slack[0], ends[1] + slack[1]])

    def _abs(self, x):
        low, high = self._ends(x)
        if low >= 0:
            return x
        if high <= 0:
            return -x
        return self.iv.mpf([0, max(-low, high)])

    def _sign(self, x):
        low, high = self._ends(x)
        return self.iv.mpf(1 if low > 0 else -1 if high < 0 else [-1, 1])

    def _atan2(self, y, x):
        """Real for real arguments: within [-pi, pi] (only (0, 0), SymPy's nan, is undefined)."""
        if 0 in self.iv.mpf(self._ends(y)) and 0 in self.iv.mpf(self._ends(x)):
            return None
        return self.iv.mpf([-4, 4])

    def _ends(self, x):
        """The two endpoints of an interval, as exact multiprecision numbers."""
        return tuple(self.mp.make_mpf(end) for end in x._mpi_)

    def _finite(self, x) -> bool:
        return all(self.mp.isfinite(end) for end in self._ends(x))

    def _holds_no_integer(self, x) -> bool:
        low, high = self._ends(x)
        return self.mp.floor(low) == self.mp.floor(high) and self.mp.floor(low) != low


@functools.cache
def _contexts() -> tuple[MPIntervalContext, MPContext]:
    """mpmath's interval and number contexts at our precision: made once (half a
    millisecond each), never changed after, so every checker shares them."""
    iv = MPIntervalContext()
    iv.prec = PRECISION_BITS
    mp = MPContext()
    mp.prec = PRECISION_BITS + 10
    return iv, mp


def _fold(values: Sequence[object], combine: Callable[[object, object], object]):
    result = values[0]
    for value in values[1:]:
        result = combine(result, value)
    return result

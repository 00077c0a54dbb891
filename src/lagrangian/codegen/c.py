"""C99 text shared by every C target: one printer, one linear solve, one sin/cos fusion.

- :class:`CPrinter`: SymPy's C99 printer in double (``float64``) or single
  (``float32``) precision.  Single precision has ``F``-suffixed literals and
  ``sinf``-style calls, so nothing is silently promoted to double.  Floats are the
  shortest text that reads back as the same double
  (:class:`~lagrangian.codegen.literals.FloatLiterals`); pi and e are numbers and
  there are no math macros (``M_PI``, ``M_SQRT2``... are POSIX, not C99, and NVRTC
  has none); small integer powers are products (exact, and faster than ``pow``).
- :func:`gaussian_elimination`: the C text of the one linear solve
  (:func:`lagrangian.codegen.steps.elimination`, Gaussian elimination with partial
  pivoting for one compile-time size: the exported ``rhs`` and the CUDA kernel's steps).
- :func:`fuse_sine_cosine`: ``sincos`` where both the sine and the cosine of one
  argument are used (a GNU and CUDA function, not C99: the CUDA kernel uses it).
"""

from __future__ import annotations

import math

import sympy
from sympy.codegen.ast import float32, real
from sympy.printing.c import C99CodePrinter
from sympy.printing.precedence import PRECEDENCE

from .literals import FloatLiterals
from .steps import CStepPrinter, elimination

PRECISIONS = ("float64", "float32")


class CPrinter(FloatLiterals, C99CodePrinter):
    """C99 in one precision (see the module docstring)."""

    def __init__(self, precision: str = "float64"):
        if precision not in PRECISIONS:
            raise ValueError(f"unknown precision {precision!r} (precisions: {PRECISIONS})")
        self.precision = precision
        settings: dict[str, object] = {"strict": True, "math_macros": {}}
        if precision == "float32":
            settings["type_aliases"] = {real: float32}
        super().__init__(settings)
        #: the type of a real number, the literal suffix and the absolute value function
        self.real = "float" if precision == "float32" else "double"
        self.suffix = self._get_literal_suffix(real)
        self.fabs = "fabsf" if precision == "float32" else "fabs"

    def literal(self, value: float) -> str:
        """A Python float as a literal of this precision."""
        return self._print_Float(sympy.Float(value))

    def _print_Float(self, expr) -> str:
        text = super()._print_Float(expr)  # repr, or +-infinity
        return text + self.suffix if text[-1].isdigit() else text

    def _print_Pi(self, expr) -> str:
        return self.literal(math.pi)

    def _print_Exp1(self, expr) -> str:
        return self.literal(math.e)

    def _print_Pow(self, expr):
        base, exponent = expr.args
        if exponent.is_Integer and 2 <= abs(int(exponent)) <= 8:
            factor = self.parenthesize(base, PRECEDENCE["Mul"])
            product = "*".join([factor] * abs(int(exponent)))
            return f"({product})" if exponent > 0 else f"(1/({product}))"
        if exponent == sympy.Rational(-1, 2):
            return f"(1/{self._print(sympy.sqrt(base))})"
        return super()._print_Pow(expr)

    def _print_Infinity(self, expr):
        # a coefficient beyond double range (machine_numbers); INFINITY needs <math.h>
        return f"(1.0{self.suffix}/0.0{self.suffix})"

    def _print_NegativeInfinity(self, expr):
        return f"(-{self._print_Infinity(expr)})"

    def _print_Integer(self, expr):
        # beyond int range C would need a long literal; a real one is what we mean
        if abs(int(expr)) >= 2**31:
            return self._print(sympy.Float(expr, 17))
        return super()._print_Integer(expr)


def gaussian_elimination(
    name: str,
    size: int,
    printer: CPrinter,
    *,
    qualifiers: str = "static",
    unroll: bool = False,
    real_type: str | None = None,
) -> str:
    """The C function ``int name(real *a, real *b, real *x, int offset)``: x[offset:] with
    a x = b, printed from :func:`lagrangian.codegen.steps.elimination` (its contract).

    ``size`` is the number of unknowns; ``real_type`` names the type of the entries (the
    printer's ``float`` or ``double`` by default); with ``unroll`` the loops carry
    ``#pragma unroll``.
    """
    steps = CStepPrinter(size, printer, real_type or printer.real, unroll=unroll)
    comment = (
        "/* x with a x = b by Gaussian elimination with partial pivoting (a, b overwritten; x "
        "may\n   be b). Returns 0, or 1 where a pivot is 0 or not finite (a singular). */"
    )
    return comment + "\n" + steps.function(elimination(size, name), qualifiers)


def fuse_sine_cosine(replacements, reduced):
    """Statements [(symbol | (sine, cosine), value)] with sin(a) and cos(a) made by one call.

    ``replacements`` and ``reduced`` are :func:`sympy.cse`'s.  Where both the sine and
    the cosine of one argument are used, sincos(a) computes them together (one range
    reduction instead of two; on the GPU, where float64 arithmetic is the bound, that
    is a tenth of a double pendulum's RK4 stage).  The call goes right after the last
    statement its argument needs.
    """
    values = [value for _, value in replacements] + list(reduced)
    sines, cosines = set(), set()
    for value in values:
        sines |= {f.args[0] for f in value.atoms(sympy.sin)}
        cosines |= {f.args[0] for f in value.atoms(sympy.cos)}
    shared = sorted(sines & cosines, key=sympy.default_sort_key)
    if not shared:
        return list(replacements), list(reduced)
    defined_at = {symbol: index for index, (symbol, _) in enumerate(replacements)}
    calls: dict[int, list] = {}
    substitute = {}
    for k, argument in enumerate(shared):
        sine, cosine = sympy.Symbol(f"_sin{k}"), sympy.Symbol(f"_cos{k}")
        after = max((defined_at.get(s, -1) for s in argument.free_symbols), default=-1)
        calls.setdefault(after, []).append(((sine, cosine), argument))
        substitute[sympy.sin(argument)] = sine
        substitute[sympy.cos(argument)] = cosine
    statements = list(calls.get(-1, []))
    for index, (symbol, value) in enumerate(replacements):
        statements.append((symbol, value.xreplace(substitute)))
        statements.extend(calls.get(index, []))
    return statements, [value.xreplace(substitute) for value in reduced]

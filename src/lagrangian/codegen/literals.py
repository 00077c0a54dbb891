"""Numbers in generated code: what a double can hold, written so that it reads back exactly.

Every code generator (the numba kernels, the CUDA kernel, the exported C, Julia,
MATLAB and NumPy files) prints SymPy's exact numbers and floats into source text.
Two things go wrong when they are printed as SymPy writes them:

* an exact integer of 2**63 or more is an invalid C literal (or, in -Werror
  builds, a compile error), an Int128 or BigInt in Julia (a BigFloat result),
  and too large for numba's typing: :func:`machine_numbers` turns every exact
  number that a double cannot hold exactly (beyond 2**53, or a fraction with
  such a part) into the nearest double, and one beyond double range into
  +-infinity, which is what the double arithmetic of the generated code would
  give it anyway;
* SymPy prints a float with 15 significant digits, which does not read back as
  the same double: :class:`FloatLiterals` prints ``repr(float)``, the shortest
  text that does (17 significant digits at most).
"""

from __future__ import annotations

import math

import sympy

#: Integers of this size and beyond are not all exact in a double (53-bit significand).
EXACT_LIMIT = 2**53


def machine_numbers(expr: sympy.Basic) -> sympy.Basic:
    """``expr`` with every exact number that a double cannot hold exactly made a float."""
    replace = {}
    for number in expr.atoms(sympy.Rational):
        if abs(number.p) >= EXACT_LIMIT or number.q >= EXACT_LIMIT:
            replace[number] = _nearest_double(number)
    return expr.xreplace(replace) if replace else expr


def _nearest_double(number: sympy.Rational) -> sympy.Expr:
    try:
        value = number.p / number.q  # int / int: correctly rounded
    except OverflowError:
        return sympy.oo if number > 0 else -sympy.oo
    return sympy.Float(value, 17)


class FloatLiterals:
    """Printer mixin: a float as the shortest text that reads back as the same double.

    Mix in before the SymPy printer class: ``class P(FloatLiterals, C99CodePrinter)``.
    """

    def _print_Float(self, expr) -> str:
        value = float(expr)
        if math.isfinite(value):
            return repr(value)
        return self._print(sympy.oo if value > 0 else -sympy.oo)

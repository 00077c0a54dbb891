"""Printing large expressions in linear time, from their SymEngine form.

SymPy's printers sort the terms and factors of every sum and product
(``as_ordered_terms`` asks each term for its real and imaginary parts), which costs
seconds for the equations of a 20-link chain and hours for 100 links.  Systems that
were derived on the SymEngine route (``FAST_MIN_COORDINATES`` coordinates or more)
are printed here instead: each expression is converted to SymEngine once (shared
subexpressions once per document) and written out by a walk over its tree:

- :func:`plain_printer`: SymEngine's ``str``, the same language as SymPy's ``str()``
  (``x**2``, ``sin(x)``, ``(1/2)*m``, ``x**(-1)``), read back by ``sympy.parse_expr``
  with the model's names (DESIGN section 5);
- :func:`unicode_printer` and :func:`latex_printer`: the notation of
  :mod:`lagrangian.output.notation` (dots over velocities, sin²θ, juxtaposed
  products, accelerations first in a sum) without SymPy's ordering of the rest.

The walks are in :mod:`lagrangian.output.large_walks`.  Smaller systems keep SymPy's
printers for expressions up to ``PLAIN_MAX_NODES`` nodes, and so do expressions SymEngine
cannot hold (declared functions and their derivatives, floating-point numbers).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import sympy

from ..algebra import FAST_MIN_COORDINATES, to_symengine

Printer = Callable[[sympy.Expr], str]  # also takes the SymEngine forms of Printed


def is_large(system) -> bool:
    """Whether ``system`` is printed from its SymEngine form (the derivation's route)."""
    return system is not None and len(system.coordinates) >= FAST_MIN_COORDINATES


#: Above this many nodes an expression of a small system is also written by SymEngine
#: (the solved q'' of a 4-link chain: SymPy's ``str`` takes a second per entry).
PLAIN_MAX_NODES = 1000


@dataclass(frozen=True)
class Printed:
    """What a document prints: SymPy expressions, or for a large system derived on the
    SymEngine route the same expressions in its SymEngine form (no conversion back)."""

    lagrangian: object
    equations: Sequence
    mass_matrix: Sequence[Sequence]
    forcing: Sequence


def printed(eom) -> Printed:
    """L, the equations, M (rows) and f of ``eom`` in the form to print."""
    forms = eom.symengine
    if forms is not None and is_large(eom.system):
        return Printed(forms.lagrangian, forms.equations, forms.mass_matrix, forms.forcing)
    n = len(eom.coordinates)
    matrix = [[eom.mass_matrix[i, j] for j in range(n)] for i in range(n)]
    forcing = [eom.forcing[i, 0] for i in range(n)]
    return Printed(eom.system.lagrangian, eom.equations, matrix, forcing)


def plain_printer(system) -> Printer:
    """SymPy ``str()`` text; SymEngine's ``str`` of the same expression where it is large."""
    large = is_large(system)
    cache: dict = {}
    written: dict = {}  # SymEngine form -> its text: M's lower triangle is the upper's entries

    def show(expr: sympy.Expr) -> str:
        if not isinstance(expr, sympy.Basic):  # a SymEngine form (see printed)
            text = written.get(expr)
            if text is None:
                text = written[expr] = symengine_text(expr, written)
            return text
        if large or _longer_than_plain(expr):
            converted = to_symengine(expr, cache)
            if converted is not None:
                return str(converted)
        return str(expr)

    return show


def symengine_text(expr, written: dict) -> str:
    """SymEngine's ``str`` of ``expr``, where a sum holds a multiple of a sum whose text is
    in ``written`` (an equation's ``-(f)`` beside the forcing f) with that text put in
    instead of printed again (SymEngine's printer writes about 17 MB/s).

    SymEngine's printer writes a sum's terms ordered by their sums, products, powers, ...
    without their coefficients: first by the kind of node, then, within a kind, by
    comparing the nodes.  Where the written sum is the only sum among them, a placeholder
    sum of two names no model can spell takes its place in that order, and its text in
    parentheses is the written text's place."""
    import symengine as se

    if type(expr) is not se.Add:
        return str(expr)
    terms = expr.args
    held = None
    for k, term in enumerate(terms):
        kind = type(term)
        if kind is se.Add:
            return str(expr)  # a sum as a term of its own (coefficient 1)
        if kind is se.Mul:
            factors = term.args
            if len(factors) == 2 and type(factors[1]) is se.Add and factors[0].is_Number:
                if held is not None:
                    return str(expr)  # two sums: their order is compared, not by kind
                held = k
    if held is None:
        return str(expr)
    coefficient, inner = terms[held].args
    text = written.get(inner)
    if text is None:
        return str(expr)
    placeholder = se.Symbol("\0written") + se.Symbol("\0sum")
    shown = str(se.Add(*terms[:held], *terms[held + 1 :], coefficient * placeholder))
    mark = f"({placeholder})"
    if shown.count(mark) != 1:
        return str(expr)
    return shown.replace(mark, f"({text})")


def unicode_printer(system) -> Printer:
    """One line of Unicode notation per expression (see :class:`UnicodePrinter`)."""
    from .large_walks import UnicodeWalk
    from .notation import UnicodePrinter, declared_functions

    fallback = UnicodePrinter(declared_functions(system)).doprint
    return _walking(system, UnicodeWalk(), fallback)


def latex_printer(system) -> Printer:
    """LaTeX of each expression (see :class:`DotLatexPrinter`)."""
    from .large_walks import LatexWalk
    from .notation import DotLatexPrinter, declared_functions

    fallback = DotLatexPrinter(declared_functions(system)).doprint
    return _walking(system, LatexWalk(), fallback)


def _longer_than_plain(expr: sympy.Expr) -> bool:
    """Whether a SymPy expression is printed from its SymEngine form however small its system
    (the notation module is imported only where SymPy expressions are printed)."""
    from .notation import longer_than

    return longer_than(expr, PLAIN_MAX_NODES)


def _walking(system, walk, fallback: Printer) -> Printer:
    large = is_large(system)
    cache: dict = {}

    def show(expr: sympy.Expr) -> str:
        if not isinstance(expr, sympy.Basic):
            return walk.text(expr)  # a SymEngine form (see printed)
        if not (large or _longer_than_plain(expr)):
            return fallback(expr)
        converted = to_symengine(expr, cache)
        return fallback(expr) if converted is None else walk.text(converted)

    return show

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

Smaller systems keep SymPy's printers for expressions up to ``PLAIN_MAX_NODES``
nodes, and so do expressions SymEngine cannot hold (declared functions and their
derivatives, floating-point numbers).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import sympy

from ..algebra import FAST_MIN_COORDINATES, to_symengine
from .notation import (
    SUPERSCRIPT,
    DotLatexPrinter,
    UnicodePrinter,
    _split_dots,
    declared_functions,
    latex_name,
    longer_than,
    unicode_name,
)

Printer = Callable[[sympy.Expr], str]  # also takes the SymEngine forms of Printed

ADD, MUL, POW, ATOM = 1, 2, 3, 4  # binding strength of what a walk returns


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
                text = written[expr] = str(expr)
            return text
        if large or longer_than(expr, PLAIN_MAX_NODES):
            converted = to_symengine(expr, cache)
            if converted is not None:
                return str(converted)
        return str(expr)

    return show


def unicode_printer(system) -> Printer:
    """One line of Unicode notation per expression (see :class:`UnicodePrinter`)."""
    fallback = UnicodePrinter(declared_functions(system)).doprint
    return _walking(system, _UnicodeWalk(), fallback)


def latex_printer(system) -> Printer:
    """LaTeX of each expression (see :class:`DotLatexPrinter`)."""
    fallback = DotLatexPrinter(declared_functions(system)).doprint
    return _walking(system, _LatexWalk(), fallback)


def _walking(system, walk: _Walk, fallback: Printer) -> Printer:
    large = is_large(system)
    cache: dict = {}

    def show(expr: sympy.Expr) -> str:
        if not isinstance(expr, sympy.Basic):
            return walk.text(expr)  # a SymEngine form (see printed)
        if not (large or longer_than(expr, PLAIN_MAX_NODES)):
            return fallback(expr)
        converted = to_symengine(expr, cache)
        return fallback(expr) if converted is None else walk.text(converted)

    return show


class _Walk:
    """Text of a SymEngine tree: one visit per distinct node (results are kept)."""

    def __init__(self):
        import symengine as se

        self.se = se
        self._done: dict = {}
        self._names: dict = {}
        self._ranks: dict = {}

    def text(self, node) -> str:
        return self.visit(node)[0]

    def visit(self, node) -> tuple[str, int]:
        found = self._done.get(node)
        if found is None:
            found = self._done[node] = self._visit(node)
        return found

    def wrapped(self, node, strength: int) -> str:
        text, own = self.visit(node)
        return self.parenthesized(text) if own < strength else text

    def _visit(self, node) -> tuple[str, int]:
        se = self.se
        kind = type(node)
        if kind is se.Symbol:
            return self.symbol(node.name), ATOM
        if kind is se.Add:
            return self.add(node)
        if kind is se.Mul:
            return self.mul(node)
        if kind is se.Pow:
            base, exponent = node.args
            if exponent.is_Number and exponent < 0:
                return self.mul(node)  # 1/x: a product with a denominator
            return self.power(base, exponent)
        if node.is_Number:
            text = str(node)
            negative = node < 0
            if kind is se.Rational or "/" in text:
                return self.rational(node), ADD if negative else MUL
            return text, ADD if negative else ATOM
        if not node.args:
            return self.constant(node), ATOM
        return self.function(type(node).__name__, node.args), ATOM

    def rank(self, node) -> int:
        """2 for an expression with an acceleration, 1 with a velocity, 0 otherwise
        (each distinct subexpression looked at once)."""
        found = self._ranks.get(node)
        if found is None:
            if type(node) is self.se.Symbol:
                found = _split_dots(node.name)[1]
            else:
                found = max((self.rank(arg) for arg in node.args), default=0)
            self._ranks[node] = found
        return found

    def add(self, node) -> tuple[str, int]:
        """Accelerations first, then velocities, then the rest; alphabetical within each."""
        terms = []
        for term in node.args:
            negative = _coefficient(term) < 0
            text = self.wrapped(-term if negative else term, MUL)
            terms.append((-self.rank(term), text, negative))
        terms.sort()
        parts = []
        for _, text, negative in terms:
            if parts:
                parts.append((" - " if negative else " + ") + text)
            else:
                parts.append(("-" if negative else "") + text)
        return "".join(parts), ADD

    def ordered(self, factors: list) -> list[str]:
        """Numbers, parameters, then the rest; velocities and accelerations last."""
        keyed = []
        for factor in factors:
            if isinstance(factor, int):
                keyed.append((0, 0, str(factor)))
                continue
            text = self.wrapped(factor, MUL)
            symbol = factor.args[0] if type(factor) is self.se.Pow else factor
            kind = 0 if factor.is_Number else 1 if type(symbol) is self.se.Symbol else 2
            keyed.append((self.rank(factor), kind, text))
        keyed.sort()
        return [text for *_, text in keyed]

    def factors(self, factors: list) -> str:
        return " ".join(self.ordered(factors))

    def mul(self, node) -> tuple[str, int]:
        se = self.se
        coefficient = _coefficient(node)
        negative = coefficient < 0
        magnitude = -coefficient if negative else coefficient
        top, bottom = [], []
        if magnitude != 1:
            numerator, denominator = _fraction(magnitude)
            if numerator != 1:
                top.append(numerator)
            if denominator != 1:
                bottom.append(denominator)
        for factor in se.Mul.make_args(node) if type(node) is se.Mul else (node,):
            if factor.is_Number:
                continue
            if type(factor) is se.Pow and factor.args[1].is_Number and factor.args[1] < 0:
                base, exponent = factor.args
                bottom.append(base if exponent == -1 else base ** (-exponent))
            else:
                top.append(factor)
        text = self.product(top, bottom)
        return ("-" + text if negative else text), ADD if negative else MUL

    def function_name(self, name: str) -> str:
        return {"Abs": "abs"}.get(name, name)


class _UnicodeWalk(_Walk):
    """Unicode as :class:`~lagrangian.output.notation.UnicodePrinter` writes it."""

    def symbol(self, name: str) -> str:
        found = self._names.get(name)
        if found is None:
            found = self._names[name] = unicode_name(name)
        return found

    def parenthesized(self, text: str) -> str:
        return f"({text})"

    def rational(self, number) -> str:
        return str(number)

    def constant(self, node) -> str:
        return {"pi": "π", "E": "e"}.get(str(node), str(node))

    def product(self, top: list, bottom: list) -> str:
        numerator = self.factors(top) if top else "1"
        if not bottom:
            return numerator
        if len(bottom) == 1 and not isinstance(bottom[0], int):
            denominator = self.wrapped(bottom[0], POW)
        else:
            denominator = self.factors(bottom)
            denominator = denominator if len(bottom) == 1 else f"({denominator})"
        return f"{numerator}/{denominator}"

    def power(self, base, exponent) -> tuple[str, int]:
        se = self.se
        if base == se.E:
            return f"exp({self.text(exponent)})", ATOM
        if exponent == se.Rational(1, 2):
            return f"√{self.wrapped(base, ATOM)}", POW
        if exponent.is_Integer and exponent > 1:
            sup = str(exponent).translate(SUPERSCRIPT)
            if base.args and type(base) not in (se.Add, se.Mul, se.Pow) and len(base.args) == 1:
                name = type(base).__name__
                if name != "Abs":
                    return f"{name}{sup}({self.text(base.args[0])})", ATOM  # sin²(θ)
            return f"{self.wrapped(base, ATOM)}{sup}", POW
        return f"{self.wrapped(base, ATOM)}^{self.wrapped(exponent, ATOM)}", POW

    def function(self, name: str, args) -> str:
        if name == "Abs":
            return f"|{self.text(args[0])}|"
        return f"{name}({', '.join(self.text(a) for a in args)})"


class _LatexWalk(_Walk):
    """LaTeX as :class:`~lagrangian.output.notation.DotLatexPrinter` writes it."""

    FUNCTIONS = frozenset(("sin", "cos", "tan", "exp", "log", "sinh", "cosh", "tanh"))

    def symbol(self, name: str) -> str:
        found = self._names.get(name)
        if found is None:
            found = self._names[name] = latex_name(name)
        return found

    def parenthesized(self, text: str) -> str:
        return rf"\left({text}\right)"

    def rational(self, number) -> str:
        numerator, denominator = _fraction(abs(number))
        sign = "-" if number < 0 else ""
        return rf"{sign}\frac{{{numerator}}}{{{denominator}}}"

    def constant(self, node) -> str:
        return {"pi": r"\pi", "E": "e"}.get(str(node), str(node))

    def product(self, top: list, bottom: list) -> str:
        numerator = self.factors(top) if top else "1"
        if not bottom:
            return numerator
        return rf"\frac{{{numerator}}}{{{self.factors(bottom)}}}"

    def power(self, base, exponent) -> tuple[str, int]:
        se = self.se
        if base == se.E:
            return f"e^{{{self.text(exponent)}}}", POW
        if exponent == se.Rational(1, 2):
            return rf"\sqrt{{{self.text(base)}}}", ATOM
        shown = self.text(exponent)
        if exponent.is_Integer and len(base.args) == 1 and type(base).__name__ in self.FUNCTIONS:
            name = type(base).__name__
            return rf"\{name}^{{{shown}}}{{\left({self.text(base.args[0])} \right)}}", ATOM
        return f"{self.wrapped(base, ATOM)}^{{{shown}}}", POW

    def function(self, name: str, args) -> str:
        inner = ", ".join(self.text(a) for a in args)
        if name == "Abs":
            return rf"\left|{{{inner}}}\right|"
        command = rf"\{name}" if name in self.FUNCTIONS else rf"\operatorname{{{name}}}"
        return rf"{command}{{\left({inner} \right)}}"


def _coefficient(node):
    """The numeric factor of a term (1 where there is none)."""
    if node.is_Number:
        return node
    if type(node).__name__ == "Mul" and node.args[0].is_Number:
        return node.args[0]
    return 1


def _fraction(number) -> tuple:
    """(numerator, denominator) of a positive SymEngine number as Python ints, or (x, 1)."""
    text = str(number)
    if "/" in text:
        top, bottom = text.split("/")
        return int(top), int(bottom)
    return (int(text) if text.isdigit() else number), 1

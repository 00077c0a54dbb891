"""Textbook notation for printing: dots over velocities, Greek letters, sin²θ.

Two printers share one rule set:
- :class:`UnicodePrinter`, one line of Unicode text (``r̈ = ω² r``) for terminals;
- :class:`DotLatexPrinter`, LaTeX with ``\\dot{\\theta}`` and partial derivatives
  of declared functions written as ``\\frac{\\partial A}{\\partial x}``.
A declared function applied to its declared arguments, A(x, y, z), prints as A.
"""

from __future__ import annotations

import functools
import unicodedata
from collections.abc import Callable, Iterable

import sympy
from sympy.core.function import AppliedUndef
from sympy.printing.latex import LatexPrinter, greek_letters_set
from sympy.printing.pretty.pretty_symbology import pretty_symbol
from sympy.printing.str import StrPrinter

from ..symbols import ACCELERATION_SUFFIX, VELOCITY_SUFFIX

SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")
COMBINING_DOT = "\u0307"
COMBINING_DIAERESIS = "\u0308"


def _split_dots(name: str) -> tuple[str, int]:
    """('theta', 1) for 'theta_dot', ('x', 2) for 'x_ddot', (name, 0) otherwise."""
    if name.endswith(ACCELERATION_SUFFIX) and len(name) > len(ACCELERATION_SUFFIX):
        return name[: -len(ACCELERATION_SUFFIX)], 2
    if name.endswith(VELOCITY_SUFFIX) and len(name) > len(VELOCITY_SUFFIX):
        return name[: -len(VELOCITY_SUFFIX)], 1
    return name, 0


def unicode_name(name: str) -> str:
    """θ̇₁ for 'theta1_dot': the pretty symbol with a combining dot on its head."""
    base, dots = _split_dots(name)
    head, _, tail = base.partition("_")
    if len(tail) > 1 and not tail.isdigit():
        # p_theta: a word as subscript reads better as p_θ than as p with tiny letters
        shown = f"{pretty_symbol(head)}_{pretty_symbol(tail)}"
    else:
        shown = pretty_symbol(base)
    if dots == 0:
        return shown
    head = len(shown)
    while head > 1 and not shown[head - 1].isalpha():
        head -= 1  # subscripts and primes stay after the dot
    mark = COMBINING_DOT if dots == 1 else COMBINING_DIAERESIS
    return unicodedata.normalize("NFC", shown[:head] + mark + shown[head:])  # ẋ, not x + dot


@functools.lru_cache(maxsize=4096)  # a page names each symbol hundreds of times
def latex_name(name: str) -> str:
    """\\dot{\\theta}_{1} for 'theta1_dot'; a name that begins with a word (three
    letters or more, not a Greek letter) upright as it is written:
    \\mathrm{mechanical\\_energy} (SymPy's rule read 'mechanical' as a calligraphic
    'mechani' and the rest as a subscript)."""
    base, dots = _split_dots(name)
    shown = _word(base) or _subscripted(base) or sympy.latex(sympy.Symbol(base))
    if dots == 0:
        return shown
    command = r"\dot" if dots == 1 else r"\ddot"
    head, sep, subscript = shown.partition("_")
    return f"{command}{{{head}}}{sep}{subscript}"


def _word(base: str) -> str | None:
    """``\\mathrm{...}`` of a name whose first part is a word, else None (SymPy's rule)."""
    head = base.partition("_")[0].rstrip("0123456789")
    if len(head) < 3 or not head.isalpha() or head.lower() in _GREEK:
        return None
    return r"\mathrm{" + base.replace("_", r"\_") + "}"


def _subscripted(base: str) -> str | None:
    """``p_{\\theta_{2}}`` for 'p_theta2': a subscript that is a name is typeset as that
    name (the momentum of theta2; SymPy's rule wrote p_{theta2}), else None."""
    head, sep, tail = base.partition("_")
    if not (sep and head and tail.isalnum()) or tail.isdigit():
        return None
    return f"{sympy.latex(sympy.Symbol(head))}_{{{sympy.latex(sympy.Symbol(tail))}}}"


_GREEK = frozenset({*greek_letters_set, "lamda", "lambda"})


def _dot_rank(term: sympy.Expr) -> int:
    """2 for a term with an acceleration, 1 with a velocity, 0 otherwise."""
    return max((_split_dots(s.name)[1] for s in term.free_symbols if s.is_Symbol), default=0)


class _TextbookOrder:
    """Sums print as a textbook writes them: accelerations, then velocities, then the rest."""

    def _as_ordered_terms(self, expr, order=None):
        terms = super()._as_ordered_terms(expr, order=order)
        return sorted(terms, key=lambda term: -_dot_rank(term))


class UnicodePrinter(_TextbookOrder, StrPrinter):
    """One-line Unicode text: juxtaposition for products, superscripts for small powers."""

    def __init__(self, declared: Iterable[sympy.Expr] = ()):
        super().__init__({"order": None})
        self._declared = frozenset(declared)

    def _print_Symbol(self, expr):
        return unicode_name(expr.name)

    def _print_Pi(self, expr):
        return "π"

    def _print_Exp1(self, expr):
        return "e"

    def _print_Abs(self, expr):
        return f"|{self._print(expr.args[0])}|"

    def _print_Function(self, expr):
        if isinstance(expr, AppliedUndef) and expr in self._declared:
            return expr.func.__name__
        return super()._print_Function(expr)

    def _print_Derivative(self, expr):
        function = expr.expr
        if isinstance(function, AppliedUndef) and function in self._declared:
            order = sum(count for _, count in expr.variable_count)
            top = "∂" + (str(order).translate(SUPERSCRIPT) if order > 1 else "")
            bottom = "".join(
                "∂" + self._print(v) + (str(c).translate(SUPERSCRIPT) if c > 1 else "")
                for v, c in expr.variable_count
            )
            return f"{top}{function.func.__name__}/{bottom}"
        return super()._print_Derivative(expr)

    def _print_Pow(self, expr, rational=False):
        base, exponent = expr.args
        if exponent == sympy.Rational(1, 2):
            return f"√{self._atom(base)}"
        if exponent.is_Integer and exponent > 1:
            sup = str(exponent).translate(SUPERSCRIPT)
            if (
                isinstance(base, sympy.Function)
                and len(base.args) == 1
                and not isinstance(base, AppliedUndef)
            ):
                return f"{base.func.__name__}{sup}{self._atom(base.args[0])}"  # sin²(θ)
            return f"{self._atom(base)}{sup}"
        return super()._print_Pow(expr, rational).replace("**", "^")

    def _print_Mul(self, expr):
        return super()._print_Mul(expr).replace("*", " ")

    def _atom(self, expr) -> str:
        text = self._print(expr)
        if expr.is_Atom or isinstance(expr, sympy.Function | sympy.Derivative):
            return text if expr.is_Atom or text[-1] == ")" else f"({text})"
        return f"({text})"


class DotLatexPrinter(_TextbookOrder, LatexPrinter):
    """LaTeX with dot notation and compact partial derivatives of declared functions."""

    def __init__(self, declared: Iterable[sympy.Expr] = ()):
        super().__init__()
        self._declared = frozenset(declared)

    def _print_Symbol(self, expr, style="plain"):
        return latex_name(expr.name)

    def _print_Function(self, expr, exp=None):
        if isinstance(expr, AppliedUndef) and expr in self._declared:
            name = expr.func.__name__
            return f"{name}^{{{exp}}}" if exp else name
        return super()._print_Function(expr, exp)

    def _print_Derivative(self, expr):
        function = expr.expr
        if isinstance(function, AppliedUndef) and function in self._declared:
            order = sum(count for _, count in expr.variable_count)
            top = r"\partial" + (f"^{{{order}}}" if order > 1 else "")
            bottom = " ".join(
                r"\partial " + self._print(v) + (f"^{{{c}}}" if c > 1 else "")
                for v, c in expr.variable_count
            )
            return rf"\frac{{{top} {function.func.__name__}}}{{{bottom}}}"
        return super()._print_Derivative(expr)


def declared_functions(system) -> frozenset:
    """The applied forms A(x, y, z) of a system's declared functions (printed as A)."""
    if system is None:
        return frozenset()
    return frozenset(f.applied for f in system.functions)


#: Solved accelerations and multipliers longer than this (nodes of the expression tree)
#: are not printed as text or LaTeX: the closed-form q'' of a 6-link chain runs to
#: 200,000 operations (megabytes of text, minutes of printing); ``derive --json`` keeps them.
PRINT_MAX_NODES = 5000
TOO_LONG = f"too long to print (more than {PRINT_MAX_NODES:,} nodes); derive --json gives it"


def too_long_to_print(expr: sympy.Expr) -> bool:
    """Whether ``expr`` has more than ``PRINT_MAX_NODES`` nodes (stops counting there)."""
    return longer_than(expr, PRINT_MAX_NODES)


def equality(
    lhs: str, rhs: sympy.Expr, show: Callable[[sympy.Expr], str], *, equals=" = ", named=": {}"
) -> str:
    """``lhs = rhs``, the right side printed by ``show``; a closed form too long to read is
    named, not printed (``named`` formats the note)."""
    if too_long_to_print(rhs):
        return lhs + named.format(TOO_LONG)
    return lhs + equals + show(rhs)


def longer_than(expr: sympy.Expr, limit: int) -> bool:
    """Whether the tree of ``expr`` has more than ``limit`` nodes, repeats counted.

    Each distinct subexpression is sized once (the solved q'' of a chain repeats the
    same sums hundreds of times), and the count stops once past ``limit``.
    """
    sizes: dict = {}

    def size(node) -> int:
        found = sizes.get(node)
        if found is None:
            found = 1
            for arg in node.args:
                found += size(arg)
                if found > limit:
                    break
            sizes[node] = found
        return found

    return size(expr) > limit


def step_terms(step) -> list[tuple[str, sympy.Expr]]:
    """The terms of one coordinate's Lagrange equation in the order a derivation by hand
    shows them, each (what, expression): ``momentum``, ``momentum_rate``,
    ``force_gradient``, then those that are not zero of ``generalized_force``,
    ``dissipation_force`` and ``constraint_force``, and the ``equation``."""
    terms = [
        ("momentum", step.momentum),
        ("momentum_rate", step.momentum_rate),
        ("force_gradient", step.force_gradient),
    ]
    optional = ("generalized_force", "dissipation_force", "constraint_force")
    terms += [(what, getattr(step, what)) for what in optional if getattr(step, what) != 0]
    terms.append(("equation", step.equation))
    return terms

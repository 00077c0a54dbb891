"""The equilibria and normal modes of a page: in view, and as numbers that follow the sliders.

Each equilibrium is one block of the page's document (``{"equilibrium": {...}}``): the
point and its verdict first, then a table the page fills with ω², ω and the period of
each mode and the mode shapes at the parameter values of the moment, then the symbolic
forms.  The symbolic forms are written to break across lines (:func:`breakable_latex`,
typeset by KaTeX in inline mode, which breaks after a top-level ``+``, ``-`` or ``=``):
for the double pendulum a display line of ω² was 1,800 px wide, and its verdict at the
end of it was out of sight in a 670 px column.

The numbers come from one routine of the page's module, ``results(t, y, params)``,
printed by the JavaScript target of :mod:`lagrangian.codegen` like every other routine
(the page evaluates generated code, never the model's text): a column ``X`` of every
point coordinate, ω² and mode-shape entry that depends on the parameters alone; the
document holds each one's index in ``X`` (``null`` where an expression cannot be
evaluated in the page: a family's free coordinate, a number found numerically).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import sympy
from sympy.core.function import AppliedUndef

from ..algebra import as_expression
from ..analysis import Analysis
from ..analysis.modes import Stability
from ..codegen import Program
from .notation import latex_name, too_long_to_print, unicode_name

Printer = Callable[[sympy.Expr], str]
#: What the page says instead of an expression too long to typeset.
TOO_LONG = r"\text{too long to print; analyze --json gives it}"


@dataclass
class _Values:
    """The expressions the page evaluates, in the order of the routine's column ``X``."""

    parameters: dict[str, sympy.Symbol]
    expressions: list[sympy.Expr] = field(default_factory=list)

    def index(self, expr) -> dict | None:
        """``{"x": i}``, where ``expr`` is in ``X``; ``{"number": v}`` for a plain number;
        None where the page cannot evaluate it (a symbol that is not a parameter, an
        unspecified function, a number that is not real)."""
        expr = as_expression(expr)
        if expr.is_number:
            value = complex(expr.evalf())
            real = abs(value.imag) <= 1e-12 * max(1.0, abs(value))
            return {"number": value.real} if real else None
        names = {s.name for s in expr.free_symbols}
        if not names <= set(self.parameters) or expr.has(AppliedUndef, sympy.Derivative):
            return None
        by_name = {s: self.parameters[s.name] for s in expr.free_symbols}
        self.expressions.append(expr.xreplace(by_name))
        return {"x": len(self.expressions) - 1}


def results_section(
    analysis: Analysis, show: Printer, parameters: dict[str, sympy.Symbol]
) -> tuple[dict, list[sympy.Expr]]:
    """The page's section "Equilibria and small oscillations" and the expressions its
    numbers come from (the column ``X`` of :func:`results_routine`).

    ``parameters``: {name: symbol} of the model's parameters, the only symbols the page
    can give values to.
    """
    values = _Values(parameters)
    items: list[dict] = []
    for e in analysis.equilibria:
        items.append({"equilibrium": _equilibrium(e, show, values)})
    if not analysis.equilibria:
        items.append({"text": _no_equilibria(analysis)})
    if analysis.reduction is not None:
        potential = analysis.reduction.effective_potential
        items.append(
            {"latex": r"V_{\mathrm{eff}} = " + breakable_latex(potential, show), "wrap": True}
        )
    for u in analysis.undecided:  # out of time: said, not left out silently
        items.append({"text": f"{u.stage}: {u.reason}"})
    section = {"title": "Equilibria and small oscillations", "items": items}
    return section, values.expressions


def _no_equilibria(analysis: Analysis) -> str:
    not_applied = [n for n in analysis.notes if n.startswith("equilibria: ")]
    if not_applied:
        return "Equilibria not computed: " + not_applied[0].removeprefix("equilibria: ")
    return "No equilibrium was found."


def _equilibrium(e, show: Printer, values: _Values) -> dict:
    """One equilibrium: its point, verdict and remarks, and each mode's ω² (LaTeX and the
    index of its number), shape (indices) and the free motions of its zero modes."""
    point = [
        {
            "name": unicode_name(k),
            "latex": rf"{latex_name(k)} = {_latex(v, show)}",
            "value": values.index(v),
        }
        for k, v in e.point.items()
    ]
    modes = e.modes
    shapes = list(modes.shapes) if len(modes.shapes) == len(modes.omega_squared) else []
    mode_list = []
    for k, w2 in enumerate(modes.omega_squared):
        shape = [values.index(x) for x in shapes[k]] if shapes and len(shapes[k]) > 1 else []
        mode_list.append(
            {
                "latex": breakable_latex(w2, show),
                "value": values.index(w2),
                "shape": shape,
            }
        )
    remarks = []
    if getattr(e, "free", ()):
        remarks.append("a family of equilibria, free: " + ", ".join(map(unicode_name, e.free)))
    if getattr(e, "family_dimension", 0):
        remarks.append(f"one member of a family of up to {e.family_dimension} free directions")
    if getattr(e, "degenerate", ()):
        names = ", ".join(map(unicode_name, e.degenerate))
        remarks.append(f"{names} degenerate here (singular coordinates): the regular directions")
    zero_modes = list(getattr(e, "zero_modes", ()))
    for name in dict.fromkeys(zero_modes):
        count = zero_modes.count(name)
        remarks.append(f"ω² = 0{f' (×{count})' if count > 1 else ''}: {name}")
    if modes.note:
        remarks.append(modes.note)
    condition = getattr(e, "stability_condition", None)
    return {
        "point": point,
        "stability": modes.stability.value,
        # whether the verdict depends on the parameters (the page then judges it at the
        # values of the moment from the numbers of ω²)
        "depends": bool(getattr(e, "at_defaults", False)),
        "judged": modes.stability not in (Stability.ASYMPTOTICALLY_STABLE, Stability.UNDETERMINED),
        "numeric": bool(e.numeric),
        "condition": None if condition is None else _relation_latex(condition, show),
        "modes": mode_list,
        "remarks": remarks,
    }


def _relation_latex(condition, show: Printer) -> str:
    parts = condition.args if isinstance(condition, sympy.And) else (condition,)
    return r" \ \wedge\ ".join(
        f"{breakable_latex(p.lhs, show)} > {breakable_latex(p.rhs, show)}" for p in parts
    )


def _latex(expr, show: Printer) -> str:
    expr = as_expression(expr)
    return TOO_LONG if too_long_to_print(expr) else show(expr)


def breakable_latex(expr, show: Printer) -> str:
    """LaTeX of ``expr`` that KaTeX's inline mode can break across lines: a product with
    a long sum, ``g (a + b - c) / (2 l m)``, as ``\\dfrac{g}{2 l m}\\,(a + b - c)`` with
    plain parentheses (KaTeX breaks after a top-level ``+``, never inside ``\\left(``,
    a fraction or a root), a sum as its terms.

    >>> import sympy
    >>> a, b, g, l = sympy.symbols("a b g l")
    >>> breakable_latex(g * (a + b) / (2 * l), sympy.latex)
    '\\\\dfrac{g}{2 l}\\\\,(a + b)'
    """
    expr = as_expression(expr)
    if too_long_to_print(expr):
        return TOO_LONG
    if isinstance(expr, sympy.Add):
        return _display_fractions(show(expr))
    numerator, denominator = sympy.fraction(expr)
    sums = [f for f in sympy.Mul.make_args(numerator) if isinstance(f, sympy.Add)]
    if not sums:
        return _display_fractions(show(expr))
    longest = max(sums, key=sympy.count_ops)
    sign, coefficient = (
        "",
        sympy.Mul(*[f for f in sympy.Mul.make_args(numerator) if f is not longest]),
    )
    if coefficient.could_extract_minus_sign():
        sign, coefficient = "-", -coefficient
    if denominator == 1 and coefficient == 1:
        head = ""
    elif denominator == 1:
        head = show(coefficient) + r"\,"
    else:
        head = rf"\dfrac{{{show(coefficient)}}}{{{show(denominator)}}}\,"
    return f"{sign}{head}({_display_fractions(show(longest))})"


def _display_fractions(latex: str) -> str:
    """Fractions at the size of display math (inline math would set them small)."""
    return latex.replace(r"\frac{", r"\dfrac{")


def results_script(code: Program, expressions: Sequence[sympy.Expr]) -> str:
    """The function ``results(t, y, params)`` of the page's module, the column ``X`` of
    ``expressions`` (over the model's parameters), printed by the JavaScript target; ""
    where there is nothing to evaluate, or an expression has a function JavaScript lacks
    (the page then shows the symbolic forms and the numbers it was written with)."""
    from ..codegen.javascript import JavaScriptTarget

    if not expressions:
        return ""
    routine = code.routine("results", [("X", sympy.Matrix(list(expressions)))])
    try:
        lines = JavaScriptTarget().function("results", code, routine, exported=False)
    except NotImplementedError:  # SymPy's strict printer: a function with no JavaScript
        return ""
    return "\n".join(lines) + "\n"

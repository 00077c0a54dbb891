"""LaTeX of equations and derivations, with dot notation."""

from __future__ import annotations

import sympy

from ..derive import EquationsOfMotion
from ..model import System
from .large import latex_printer, printed
from .notation import (
    TOO_LONG,
    DotLatexPrinter,
    declared_functions,
    latex_name,
    too_long_to_print,
)


def latex_expression(expr: sympy.Expr, system: System | None = None) -> str:
    return DotLatexPrinter(declared_functions(system)).doprint(expr)


def _solved(name: str, value: sympy.Expr, system: System) -> str:
    """An ``align*`` row ``name &= value``; a closed form too long to read is named only."""
    if too_long_to_print(value):
        return rf"{name} &: \text{{{TOO_LONG}}}"
    return rf"{name} &= {latex_printer(system)(value)}"


def latex_equations(eom: EquationsOfMotion) -> str:
    """An ``align*`` block: L, each equation (= 0) and each solved acceleration."""
    system = eom.system
    show = latex_printer(system)  # linear-time printing for large systems
    shown = printed(eom)
    rows = [rf"L &= {show(shown.lagrangian)}"]
    rows += [rf"0 &= {show(equation)}" for equation in shown.equations]
    if eom.accelerations is not None:
        rows += [
            _solved(latex_name(c.q_ddot.name), eom.accelerations[c.name], system)
            for c in eom.coordinates
        ]
    if eom.multipliers is not None:
        rows += [_solved(latex_name(n), v, system) for n, v in eom.multipliers.items()]
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


def latex_steps(eom: EquationsOfMotion) -> str:
    """The derivation step by step as LaTeX (one ``align*`` block)."""
    system = eom.system
    show = latex_printer(system)  # linear-time printing for large systems
    rows = []
    if system.kinetic is not None:
        rows += [rf"T &= {show(system.kinetic)}", rf"V &= {show(system.potential)}"]
    rows.append(rf"L &= {show(system.lagrangian)}")
    if system.dissipation != 0:
        rows.append(rf"\mathcal{{F}} &= {show(system.dissipation)}")
    for step in eom.steps:
        c = step.coordinate
        q, q_dot = latex_name(c.name), latex_name(c.q_dot.name)
        d_dq_dot = rf"\frac{{\partial L}}{{\partial {q_dot}}}"
        rows.append(rf"{d_dq_dot} &= {show(step.momentum)}")
        rows.append(rf"\frac{{d}}{{dt}}{d_dq_dot} &= {show(step.momentum_rate)}")
        rows.append(rf"\frac{{\partial L}}{{\partial {q}}} &= {show(step.force_gradient)}")
        if step.generalized_force != 0:
            rows.append(rf"Q_{{{q}}} &= {show(step.generalized_force)}")
        if step.dissipation_force != 0:
            d_f = rf"\frac{{\partial \mathcal{{F}}}}{{\partial {q_dot}}}"
            rows.append(rf"{d_f} &= {show(step.dissipation_force)}")
        if step.constraint_force != 0:
            rows.append(rf"\sum_j \lambda_j a_{{j {q}}} &= {show(step.constraint_force)}")
        divided = (
            rf" &&\text{{(divided by }} {show(step.divided_by)}\text{{)}}"
            if step.divided_by != 1
            else ""
        )
        rows.append(rf"0 &= {show(step.equation)}{divided}")
        if eom.accelerations is not None:
            rows.append(_solved(latex_name(c.q_ddot.name), eom.accelerations[c.name], system))
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"

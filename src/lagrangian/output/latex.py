"""LaTeX of equations and derivations, with dot notation."""

from __future__ import annotations

import sympy

from ..collector import cycle_collector_paused
from ..derive import EquationsOfMotion
from ..model import System
from .large import latex_printer, printed
from .notation import DotLatexPrinter, declared_functions, equality, latex_name, step_terms


def latex_expression(expr: sympy.Expr, system: System | None = None) -> str:
    return DotLatexPrinter(declared_functions(system)).doprint(expr)


def _solved(name: str, value: sympy.Expr, system: System) -> str:
    """An ``align*`` row ``name &= value``; a closed form too long to read is named only."""
    return equality(name, value, latex_printer(system), equals=" &= ", named=r" &: \text{{{}}}")


def latex_equations(eom: EquationsOfMotion) -> str:
    """An ``align*`` block: L, each equation (= 0) and each solved acceleration."""
    return aligned(equation_rows(eom))


def aligned(rows: list[str]) -> str:
    """The ``align*`` block of ``rows`` (each ``lhs &= rhs``)."""
    return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}"


@cycle_collector_paused()  # a large system's walk keeps 100,000s of records, no cycles
def equation_rows(eom: EquationsOfMotion) -> list[str]:
    """The rows of :func:`latex_equations`."""
    system = eom.system
    show = latex_printer(system)  # linear-time printing for large systems
    shown = printed(eom)
    rows = _units_rows(system)
    rows.append(rf"L &= {show(shown.lagrangian)}")
    rows += [rf"0 &= {show(equation)}" for equation in shown.equations]
    if eom.accelerations is not None:
        rows += [
            _solved(latex_name(c.q_ddot.name), eom.accelerations[c.name], system)
            for c in eom.coordinates
        ]
    if eom.multipliers is not None:
        rows += [_solved(latex_name(n), v, system) for n, v in eom.multipliers.items()]
    return rows


def _units_rows(system: System) -> list[str]:
    """The units row of a dimensioned model; none otherwise (nor the units module imported)."""
    if system.units is None:
        return []
    from .units import latex_units_row

    return [latex_units_row(system)]


#: The row of each term of a coordinate's equation (see notation.step_terms).
_STEP_ROWS = {
    "momentum": r"\frac{{\partial L}}{{\partial {q_dot}}} &= {value}",
    "momentum_rate": r"\frac{{d}}{{dt}}\frac{{\partial L}}{{\partial {q_dot}}} &= {value}",
    "force_gradient": r"\frac{{\partial L}}{{\partial {q}}} &= {value}",
    "generalized_force": r"Q_{{{q}}} &= {value}",
    "dissipation_force": r"\frac{{\partial \mathcal{{F}}}}{{\partial {q_dot}}} &= {value}",
    "constraint_force": r"\sum_j \lambda_j a_{{j {q}}} &= {value}",
    "equation": r"0 &= {value}{divided}",
}


def latex_steps(eom: EquationsOfMotion) -> str:
    """The derivation step by step as LaTeX (one ``align*`` block)."""
    return aligned(step_rows(eom))


@cycle_collector_paused()  # a large system's walk keeps 100,000s of records, no cycles
def step_rows(eom: EquationsOfMotion) -> list[str]:
    """The rows of :func:`latex_steps`."""
    system = eom.system
    show = latex_printer(system)  # linear-time printing for large systems
    rows = _units_rows(system)
    if system.kinetic is not None:
        rows += [rf"T &= {show(system.kinetic)}", rf"V &= {show(system.potential)}"]
    rows.append(rf"L &= {show(system.lagrangian)}")
    if system.dissipation != 0:
        rows.append(rf"\mathcal{{F}} &= {show(system.dissipation)}")
    for step in eom.steps:
        c = step.coordinate
        names = {"q": latex_name(c.name), "q_dot": latex_name(c.q_dot.name)}
        divided = (
            rf" &&\text{{(divided by }} {show(step.divided_by)}\text{{)}}"
            if step.divided_by != 1
            else ""
        )
        rows += [
            _STEP_ROWS[what].format(**names, value=show(value), divided=divided)
            for what, value in step_terms(step)
        ]
        if eom.accelerations is not None:
            rows.append(_solved(latex_name(c.q_ddot.name), eom.accelerations[c.name], system))
    return rows


def top_level_terms(latex: str) -> list[str]:
    """``latex`` cut before each `` + `` and `` - `` outside every group (braces,
    ``\\left ... \\right``, environments): the first piece keeps its own sign, the others
    begin with ``+ `` or ``- ``."""
    pieces, start, depth = [], 0, 0
    i = 0
    while i < len(latex):
        if latex.startswith("\\left", i) and not latex[i + 5 : i + 6].isalpha():
            depth += 1
            i += 5
            continue
        if latex.startswith("\\right", i) and not latex[i + 6 : i + 7].isalpha():
            depth -= 1
            i += 6
            continue
        if latex.startswith("\\begin", i):
            depth += 1
            i += 6
            continue
        if latex.startswith("\\end", i):
            depth -= 1
            i += 4
            continue
        char = latex[i]
        if char == "\\":
            i += 2  # an escaped character (\{, \}) is no group
            continue
        if char == "{":
            depth += 1
        elif char == "}":
            depth -= 1
        elif depth == 0 and latex[i : i + 3] in (" + ", " - ") and latex[start:i].strip():
            pieces.append(latex[start:i].strip())
            start = i + 1
        i += 1
    pieces.append(latex[start:].strip())
    return [p for p in pieces if p]

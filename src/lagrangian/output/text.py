"""Readable Unicode text of equations and of the derivation step by step."""

from __future__ import annotations

import sympy

from ..collector import cycle_collector_paused
from ..derive import EquationsOfMotion
from ..model import System
from .large import printed, unicode_printer
from .notation import UnicodePrinter, declared_functions, equality, step_terms, unicode_name


def unicode_expression(expr: sympy.Expr, system: System | None = None) -> str:
    """One line of textbook notation, e.g. ``r̈ = ω² r`` for Eq(r_ddot, omega**2*r)."""
    return UnicodePrinter(declared_functions(system)).doprint(expr)


@cycle_collector_paused()  # a large system's walk keeps 100,000s of records, no cycles
def format_equations(eom: EquationsOfMotion) -> str:
    """The equations of motion as text: L, the equations (= 0) and the accelerations."""
    system = eom.system
    show = unicode_printer(system)  # linear-time printing for large systems
    lines = [_title(system)]
    shown = printed(eom)
    lines.append(f"  L = {show(shown.lagrangian)}")
    lines.append("")
    lines.append("Equations of motion:")
    for c, equation in zip(eom.coordinates, shown.equations, strict=True):
        lines.append(f"  {unicode_name(c.name)}:  {show(equation)} = 0")
    if eom.accelerations is not None:
        lines.append("")
        lines.append("Accelerations:")
        for c in eom.coordinates:
            lines.append(
                "  " + equality(unicode_name(c.q_ddot.name), eom.accelerations[c.name], show)
            )
    if eom.multipliers is not None:
        lines.append("")
        lines.append("Lagrange multipliers (constraint forces):")
        for name, value in eom.multipliers.items():
            lines.append("  " + equality(unicode_name(name), value, show))
    if system.linkage is not None:  # the linkage module imported for linkages only
        from .linkage_summary import linkage_lines

        lines += linkage_lines(eom)
    return "\n".join(lines)


#: The line of each term of a coordinate's equation (see notation.step_terms).
_STEP_LINES = {
    "momentum": "  ∂L/∂{q_dot} = {value}",
    "momentum_rate": "  d/dt(∂L/∂{q_dot}) = {value}",
    "force_gradient": "  ∂L/∂{q} = {value}",
    "generalized_force": "  Q_{q} = {value}",
    "dissipation_force": "  ∂F/∂{q_dot} = {value}",
    "constraint_force": "  Σ λ a_{q} = {value}   (constraint force)",
    "equation": "  equation: {value} = 0{divided}",
}


@cycle_collector_paused()  # a large system's walk keeps 100,000s of records, no cycles
def format_steps(eom: EquationsOfMotion) -> str:
    """The derivation as done by hand: T, V, L, then each coordinate's terms."""
    system = eom.system
    show = unicode_printer(system)  # linear-time printing for large systems
    lines = [_title(system)]
    if system.kinetic is not None:
        lines.append(f"  T = {show(system.kinetic)}")
        lines.append(f"  V = {show(system.potential)}")
    lines.append(f"  L = {show(system.lagrangian)}")
    if system.dissipation != 0:
        lines.append(f"  F = {show(system.dissipation)}   (Rayleigh dissipation function)")
    lines.append("")
    law = "d/dt(∂L/∂q̇) − ∂L/∂q = Q − ∂F/∂q̇" + (" + Σ λ a_q" if eom.constraints else "")
    lines.append(f"Lagrange's equation for each coordinate q: {law}")
    for step in eom.steps:
        c = step.coordinate
        q, q_dot = unicode_name(c.name), unicode_name(c.q_dot.name)
        lines.append("")
        lines.append(f"Coordinate {q}:")
        divided = f"   (divided by {show(step.divided_by)})" if step.divided_by != 1 else ""
        lines += [
            _STEP_LINES[what].format(q=q, q_dot=q_dot, value=show(value), divided=divided)
            for what, value in step_terms(step)
        ]
        if eom.accelerations is not None:
            lines.append(
                "  " + equality(unicode_name(c.q_ddot.name), eom.accelerations[c.name], show)
            )
    return "\n".join(lines)


def _title(system: System) -> str:
    """The model's name and coordinates, and a second line of its units if it has them."""
    if system.units is None:  # the units module imported for dimensioned models only
        return _name_line(system)
    from .units import units_line

    line = units_line(system)
    return _name_line(system) + (f"\n{line}" if line else "")


def _name_line(system: System) -> str:
    coordinates = ", ".join(unicode_name(name) for name in system.coordinate_names)
    return f"{system.name}   (coordinates: {coordinates})"

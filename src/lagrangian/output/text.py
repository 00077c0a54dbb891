"""Readable Unicode text of equations and of the derivation step by step."""

from __future__ import annotations

import sympy

from ..derive import EquationsOfMotion
from ..model import System
from .large import printed, unicode_printer
from .notation import (
    TOO_LONG,
    UnicodePrinter,
    declared_functions,
    too_long_to_print,
    unicode_name,
)


def unicode_expression(expr: sympy.Expr, system: System | None = None) -> str:
    """One line of textbook notation, e.g. ``r̈ = ω² r`` for Eq(r_ddot, omega**2*r)."""
    return UnicodePrinter(declared_functions(system)).doprint(expr)


def _equality(lhs: str, rhs: sympy.Expr, system: System) -> str:
    """``lhs = rhs``; a closed form too long to read is named, not printed."""
    if too_long_to_print(rhs):
        return f"{lhs}: {TOO_LONG}"
    return f"{lhs} = {unicode_printer(system)(rhs)}"


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
                "  " + _equality(unicode_name(c.q_ddot.name), eom.accelerations[c.name], system)
            )
    if eom.multipliers is not None:
        lines.append("")
        lines.append("Lagrange multipliers (constraint forces):")
        for name, value in eom.multipliers.items():
            lines.append("  " + _equality(unicode_name(name), value, system))
    return "\n".join(lines)


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
        lines.append(f"  ∂L/∂{q_dot} = {show(step.momentum)}")
        lines.append(f"  d/dt(∂L/∂{q_dot}) = {show(step.momentum_rate)}")
        lines.append(f"  ∂L/∂{q} = {show(step.force_gradient)}")
        if step.generalized_force != 0:
            lines.append(f"  Q_{q} = {show(step.generalized_force)}")
        if step.dissipation_force != 0:
            lines.append(f"  ∂F/∂{q_dot} = {show(step.dissipation_force)}")
        if step.constraint_force != 0:
            lines.append(f"  Σ λ a_{q} = {show(step.constraint_force)}   (constraint force)")
        divided = f"   (divided by {show(step.divided_by)})" if step.divided_by != 1 else ""
        lines.append(f"  equation: {show(step.equation)} = 0{divided}")
        if eom.accelerations is not None:
            lines.append(
                "  " + _equality(unicode_name(c.q_ddot.name), eom.accelerations[c.name], system)
            )
    return "\n".join(lines)


def _title(system: System) -> str:
    coordinates = ", ".join(unicode_name(name) for name in system.coordinate_names)
    return f"{system.name}   (coordinates: {coordinates})"

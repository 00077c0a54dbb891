"""The units of results, named from a dimensioned model's :class:`~lagrangian.model.units.Units`.

Everything is computed in SI base units (the model converted its values when it was
loaded), so a result's unit follows from its dimension: a conserved quantity's from its
expression (:func:`~lagrangian.model.dimensions.dimension_of`), ω in rad/s, a period in
s, a column of a trajectory from its name.  For a model without units every function
here says nothing (None, or an empty section), and the outputs are as they were.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

import sympy

from ..algebra import as_expression
from ..model.dimensions import ENERGY, RATE, dimension_of, power, unit_text
from .notation import latex_name

if TYPE_CHECKING:
    from ..model.system import System

#: The units of the numbers of small oscillations.
OMEGA, OMEGA_SQUARED, PERIOD = unit_text(RATE, angle=True), unit_text(power(RATE, 2)), "s"


def expression_unit(system: System, expr: sympy.Expr) -> str | None:
    """The SI unit of ``expr`` (over the model's names), or None: no units, or a
    dimension the expression does not have (a sum of unlike terms)."""
    if system.units is None:
        return None
    expr = as_expression(expr)
    table = system.units.symbols(system)
    for symbol in expr.free_symbols - set(table):  # momenta p_q (a Hamiltonian's), by name
        dimension = _momentum(system, symbol.name)
        if dimension is not None:
            table[symbol] = dimension
    found = dimension_of(expr, table)
    return None if found is None else unit_text(found)


def _momentum(system: System, name: str):
    return system.units.momentum(name)


def name_unit(system: System, name: str) -> str | None:
    """The SI unit of a name of the model, of a trajectory's column (``energy``,
    ``p_theta``) or of time; None without units or for a name it cannot tell."""
    return None if system.units is None else system.units.column_unit(name)


def units_section(system: System) -> dict | None:
    """The ``units`` of a JSON document: every name's SI unit, and which were inferred
    from the equations rather than given; None for a model without units."""
    units = system.units
    if units is None:
        return None
    names = [*system.coordinate_names, *(f"{q}_dot" for q in system.coordinate_names)]
    names += [*system.parameter_names, *(f.name for f in system.functions)]
    return {
        "names": {name: units.unit(name) for name in names},
        "inferred": list(units.inferred),
        "time": "s",
        "energy": unit_text(ENERGY),
    }


def units_line(system: System) -> str | None:
    """One line of text naming every unit, the inferred ones marked: ``Units (SI):
    theta rad (inferred), m kg, ...``; None for a model without units."""
    section = units_section(system)
    if section is None:
        return None
    inferred = set(section["inferred"])
    shown = [
        f"{name} {unit}" + (" (inferred)" if name in inferred else "")
        for name, unit in section["names"].items()
        if not name.endswith("_dot")
    ]
    return "Units (SI): " + ", ".join(shown)


def bracketed(unit: str | None) -> str:
    """`` [J]`` after a quantity, or nothing."""
    return f" [{unit}]" if unit else ""


def latex_unit(unit: str) -> str:
    r"""A unit as upright LaTeX: ``kg*m^2`` -> ``\mathrm{kg\cdot m^2}``, ``m^(1/2)`` ->
    ``\mathrm{m^{1/2}}``, ``s^12`` -> ``\mathrm{s^{12}}`` (a bare ``*`` would print as a
    star, and ``^12`` raises only the 1)."""
    text = re.sub(r"\^(?:\((\d+/\d+)\)|(\d\d+))", lambda m: f"^{{{m[1] or m[2]}}}", unit)
    text = text.replace("*", r"\cdot ")
    return rf"\mathrm{{{text}}}"


def latex_units_row(system: System) -> str | None:
    r"""The ``Units (SI)`` line of the text output as a row of an ``align*`` block
    (``&\text{Units (SI): } \theta\ [\mathrm{rad}]\ \text{(inferred)}, ...``); None for a
    model without units."""
    section = units_section(system)
    if section is None:
        return None
    inferred = set(section["inferred"])
    shown = [
        rf"{latex_name(name)}\ [{latex_unit(unit)}]"
        + (r"\ \text{(inferred)}" if name in inferred else "")
        for name, unit in section["names"].items()
        if not name.endswith("_dot")
    ]
    return r"&\text{Units (SI): } " + r",\ ".join(shown)


def latex_mode_numbers(numbers: dict, system: System) -> str:
    r"""An ``align*`` row of the numbers of :func:`~lagrangian.output.analysis.modes_at_values`
    in SI units: ``&\quad\text{at } g = 9.81\ \mathrm{m/s^2}: \ \omega^2 = 19.62\
    \mathrm{1/s^2};\ \omega = ...``, as the text output's ``at g = 9.81 m/s^2: ω² = ...``."""

    def quantity(value: float | None, unit: str | None, digits: str = ".6g") -> str:
        shown = "-" if value is None else format(value, digits)
        return shown + (rf"\ {latex_unit(unit)}" if unit else "")

    at = r",\ ".join(
        f"{latex_name(n)} = {quantity(v, name_unit(system, n), 'g')}"
        for n, v in numbers["parameters"].items()
    )
    parts = [
        r"\omega^2 = " + ", ".join(quantity(w2, OMEGA_SQUARED) for w2 in numbers["omega_squared"])
    ]
    if any(w is not None for w in numbers["omega"]):
        parts.append(r"\omega = " + ", ".join(quantity(w, OMEGA) for w in numbers["omega"]))
        parts.append(
            r"\text{periods } " + ", ".join(quantity(p, PERIOD) for p in numbers["periods"])
        )
    return rf"&\quad\text{{at }} {at}: \ " + r";\ ".join(parts)

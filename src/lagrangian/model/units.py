"""The units of a dimensioned model: read at load, converted to SI, checked, named.

A model is dimensioned when a unit appears anywhere in it: a parameter's value with a
unit (``m = "2 kg"``, ``l = {value = "50 cm", sign = "real"}``) or a ``[units]`` table
(``x = "m"``, ``theta = "deg"``, ``F = "N"``: the unit of a coordinate, an input, or a
parameter's bare number).  Every value is converted to SI base units when the model is
loaded (:func:`read_units`), so that everything below the model layer computes in one
consistent system and never sees a unit.  The dimensions of all names are then checked
and inferred (:mod:`.dimension_check`) and kept on the System as :class:`Units`, which
the outputs read to name their units.

A model without a unit is not touched: :func:`has_units` looks at it without importing
anything, and pint (:mod:`.quantities`) is imported only for a model with a unit.

A bare number given for a name (``--set l=0.5``, ``[initial] x = 3``) is in the unit the
model declares for it (its ``[units]`` entry, else the unit of its value); a value given
with a unit (``--set l=50cm``) is converted, after checking that it has the name's
dimension (:func:`values_given`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from fractions import Fraction
from types import MappingProxyType
from typing import TYPE_CHECKING

import sympy

from ..errors import ModelError
from ..symbols import ACCELERATION_SUFFIX, TIME_NAME, VELOCITY_SUFFIX
from .dimensions import DIMENSIONLESS, ENERGY, TIME, Dimension, describe, over, unit_text
from .inputs import input_entries
from .quantities import Quantity, Unit, has_unit, read_quantity, read_unit

if TYPE_CHECKING:
    from .spec import ModelSpec
    from .system import System


@dataclass(frozen=True)
class Units:
    """The dimension of every name of a dimensioned model, and the units declared for them.

    ``dimensions``: coordinate, parameter (inputs included) and function names ->
    dimension; ``declared``: the names whose unit the model gives -> that unit (bare
    numbers given for the name are in it); ``inferred``: the names whose dimension the
    check found from the equations.  Values inside the System are in SI base units.
    """

    dimensions: Mapping[str, Dimension]
    declared: Mapping[str, Unit]
    inferred: tuple[str, ...]
    coordinates: tuple[str, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "dimensions", MappingProxyType(dict(self.dimensions)))
        object.__setattr__(self, "declared", MappingProxyType(dict(self.declared)))

    def dimension(self, name: str) -> Dimension | None:
        """The dimension of ``name``: t, a coordinate, its velocity or acceleration, a
        parameter; None for a name the model does not have."""
        if name == TIME_NAME:
            return TIME
        for suffix, order in ((ACCELERATION_SUFFIX, 2), (VELOCITY_SUFFIX, 1)):
            base = name.removesuffix(suffix)
            if base != name and base in self.coordinates:
                return over(self.dimensions[base], tuple(order * x for x in TIME))
        return self.dimensions.get(name)

    def unit(self, name: str) -> str:
        """The SI unit of ``name``'s values (``m``, ``rad/s``, ``kg``); a coordinate
        without dimension is an angle (``rad``)."""
        value = self.dimension(name)
        if value is None:
            raise ModelError(f"unknown name '{name}'")
        return unit_text(value, angle=self._angular(name))

    def describe(self, name: str) -> str:
        """``name``'s dimension in words: ``a length (m)``; an angle's rate ``an angular
        rate (rad/s)``, not ``a rate (1/s)``."""
        return describe(self.dimension(name), angular=self._angular(name))

    def momentum(self, name: str) -> Dimension | None:
        """The dimension of ``p_q``, the momentum dL/dq_dot of a coordinate q, or None."""
        if not (name.startswith("p_") and name[2:] in self.coordinates):
            return None
        return over(ENERGY, self.dimension(f"{name[2:]}_dot"))

    def column_unit(self, name: str) -> str | None:
        """The SI unit of a trajectory's column or a result named ``name``: t, a
        coordinate or velocity, ``energy`` (or ``jacobi``), a momentum ``p_q``, a
        parameter; None for a name it cannot tell (a multiplier, an invariant)."""
        if name in ("energy", "jacobi", "hamiltonian"):
            return unit_text(ENERGY)
        momentum = self.momentum(name)
        if momentum is not None:
            return unit_text(momentum)
        return None if self.dimension(name) is None else self.unit(name)

    def _angular(self, name: str) -> bool:
        base = name.removesuffix(ACCELERATION_SUFFIX).removesuffix(VELOCITY_SUFFIX)
        return base in self.coordinates and self.dimensions[base] == DIMENSIONLESS

    def bare(self, name: str, number: float) -> float:
        """A bare number given for ``name``, in the unit declared for it, in SI."""
        base = name.removesuffix(ACCELERATION_SUFFIX).removesuffix(VELOCITY_SUFFIX)
        unit = self.declared.get(name) or (
            self.declared.get(base) if base in self.coordinates else None
        )
        return number if unit is None else number * unit.factor

    def symbols(self, system: System) -> dict[sympy.Expr, Dimension]:
        """SymPy symbol (and declared function applied) -> dimension, for
        :func:`~lagrangian.model.dimensions.dimension_of`."""
        table = {}
        for name, symbol in system.symbols.items():
            value = self.dimension(name)
            if value is not None:
                table[symbol] = value
        for function in system.functions:
            table[function.applied] = self.dimensions[function.name]
        return table


def has_units(spec: ModelSpec) -> bool:
    """Whether ``spec`` has a unit anywhere (without reading any)."""
    if spec.units or any(isinstance(value, str) for value in spec.initial.values()):
        return True
    parameters = spec.parameters
    if not isinstance(parameters, Mapping):
        return False
    values = (e.get("value") if isinstance(e, Mapping) else e for e in parameters.values())
    return any(isinstance(value, str) for value in values)


def read_units(spec: ModelSpec) -> tuple[ModelSpec, dict[str, Unit], dict[str, Quantity]]:
    """``spec`` with its parameters' values and initial values in SI base units, the unit
    declared for each name that has one, and the initial values given with a unit
    (``theta = "30 deg"``: checked against the coordinate's dimension once it is known)."""
    if not isinstance(spec.units, Mapping):
        raise ModelError('expected a table of name = "unit"', field="units")
    declared = {}
    for name, text in spec.units.items():
        if not isinstance(text, str):
            raise ModelError(f'expected a unit such as "m", got {text!r}', field=f"units.{name}")
        declared[name] = read_unit(text, f"units.{name}")
    parameters = {}
    for name, entry in (spec.parameters or {}).items():
        parameters[name] = _parameter_in_si(name, entry, declared)
    _check_declared_names(spec, declared, parameters)
    initial, given = {}, {}
    for name, value in spec.initial.items():
        base = name.removesuffix(VELOCITY_SUFFIX)
        unit = declared.get(base)
        if isinstance(value, str):
            given[name] = read_quantity(value, f"initial.{name}")
            initial[name] = given[name].value
        elif unit and isinstance(value, int | float) and not isinstance(value, bool):
            initial[name] = value * unit.factor
        else:
            initial[name] = value
    return replace(spec, parameters=parameters, initial=initial), declared, given


def _parameter_in_si(name: str, entry: object, declared: dict[str, Unit]) -> object:
    """A parameter's entry with its value in SI: a value with a unit converted (and its
    unit declared for the name, unless [units] declares one), a bare number in the
    unit [units] gives it."""
    where = f"parameters.{name}"
    value = entry.get("value") if isinstance(entry, Mapping) else entry
    if isinstance(value, str):
        quantity = read_quantity(value, where)
        unit = declared.setdefault(name, quantity.unit)
        if unit.dimension != quantity.unit.dimension:
            raise ModelError(
                f"{value!r} is {describe(quantity.unit.dimension)}, but [units] gives "
                f"{name} in {unit.text}, {describe(unit.dimension)}",
                field=where,
            )
        number = quantity.value
    elif isinstance(value, int | float) and not isinstance(value, bool) and name in declared:
        number = value * declared[name].factor
    else:
        return entry
    return {**entry, "value": number} if isinstance(entry, Mapping) else number


def _check_declared_names(spec: ModelSpec, declared: Mapping[str, Unit], parameters) -> None:
    names = set(spec.coordinates) | set(parameters) | set(spec.functions)
    names |= {name for name, _, _ in input_entries(spec.inputs)}
    for name in declared:
        if name not in names:
            raise ModelError(
                "not a coordinate, parameter, input or function of the model", field=f"units.{name}"
            )


def dimensioned(
    system: System,
    spec: ModelSpec,
    declared: Mapping[str, Unit],
    initial: Mapping[str, Quantity] | None = None,
    trees: Mapping[str, object] | None = None,
) -> System:
    """``system`` (built from ``spec``) with its :class:`Units`, after the dimension check
    (and the check of the ``initial`` values given with a unit against it); ``trees``:
    the syntax trees of its texts, kept by the build (text -> tree)."""
    from .dimension_check import Names, check_dimensions

    names = Names(
        coordinates=system.coordinate_names,
        parameters=system.parameter_names,
        functions=tuple(f.name for f in system.functions),
        known={name: unit.dimension for name, unit in declared.items()},
    )
    dimensions = check_dimensions(spec, names, trees)
    units = Units(
        dimensions=dimensions,
        declared=declared,
        inferred=tuple(name for name in dimensions if name not in declared),
        coordinates=system.coordinate_names,
    )
    for name, quantity in (initial or {}).items():
        if quantity.unit.dimension != units.dimension(name):
            raise ModelError(
                f"{name} is {units.describe(name)} but the value is "
                f"{describe(quantity.unit.dimension)}",
                field=f"initial.{name}",
            )
    return replace(system, units=units)


def values_given(
    system: System, texts: Mapping[str, str], where: str
) -> tuple[System, dict[str, float]]:
    """Values given as text for names of ``system`` (``--set l=50cm``), in SI.

    A bare number is in the unit the model declares for the name; a value with a unit
    is converted, and refused unless it has the name's dimension.  A unit given for a
    model without units makes it dimensioned: it is built again with each such name in
    the SI unit of its value (and then checked, as a model file with units is).
    Returns the system (the same, or the dimensioned one) and the values.
    """
    quantities = {}
    for name, text in texts.items():
        if has_unit(text):
            quantities[name] = read_quantity(text.strip(), f"{where} {name}={text}")
    states = {n for q in system.coordinate_names for n in (q, f"{q}{VELOCITY_SUFFIX}")}
    for name in quantities:
        if name not in states and name not in system.parameter_names:
            raise ModelError(
                f"'{name}' is not a parameter, coordinate or velocity of the model "
                f"(parameters: {', '.join(system.parameter_names) or 'none'})",
                field=f"{where} {name}",
            )
    if quantities and system.units is None:
        try:
            system = redimensioned(system, {n: q.unit.dimension for n, q in quantities.items()})
        except ModelError as error:
            given = ", ".join(f"{n}={texts[n].strip()}" for n in quantities)
            raise ModelError(f"{where} {given} gives the model units, and then: {error}") from None
    values = {}
    for name, text in texts.items():
        if name not in quantities:
            number = float(text)
            values[name] = number if system.units is None else system.units.bare(name, number)
            continue
        quantity = quantities[name]
        expected = system.units.dimension(name)
        if expected != quantity.unit.dimension:
            raise ModelError(
                f"{name} is {system.units.describe(name)} but {text.strip()} is "
                f"{describe(quantity.unit.dimension)}",
                field=f"{where} {name}={text.strip()}",
            )
        values[name] = quantity.value
    return system, values


def exact_text(system: System, name: str, text: str) -> str:
    """The SI value of ``text`` (given for ``name`` as :func:`values_given` reads it) as an
    expression: exact where the unit is a rational multiple of pi (``180deg`` is ``pi``,
    so that an operating point at an equilibrium is exactly one), else the float."""
    if has_unit(text):
        quantity = read_quantity(text.strip(), name)
        number, factor = quantity.number, quantity.unit.factor
    else:
        unit = system.units.declared.get(name) if system.units is not None else None
        number, factor = Fraction(text.strip()), unit.factor if unit else 1.0
    turns = Fraction(factor / math.pi).limit_denominator(100_000)
    if factor and abs(float(turns) * math.pi - factor) <= 1e-15 * abs(factor):
        return f"({number * turns})*pi"
    return repr(float(number) * factor)


def redimensioned(system: System, dimensions: Mapping[str, Dimension]) -> System:
    """``system`` built again from its spec with ``dimensions`` given (in SI units)."""
    from .build import build_system

    if system.spec is None:
        raise ModelError("a value with a unit needs a model loaded from a file or text")
    known = set(system.parameter_names) | set(system.coordinate_names)
    units = {}
    for name, value in dimensions.items():
        base = name.removesuffix(VELOCITY_SUFFIX)
        if name in known:
            units[name] = unit_text(value)
        elif base in system.coordinate_names:
            units[base] = unit_text(over(value, tuple(-x for x in TIME)))
        else:
            raise ModelError(f"'{name}' is not a parameter, coordinate or velocity of the model")
    return type(system).adopt(build_system(replace(system.spec, units=units)))

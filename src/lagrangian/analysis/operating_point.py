"""The operating point of a linearization and the names it is given in (``at``, inputs,
outputs), read and checked for :func:`~lagrangian.analysis.state_space.state_space`.

Values are numbers, SymPy expressions or text for the safe parser
(:func:`lagrangian.parsing.parse_expression`) over the parameters; outputs are
text or SymPy over the coordinates, velocities, inputs and parameters.  Every
problem is a one-line ModelError naming the field (``at.theta``, ``outputs.tip``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..derive import derive
from ..errors import ModelError, ParseError, setting
from ..model import System
from ..model.naming import RESERVED
from ..model.values import check_parameter_expressions
from ..parsing import Namespace, parse_expression
from ..symbols import is_identifier


class OperatingPoint:
    """The operating point: what ``at`` gives, checked, and substituted into expressions."""

    def __init__(self, system: System, at: Mapping[str, object]):
        if not isinstance(at, Mapping):
            raise ModelError(f"expected a mapping of names to values, got {type(at).__name__}")
        self.system = system
        coordinates = {c.name: c for c in system.coordinates}
        velocities = {c.q_dot.name: c for c in system.coordinates}
        parameters = {p.name: p for p in system.parameters}
        self.given: dict[str, sympy.Expr] = {}
        self.substitution: dict[sympy.Symbol, sympy.Expr] = {}
        for name, value in at.items():
            if name in coordinates:
                symbol = coordinates[name].q
            elif name in velocities:
                symbol = velocities[name].q_dot
            elif name in parameters:
                symbol = parameters[name].symbol
            else:
                known = ", ".join((*coordinates, *velocities, *parameters))
                raise ModelError(f"'{name}' is not a coordinate, velocity, input or parameter "
                                 f"(known: {known})")  # fmt: skip
            self.given[name] = point_value(value, f"at.{name}", system)
            self.substitution[symbol] = self.given[name]
        for c in system.coordinates:
            self.substitution.setdefault(c.q_dot, sympy.Integer(0))
        for entry in system.inputs:
            self.substitution.setdefault(entry.symbol, sympy.Integer(0))
        self.defaults = dict(system.parameter_values) | {
            name: float(value)
            for name, value in self.given.items()
            if name in parameters and value.is_number and value.is_real
        }
        for name in system.input_names:
            self.defaults.pop(name, None)
        check_parameter_expressions(
            system, {name: value for name, value in self.given.items() if name in parameters}
        )

    def check_steady(self, mass: sympy.MatrixBase, forcing: sympy.MatrixBase) -> None:
        """Every coordinate in M or f is given; only coordinates absent from them move."""
        for c in self.system.coordinates:
            appears = mass.has(c.q) or forcing.has(c.q)
            if appears and c.q not in self.substitution:
                raise ModelError(
                    f"the point must give {c.name} (it appears in the equations of motion)"
                )
            rate = self.substitution[c.q_dot]
            if appears and rate != 0:
                raise ModelError(
                    f"not a steady motion: {c.name} moves ({c.q_dot.name} = {rate}) but "
                    "appears in the equations of motion"
                )

    def at(self, matrix: sympy.MatrixBase) -> sympy.Matrix:
        result = sympy.Matrix(matrix).xreplace(self.substitution)
        if any(entry.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo) for entry in result):
            raise ModelError("the equations of motion are singular at this point")
        return result


def first_equilibrium(system: System) -> dict[str, sympy.Expr]:
    """The first equilibrium :func:`~lagrangian.analysis.equilibria` finds, inputs at 0
    (its point only: the modes of every equilibrium found are not needed here)."""
    from .equilibria import rest_points

    found = rest_points(derive(system.without_inputs()))
    if not found:
        raise ModelError(f"no equilibrium found: give the operating point ({setting('at=')})")
    return dict(found[0].point)


def chosen_inputs(system: System, inputs: Sequence[str] | None) -> tuple[str, ...]:
    """The inputs of B and D in order: ``inputs``, checked, or all of the model's."""
    if inputs is None:
        return system.input_names
    if isinstance(inputs, str):
        inputs = [inputs]
    for name in inputs:
        if name not in system.input_names:
            known = ", ".join(system.input_names) or "none declared"
            raise ModelError(f"'{name}' is not an input (inputs: {known})", field="inputs")
    return tuple(inputs)


def chosen_outputs(
    system: System, outputs: Mapping[str, object] | Sequence[str] | None
) -> tuple[tuple[str, ...], list[sympy.Expr]]:
    """(names, expressions) of the outputs; the whole state by default."""
    state = {c.name: c.q for c in system.coordinates} | {
        c.q_dot.name: c.q_dot for c in system.coordinates
    }
    if outputs is None:
        return tuple(state), list(state.values())
    if isinstance(outputs, str) or not isinstance(outputs, Mapping | Sequence):
        raise ModelError("expected a list of state names or a mapping name -> expression",
                         field="outputs")  # fmt: skip
    if not isinstance(outputs, Mapping):
        for name in outputs:
            if name not in state:
                known = ", ".join(state)
                raise ModelError(f"'{name}' is not a coordinate or velocity (known: {known})",
                                 field="outputs")  # fmt: skip
        outputs = {name: name for name in outputs}
    else:
        for name in outputs:
            _check_output_name(system, name)
    allowed = dict(state) | {p.name: p.symbol for p in system.parameters}
    namespace = Namespace(symbols=allowed)
    expressions = []
    for name, given in outputs.items():
        where = f"outputs.{name}"
        if isinstance(given, str):
            try:
                expression = parse_expression(given, namespace)
            except ParseError as error:
                raise ModelError(str(error), field=where, text=given) from None
        elif isinstance(given, sympy.Expr | int | float) and not isinstance(given, bool):
            expression = point_value(given, where, system, allowed)
        else:
            raise ModelError(f"expected an expression, got {type(given).__name__}", field=where)
        if expression.has(AppliedUndef):
            raise ModelError("an output may not use unspecified functions", field=where)
        expressions.append(expression)
    return tuple(str(name) for name in outputs), expressions


def _check_output_name(system: System, name: object) -> None:
    """An output's own name: an identifier that means nothing else in the model (a name
    taken would read as that thing in y = C x + D u and in every document of it)."""
    where = f"outputs.{name}"
    if not isinstance(name, str) or not is_identifier(name):
        raise ModelError(
            f"invalid output name {name!r} (a letter, then letters, digits or _)", field="outputs"
        )
    taken = {
        **{c.name: "a coordinate" for c in system.coordinates},
        **{c.q_dot.name: "a velocity" for c in system.coordinates},
        **{c.q_ddot.name: "an acceleration" for c in system.coordinates},
        **{p.name: "a parameter" for p in system.parameters},
        **{name: "an input" for name in system.input_names},
        **{f.name: "a declared function" for f in system.functions},
        **dict.fromkeys(RESERVED, "a built-in name"),
    }
    if name in taken:
        raise ModelError(f"'{name}' is {taken[name]}: give the output another name", field=where)


def point_value(
    value: object, name: str, system: System, allowed: Mapping[str, sympy.Expr] | None = None
) -> sympy.Expr:
    """A number, text (for the safe parser) or a SymPy expression over ``allowed`` names
    (default: the parameters)."""
    table = allowed if allowed is not None else {p.name: p.symbol for p in system.parameters}
    if isinstance(value, str):
        try:
            return parse_expression(value, Namespace(symbols=table))
        except ParseError as error:
            raise ModelError(str(error), field=name, text=value) from None
    if isinstance(value, bool) or not isinstance(value, int | float | sympy.Basic):
        raise ModelError(f"expected a number, text or SymPy expression, got {value!r}", field=name)
    if isinstance(value, int):
        return sympy.Integer(value)
    if isinstance(value, float):
        if not np.isfinite(value):
            raise ModelError(f"expected a finite number, got {value!r}", field=name)
        return sympy.Float(value)
    unknown = sorted(s.name for s in value.free_symbols if s.name not in table)
    if unknown:
        raise ModelError(f"unknown symbols {unknown} in the value", field=name)
    return value.xreplace({s: table[s.name] for s in value.free_symbols})

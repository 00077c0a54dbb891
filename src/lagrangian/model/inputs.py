"""Inputs: named signals (forces, torques) applied to a system from outside.

An input u is a symbol that is neither a coordinate nor a parameter; each one
produces generalized forces Q_q(q, q', t, u), added to the model's ``forces``
in Lagrange's equation

    d/dt (dL/dq_dot) - dL/dq = Q_q + sum_u Q_q^(u) - dF/dq_dot.

In a model file (an additive section of DESIGN section 2):

    [inputs]
    F = "x"                              # F is the generalized force on x: Q_x = F
    tau = {theta = "tau", x = "-tau/r"}  # or a table: coordinate -> generalized force

A force F applied at a point r(q) gives Q_q = F . dr/dq; write that out, e.g. a
horizontal force F on a pendulum bob at (l sin(theta), -l cos(theta)) is
``F = {theta = "F*l*cos(theta)"}``.  Every entry must depend on its input.  The
Python constructors take the same as ``inputs={"F": "x"}``.

Inside a :class:`~lagrangian.model.System` an input is also listed among the
parameters, real with the default value 0: the equations of motion show it, a
simulation runs with u = 0 unless it is set (``--set F=2``, ``params={"F": 2}``,
held constant), and :func:`~lagrangian.analysis.state_space` differentiates by it
(the input matrix B).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType

import sympy

from ..errors import ModelError

#: The sign and default value an input has as a parameter of the system.
INPUT_SIGN = "real"
INPUT_DEFAULT = 0.0


@dataclass(frozen=True)
class Input:
    """An input ``name`` (symbol ``symbol``) and the generalized force it produces on each
    coordinate it acts on (coordinate name -> Q_q, an expression containing ``symbol``)."""

    name: str
    symbol: sympy.Symbol
    forces: Mapping[str, sympy.Expr] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "forces", MappingProxyType(dict(self.forces)))


def input_entries(inputs: object) -> Iterator[tuple[str, str, object]]:
    """(input name, coordinate name, generalized force as given) of every entry.

    ``inputs`` maps a name to a coordinate name (the input is the generalized
    force on it) or to a table coordinate -> expression.  A wrong shape is a
    ModelError naming the field.
    """
    if not isinstance(inputs, Mapping):
        raise ModelError("expected a table of name = coordinate or {coordinate = force}",
                         field="inputs")  # fmt: skip
    for name, entry in inputs.items():
        where = f"inputs.{name}"
        if isinstance(entry, str):
            yield name, entry, name
        elif isinstance(entry, Mapping):
            if not entry:
                raise ModelError("an input acts on at least one coordinate", field=where)
            for coordinate, force in entry.items():
                yield name, coordinate, force
        else:
            raise ModelError(
                "expected the name of a coordinate or a table {coordinate = force}, got "
                f"{type(entry).__name__}",
                field=where,
            )


def input_fields(inputs: object) -> Iterator[tuple[str, object]]:
    """(field, expression) of every generalized force of ``inputs``: ``inputs.F.x``."""
    for name, coordinate, force in input_entries(inputs):
        yield f"inputs.{name}.{coordinate}", force


def input_parameters(
    inputs: object, check_new_name: Callable[[object, str], None], parameters: set[str]
):
    """The parameters that stand for the inputs (real, default 0), names checked.

    ``check_new_name(name, field)`` refuses invalid, reserved or already used
    names; ``parameters`` are the names already declared as parameters.
    """
    from .system import Parameter

    made = []
    for name in dict.fromkeys(name for name, _, _ in input_entries(inputs)):
        where = f"inputs.{name}"
        check_new_name(name, where)
        if name in parameters:
            raise ModelError(
                f"'{name}' is declared both as a parameter and as an input", field=where
            )
        made.append(Parameter(name, sympy.Symbol(name, real=True), INPUT_DEFAULT, INPUT_SIGN))
    return tuple(made)


def assemble_inputs(
    inputs: object,
    resolved: Mapping[str, sympy.Expr],
    symbols: Mapping[str, sympy.Symbol],
    coordinates: set[str],
) -> tuple[Input, ...]:
    """The :class:`Input` objects of ``inputs``, their forces taken from ``resolved``
    (field -> parsed expression) and their symbols from ``symbols``."""
    own = {name: symbols[name] for name, _, _ in input_entries(inputs)}
    for where, expression in resolved.items():
        used = [name for name, symbol in own.items() if expression.has(symbol)]
        if used and not where.startswith("inputs."):
            raise ModelError(
                f"the input '{used[0]}' may appear only in [inputs] (its generalized forces)",
                field=where,
            )
    forces: dict[str, dict[str, sympy.Expr]] = {}
    for name, coordinate, given in input_entries(inputs):
        where = f"inputs.{name}.{coordinate}"
        if coordinate not in coordinates:
            known = ", ".join(sorted(coordinates))
            raise ModelError(
                f"'{coordinate}' is not a coordinate (coordinates: {known})",
                field=where if not isinstance(inputs[name], str) else f"inputs.{name}",
            )
        force = resolved[where]
        if not force.has(symbols[name]):
            raise ModelError(
                f"the generalized force does not depend on the input '{name}'",
                field=where,
                text=given if isinstance(given, str) else str(given),
            )
        forces.setdefault(name, {})[coordinate] = force
    return tuple(Input(name, symbols[name], table) for name, table in forces.items())


def with_input_forces(
    forces: Mapping[str, sympy.Expr], inputs: tuple[Input, ...]
) -> dict[str, sympy.Expr]:
    """The model's generalized forces with every input's added, coordinate by coordinate."""
    combined = dict(forces)
    for entry in inputs:
        for coordinate, force in entry.forces.items():
            combined[coordinate] = combined.get(coordinate, sympy.Integer(0)) + force
    return combined


def without_inputs(system, values: Mapping[str, float] | None = None):
    """``system`` with its inputs held at ``values`` (default: every input 0) and no longer
    inputs or parameters: the free system that equilibria and conserved quantities are
    about.  A system without inputs is returned as it is."""
    if not system.inputs:
        return system
    names = {entry.name for entry in system.inputs}
    unknown = sorted(set(values or {}) - names)
    if unknown:
        raise ModelError(f"'{unknown[0]}' is not an input (inputs: {', '.join(sorted(names))})")
    held = {
        entry.symbol: sympy.Rational(repr(float((values or {}).get(entry.name, INPUT_DEFAULT))))
        for entry in system.inputs
    }
    forces = {}
    for coordinate, force in system.forces.items():
        force = force.xreplace(held)
        if force != 0:
            forces[coordinate] = force
    return replace(
        system,
        parameters=tuple(p for p in system.parameters if p.name not in names),
        forces=forces,
        inputs=(),
    )

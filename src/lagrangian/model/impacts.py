"""Impacts: unilateral contacts ``[[impacts]]``, each a gap g(q, t) >= 0 and a restitution e.

A contact is closed where its gap is 0; the motion keeps g >= 0.  When g reaches 0 with
g' < 0 the velocities jump by Newton's law of restitution along the gap's gradient in the
mass metric (:mod:`lagrangian.integrate.impacts`), so that g' becomes -e g'.  The model file:

    [[impacts]]
    name = "floor"          # optional: contact1, contact2, ... by default
    gap = "y"               # a function of the coordinates (and t), 0 at contact
    restitution = "e"       # a number or an expression of the parameters, 0 <= e <= 1

Checked when the model is built (a :class:`~lagrangian.errors.ModelError` naming the field):
a gap that depends on no coordinate, a restitution outside [0, 1] at the parameters'
values, an initial state where a gap is negative (the contact already penetrated), two
contacts of one name.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, replace

import sympy

from ..algebra import as_expression
from ..errors import ModelError
from ..symbols import is_identifier
from .components import ExprLike

#: A gap this far below 0 at the initial state is a penetration, not rounding.
PENETRATION_TOLERANCE = 1e-12


@dataclass(frozen=True)
class Impact:
    """A unilateral contact: ``gap`` g(q, t) >= 0 (closed at 0), ``restitution`` e in [0, 1]."""

    gap: ExprLike
    restitution: ExprLike
    name: str = ""


def impact_fields(impacts: tuple[Impact, ...], configuration, constant) -> Iterator[tuple]:
    """(field, value, what it may depend on) of each impact's expressions."""
    for i, impact in enumerate(impacts):
        yield f"impacts[{i}].gap", impact.gap, configuration
        yield f"impacts[{i}].restitution", impact.restitution, constant


def read_impact(table: object, i: int) -> Impact:
    """One ``[[impacts]]`` table of a model file as an :class:`Impact` (not yet parsed)."""
    where = f"impacts[{i}]"
    if not isinstance(table, Mapping):
        raise ModelError("expected a table", field=where)
    unknown = sorted(set(table) - {"name", "gap", "restitution"})
    if unknown:
        raise ModelError(
            "unknown key (expected one of gap, name, restitution)", field=f"{where}.{unknown[0]}"
        )
    values = {}
    for key in ("gap", "restitution"):
        if key not in table:
            raise ModelError("missing field", field=f"{where}.{key}")
        value = table[key]
        if isinstance(value, bool) or not isinstance(value, str | int | float):
            raise ModelError(
                f"expected an expression (text or number), got {type(value).__name__}",
                field=f"{where}.{key}",
            )
        values[key] = value
    name = table.get("name", "")
    if not isinstance(name, str):
        raise ModelError(f"expected a name, got {name!r}", field=f"{where}.name")
    return Impact(gap=values["gap"], restitution=values["restitution"], name=name)


def resolve_impacts(
    impacts: tuple[Impact, ...],
    resolved: Mapping[str, sympy.Expr],
    coordinates: tuple[sympy.Symbol, ...],
    taken: set[str],
) -> tuple[Impact, ...]:
    """The impacts with their parsed expressions and names (``contact1``, ... where none was
    given); a gap that depends on no coordinate, or a name that is not a new identifier
    (``taken``: the model's other names), is a ModelError naming the field."""
    result, names = [], set()
    for i, impact in enumerate(impacts):
        where = f"impacts[{i}]"
        name = impact.name or f"contact{i + 1}"
        if not is_identifier(name):
            raise ModelError(f"invalid name {name!r}", field=f"{where}.name")
        if name in names or name in taken:
            raise ModelError(f"'{name}' is declared twice", field=f"{where}.name")
        names.add(name)
        gap = resolved[f"{where}.gap"]
        if not gap.free_symbols & set(coordinates):
            raise ModelError(
                "the gap does not depend on the coordinates: it can never close",
                field=f"{where}.gap",
                text=str(impact.gap),
            )
        repeated = _repeated_factor(gap, set(coordinates))
        if repeated is not None:
            raise ModelError(
                f"the gap's factor {repeated} has a zero gradient where it closes, so the gap "
                "touches 0 without crossing it and no contact is ever seen: write a gap that "
                "crosses 0 (y, not y^2)",
                field=f"{where}.gap",
                text=str(impact.gap),
            )
        result.append(
            replace(impact, name=name, gap=gap, restitution=resolved[f"{where}.restitution"])
        )
    return tuple(result)


#: Largest gap (in operations) whose polynomial factors are searched for repeated ones.
REPEATED_FACTOR_MAX_OPS = 200


def _repeated_factor(gap: sympy.Expr, coordinates: set) -> sympy.Expr | None:
    """A factor of the gap in the coordinates raised to a power above 1 (y^2, (x - 1)^3,
    sin(theta)^2, y^2 - 2 y + 1): there the gradient is 0 where the gap is, the gap touches
    0 without changing sign (y^2 is never negative) and an event search passes it by."""
    if sympy.count_ops(gap) > REPEATED_FACTOR_MAX_OPS:
        return None
    for factor in sympy.Mul.make_args(sympy.factor_terms(gap)):
        base, exponent = factor.as_base_exp()
        if exponent.is_number and exponent > 1 and base.free_symbols & coordinates:
            return factor
    used = sorted(gap.free_symbols & coordinates, key=str)
    if gap.is_polynomial(*used):
        for base, multiplicity in sympy.sqf_list(gap, *used)[1]:
            if multiplicity > 1 and base.free_symbols & coordinates:
                return base**multiplicity
    return None


def check_restitutions(system, values: Mapping[str, object] | None = None) -> None:
    """ModelError naming ``impacts[i].restitution`` where e is outside [0, 1] at the
    parameters' defaults updated by ``values`` (numbers, or arrays of an ensemble's members);
    an e whose parameters have no value yet is checked when they are given."""
    if not system.impacts:
        return
    import numpy as np

    numbers = {p.symbol: p.default for p in system.parameters if p.default is not None}
    given = {p.symbol: values[p.name] for p in system.parameters if p.name in (values or {})}
    numbers.update(given)
    for i, impact in enumerate(system.impacts):
        e = impact.restitution
        if not e.free_symbols <= set(numbers):
            continue
        function = sympy.lambdify(sorted(e.free_symbols, key=str), e, modules="numpy")
        value = np.asarray(function(*(numbers[s] for s in sorted(e.free_symbols, key=str))))
        bad = ~((value >= 0.0) & (value <= 1.0))
        if np.any(bad):
            shown = float(np.ravel(value)[int(np.argmax(np.ravel(bad)))])
            raise ModelError(
                f"the restitution must be from 0 to 1, not {shown:g}",
                field=f"impacts[{i}].restitution",
                text=str(e),
            )


def check_initial_gaps(system, initial: Mapping[str, float], params: Mapping[str, float]) -> None:
    """ModelError naming ``impacts[i].gap`` where the gap is negative at the initial state
    (``initial`` over the model's [initial]; missing entries 0) and the parameters' values
    (``params`` over the defaults), at t = 0: the contact would start penetrated."""
    if not system.impacts:
        return  # nothing to check: the state's Floats cost 5 ms for a 20-link chain
    numbers: dict[sympy.Symbol, sympy.Float] = {system.time: sympy.Float(0)}
    state = {**system.initial, **initial}
    for c in system.coordinates:
        numbers[c.q] = sympy.Float(float(state.get(c.name, 0.0)))
    values = {**system.parameter_values, **params}
    numbers.update(
        {
            p.symbol: sympy.Float(float(values[p.name]))
            for p in system.parameters
            if p.name in values
        }
    )
    for i, impact in enumerate(system.impacts):
        if not impact.gap.free_symbols <= set(numbers):
            continue
        try:
            value = float(as_expression(impact.gap).xreplace(numbers).evalf())
        except (TypeError, ValueError):  # a declared function: checked when it is defined
            continue
        if math.isfinite(value) and value < -PENETRATION_TOLERANCE:
            raise ModelError(
                f"the initial state penetrates the contact '{impact.name}': its gap is "
                f"{value:.6g} < 0",
                field=f"impacts[{i}].gap",
                text=str(impact.gap),
            )


def refuse_impacts(system, what: str) -> None:
    """ModelError where ``system`` has contacts and ``what`` (a kind of run) would integrate
    through them as if they were not there: only ``simulate`` (and what draws its runs)
    stops at impacts."""
    if getattr(system, "impacts", ()):
        raise ModelError(
            f"{what} does not take contacts yet ([[impacts]]): its runs would pass through "
            "them; simulate, plot and animate do",
            source=getattr(system, "source", None),
            field="impacts",
        )

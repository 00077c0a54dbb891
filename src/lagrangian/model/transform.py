"""Point transformations q = phi(q', t): the same system in other coordinates.

Lagrange's equations keep their form under q = phi(q', t) (worked examples,
summary): L'(q', q'', t) = L(phi, dphi/dt, t) with the velocities transformed by
the chain rule, dq_i/dt = sum_j dphi_i/dq'_j q'_j' + dphi_i/dt, and the
generalized forces transformed as a covector, Q'_j = sum_i Q_i dphi_i/dq'_j.
"""

from __future__ import annotations

import random
from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np
import sympy

from ..algebra import tidy_in_velocities
from ..errors import ModelError, ParseError
from ..parsing import DeclaredFunction, Namespace, parse_expression, referenced_names
from ..symbols import Coordinate, parameter_symbol
from .components import ExprLike, RigidBody
from .naming import coordinates_named
from .system import Parameter, System


def change_coordinates(
    system: System,
    coordinates: Sequence[str],
    substitution: Mapping[str, ExprLike],
    *,
    name: str | None = None,
) -> System:
    """``system`` in the new ``coordinates``, given each old coordinate as a function of them.

    >>> polar = cartesian.change_coordinates(["r", "theta"],  # doctest: +SKIP
    ...     {"x": "r*cos(theta)", "y": "r*sin(theta)"})
    """
    new = coordinates_named(tuple(coordinates))
    old_names = set(system.coordinate_names)
    if set(substitution) != old_names:
        missing = sorted(old_names - set(substitution))
        extra = sorted(set(substitution) - old_names)
        raise ModelError(
            f"give every old coordinate exactly once (missing {missing}, unknown {extra})",
            field="substitution",
        )
    if len(new) != len(system.coordinates):
        raise ModelError(
            f"{len(new)} new coordinates for {len(system.coordinates)} old ones",
            field="coordinates",
        )
    clash = {c.name for c in new} & set(system.parameter_names)
    if clash:
        raise ModelError(
            f"new coordinates clash with parameters: {sorted(clash)}", field="coordinates"
        )

    time = system.time
    parameters = system.parameters + _new_parameters(system, new, substitution)
    namespace = Namespace(
        symbols={
            "t": time,
            **{c.name: c.q for c in new},
            **{p.name: p.symbol for p in parameters},
        },
        functions={f.name: DeclaredFunction(f.function, f.arguments) for f in system.functions},
    )
    phi = {}
    for old in system.coordinates:
        value = substitution[old.name]
        where = f"substitution.{old.name}"
        phi[old] = _expression(value, namespace, where)
    _check_invertible(phi, new)

    mapping = {}
    for old, expr in phi.items():
        mapping[old.q] = expr
        mapping[old.q_dot] = sum(
            (sympy.diff(expr, c.q) * c.q_dot for c in new), sympy.diff(expr, time)
        )
    velocities = [c.q_dot for c in new]
    state = (time, *(c.q for c in new))

    def move(expr: sympy.Expr) -> sympy.Expr:
        """The expression in the new coordinates (a simultaneous substitution), tidied."""
        return tidy_in_velocities(expr.xreplace(mapping), velocities, state)

    def covector(table) -> dict[str, sympy.Expr]:
        """Q' = J^T Q: the virtual work Q . dq is the same in both coordinates."""
        moved = {}
        for c in new:
            force = move(
                sum(
                    (
                        table.get(old.name, sympy.Integer(0)) * sympy.diff(phi[old], c.q)
                        for old in system.coordinates
                    ),
                    sympy.Integer(0),
                )
            )
            if force != 0:
                moved[c.name] = force
        return moved

    forces = covector(system.forces)
    return replace(
        system,
        name=name or system.name,
        units=None,  # the new coordinates' units are not known
        spec=None,
        linkage=None,  # its poses and reactions are in the old coordinates
        coordinates=new,
        parameters=parameters,
        lagrangian=move(system.lagrangian),
        kinetic=None if system.kinetic is None else move(system.kinetic),
        potential=None if system.potential is None else move(system.potential),
        functions=tuple(
            replace(f, arguments=tuple(move(a) for a in f.arguments)) for f in system.functions
        ),
        forces=forces,
        inputs=tuple(replace(u, forces=covector(u.forces)) for u in system.inputs),
        dissipation=move(system.dissipation),
        constraints=tuple(move(c) for c in system.constraints),
        particles=tuple(
            replace(p, position=tuple(move(x) for x in p.position)) for p in system.particles
        ),
        bodies=tuple(_moved_body(b, move) for b in system.bodies),
        springs=tuple(
            replace(s, ends=tuple(tuple(move(x) for x in end) for end in s.ends))
            for s in system.springs
        ),
        initial={},
    )


def _moved_body(body, move):
    """A planar or 3-D body with every expression of its geometry moved."""
    if isinstance(body, RigidBody):
        return replace(
            body,
            position=tuple(move(x) for x in body.position),
            euler=None if body.euler is None else tuple(move(a) for a in body.euler),
            rotation=tuple(tuple(move(x) for x in row) for row in body.rotation),
        )
    return replace(body, center=tuple(move(x) for x in body.center), angle=move(body.angle))


def _new_parameters(
    system: System, new: Sequence[Coordinate], substitution: Mapping[str, ExprLike]
) -> tuple[Parameter, ...]:
    """Names the transformation introduces (a frame's angular velocity): positive parameters."""
    known = {"t", *system.parameter_names, *(c.name for c in new)}
    known |= {f.name for f in system.functions}
    found: set[str] = set()
    for old, value in substitution.items():
        if isinstance(value, str):
            try:
                found |= referenced_names(value).symbols
            except ParseError as error:
                raise ModelError(str(error), field=f"substitution.{old}", text=value) from None
        elif isinstance(value, sympy.Expr):
            found |= {s.name for s in value.free_symbols}
    return tuple(
        Parameter(name, parameter_symbol(name, positive=True)) for name in sorted(found - known)
    )


def _expression(value: ExprLike, namespace: Namespace, where: str) -> sympy.Expr:
    if isinstance(value, str):
        try:
            return parse_expression(value, namespace)
        except ParseError as error:
            raise ModelError(str(error), field=where, text=value) from None
    if isinstance(value, int | float) and not isinstance(value, bool):
        return sympy.Rational(repr(value)) if isinstance(value, float) else sympy.Integer(value)
    if isinstance(value, sympy.Expr):
        table = namespace.symbols
        unknown = [s.name for s in value.free_symbols if s.name not in table]
        if unknown:
            raise ModelError(f"unknown symbol '{unknown[0]}'", field=where, text=str(value))
        return value.xreplace({s: table[s.name] for s in value.free_symbols})
    raise ModelError(f"expected an expression, got {type(value).__name__}", field=where)


def _check_invertible(phi: Mapping[Coordinate, sympy.Expr], new: Sequence[Coordinate]) -> None:
    """The Jacobian dphi/dq' must be regular at a generic point."""
    jacobian = sympy.Matrix([[sympy.diff(expr, c.q) for c in new] for expr in phi.values()])
    rng = random.Random(3)
    values = {s: sympy.Float(rng.uniform(0.3, 1.3)) for s in jacobian.free_symbols}
    try:
        numeric = np.array(jacobian.xreplace(values).evalf(), dtype=float)
    except (TypeError, ValueError):
        return
    if np.linalg.matrix_rank(numeric) < len(new):
        raise ModelError(
            "the transformation is not invertible (its Jacobian is singular)", field="substitution"
        )

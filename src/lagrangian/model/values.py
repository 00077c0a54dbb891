"""The values a model's parameters may take, checked wherever a value is given.

A model is built with its parameters' default values, and the equations are
derived with their assumed signs (a positive m makes sqrt(m**2) = m) and, for a
3-D body, with an inertia that some body has (principal moments not negative,
within the triangle inequalities).  A value given later in place of a default
(``--set``, ``--at``, ``params=...``, an ensemble's grid) must meet the same
conditions, or the results are silently wrong for it: :func:`check_parameter_values`
applies the model file's own checks (:data:`SIGN_BREAKS`, which the file's entries
use too, and :func:`~lagrangian.model.rigid_body.check_inertia`) to the values given.

Whatever sign a parameter is declared with, the mass of each particle and body must be
positive (and a planar body's moment of inertia not negative): :func:`check_masses`,
applied to the defaults when the model is built and to every value given later.  A
negative mass gives equations with no physics in them, a zero one a singular mass matrix.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from dataclasses import replace

import numpy as np
import sympy

from ..errors import ModelError
from .components import RigidBody, RigidBody2D
from .impacts import check_restitutions
from .rigid_body import check_inertia
from .system import System

#: Per assumed sign: which values break it (elementwise on arrays), and the range to say.
SIGN_BREAKS: Mapping[str, Callable[[np.ndarray], np.ndarray]] = {
    "positive": lambda values: values <= 0,
    "nonnegative": lambda values: values < 0,
    "negative": lambda values: values >= 0,
}
SIGN_RANGE = {"positive": "> 0", "nonnegative": ">= 0", "negative": "< 0"}


def check_parameter_value(name: str, values: float | np.ndarray, sign: str) -> None:
    """ModelError naming the first of ``values`` (one or an array) of parameter ``name``
    that is not finite or breaks its assumed ``sign``."""
    values = np.ravel(np.asarray(values, dtype=float))
    bad = ~np.isfinite(values)
    if bad.any():
        value = values[int(np.argmax(bad))]
        raise ModelError(f"parameter {name} = {value:g} is not a finite number")
    breaks = SIGN_BREAKS.get(sign)
    bad = breaks(values) if breaks is not None else np.zeros(values.shape, bool)
    if bad.any():
        value = values[int(np.argmax(bad))]
        raise ModelError(
            f"parameter {name} = {value:g} breaks the model's assumption that {name} is "
            f"{sign} (the equations were derived with it): give a value {SIGN_RANGE[sign]}, "
            f'or declare {name} = {{value = ..., sign = "real"}} in the model'
        )


def check_parameter_values(system: System, values: Mapping[str, float | np.ndarray]) -> None:
    """The model file's checks of its parameters, at ``values`` in place of the defaults.

    ``values`` maps parameter names to a number or to an array of them (an ensemble's
    members: the arrays broadcast together).  Each value must be finite and keep its
    parameter's assumed sign, and every 3-D body whose inertia uses a given parameter
    must have an inertia some body has.  A ModelError names the first value that fails.
    """
    parameters = {p.name: p for p in system.parameters}
    for name, given in values.items():
        if name not in parameters:
            known = ", ".join(parameters) or "none"
            raise ModelError(f"unknown parameter '{name}' (parameters: {known})")
        check_parameter_value(name, given, parameters[name].sign)
    for i, body in enumerate(system.bodies):
        if isinstance(body, RigidBody):
            _check_body(system, body, f"bodies[{i}].inertia", values)
    check_masses(system, values)
    check_restitutions(system, values)


def with_values(system: System, values: Mapping[str, float]) -> System:
    """``system`` with ``values`` as the default values of its parameters, checked as
    values given in place of the defaults are (:func:`check_parameter_values`): what
    ``analyze --set`` is about, and where its numerical results are evaluated."""
    check_parameter_values(system, values)
    return replace(
        system,
        parameters=tuple(
            replace(p, default=float(values[p.name])) if p.name in values else p
            for p in system.parameters
        ),
    )


def check_masses(system: System, values: Mapping[str, float | np.ndarray] | None = None) -> None:
    """ModelError unless every particle's and body's mass is > 0 (and a planar body's
    moment of inertia >= 0) at the parameters' defaults, ``values`` in their place.

    Without ``values`` (the model being built) the defaults are checked, and the error
    names the parameter's entry when the mass uses one parameter: ``parameters.m``.
    """
    given_any = bool(values)
    values = values or {}
    defaults = _defaults(system)  # once: a large model has a mass per parameter or two
    for field, what, expression, sign in masses(system):
        free = expression.free_symbols  # only these are replaced: a Float for each
        used = sorted(s.name for s in free)
        names = [name for name in used if name in values]
        if given_any and not names:
            continue  # checked at the defaults when the model was built
        for at, shown in _combinations(system, names, values, defaults):
            value = expression.xreplace({k: sympy.Float(at[k]) for k in free if k in at})
            if not (value.is_number and value.is_real) or not SIGN_BREAKS[sign](float(value)):
                continue
            if not shown:  # the defaults
                shown = ", ".join(f"{n} = {system.parameter_values[n]:g}" for n in used)
            formula = f" ({field} = {expression})" if expression.free_symbols else ""
            at_values = f" with {shown}" if shown else ""
            raise ModelError(
                f"{what}{formula} is {float(value):g}{at_values}: it must be {SIGN_RANGE[sign]}",
                field=f"parameters.{used[0]}" if len(used) == 1 and not names else None,
            )


def masses(system: System) -> Iterator[tuple[str, str, sympy.Expr, str]]:
    """(field, what it is, expression, sign it must have) of each mass and planar inertia:
    the particles' masses, then each body's mass (and a planar body's moment of inertia),
    in the model's order (the page checks a value given to it by the same rule)."""
    for i, particle in enumerate(system.particles):
        yield f"particles[{i}].mass", f"the mass of '{particle.name}'", particle.mass, "positive"
    for i, body in enumerate(system.bodies):
        yield f"bodies[{i}].mass", f"the mass of '{body.name}'", body.mass, "positive"
        if isinstance(body, RigidBody2D):
            what = f"the moment of inertia of '{body.name}'"
            yield f"bodies[{i}].inertia", what, body.inertia, "nonnegative"


def check_parameter_expressions(system: System, given: Mapping[str, sympy.Expr]) -> None:
    """:func:`check_parameter_values` of parameters given as SymPy expressions (an
    operating point's ``theta = pi, M = 2*m``): each evaluated at the other parameters'
    values (given numbers first, then defaults); one that is not a real number there
    (a symbol without a value) is left to the symbolic work."""
    symbols = {p.name: p.symbol for p in system.parameters}
    known = {symbols[n]: sympy.Float(v) for n, v in system.parameter_values.items()}
    known |= {symbols[n]: v for n, v in given.items() if v.is_number}
    numbers = {}
    for name, value in given.items():
        number = value.xreplace(known)
        if number.is_number and number.is_real:
            numbers[name] = float(number)
    check_parameter_values(system, numbers)


def _check_body(
    system: System, body: RigidBody, field: str, values: Mapping[str, float | np.ndarray]
) -> None:
    """``check_inertia`` of ``body`` at each distinct combination of the given values of
    the parameters its inertia uses (the defaults for the others)."""
    used = {s.name for row in body.inertia for x in row for s in x.free_symbols}
    names = sorted(used & set(values))
    if not names:
        return  # checked at the defaults when the model was built
    for at, given in _combinations(system, names, values):
        try:
            check_inertia(body.inertia, at, field)
        except ModelError as error:
            raise ModelError(f"{error.message} (with {given})", field=field) from None


def _defaults(system: System) -> dict[sympy.Symbol, float]:
    """{symbol: default value} of the parameters that have one."""
    symbols = {p.name: p.symbol for p in system.parameters}
    return {symbols[n]: v for n, v in system.parameter_values.items()}


def _combinations(
    system: System,
    names: list[str],
    values: Mapping[str, float | np.ndarray],
    defaults: dict[sympy.Symbol, float] | None = None,
) -> Iterator[tuple[dict[sympy.Symbol, float], str]]:
    """Each distinct combination of the given values of the parameters ``names`` (arrays
    broadcast together), the defaults for the others (``defaults``, where made before):
    ({symbol: value}, "a = 1, b = 2")."""
    defaults = _defaults(system) if defaults is None else defaults
    if not names:
        yield defaults, ""
        return
    symbols = {p.name: p.symbol for p in system.parameters}
    columns = np.broadcast_arrays(*(np.asarray(values[n], dtype=float) for n in names))
    for row in np.unique(np.stack([np.ravel(c) for c in columns], axis=1), axis=0):
        at = defaults | {symbols[n]: float(v) for n, v in zip(names, row, strict=True)}
        yield at, ", ".join(f"{n} = {v:g}" for n, v in zip(names, row, strict=True))

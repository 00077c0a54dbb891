"""The values a model's parameters may take, checked wherever a value is given.

A model is built with its parameters' default values, and the equations are
derived with their assumed signs (a positive m makes sqrt(m**2) = m) and, for a
3-D body, with an inertia that some body has (principal moments not negative,
within the triangle inequalities).  A value given later in place of a default
(``--set``, ``--at``, ``params=...``, an ensemble's grid) must meet the same
conditions, or the results are silently wrong for it: :func:`check_parameter_values`
applies the model file's own checks (:data:`SIGN_BREAKS`, which the file's entries
use too, and :func:`~lagrangian.model.rigid_body.check_inertia`) to the values given.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np
import sympy

from ..errors import ModelError
from .components import RigidBody
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
    symbols = {p.name: p.symbol for p in system.parameters}
    defaults = {symbols[n]: v for n, v in system.parameter_values.items()}
    columns = np.broadcast_arrays(*(np.asarray(values[n], dtype=float) for n in names))
    for row in np.unique(np.stack([np.ravel(c) for c in columns], axis=1), axis=0):
        at = defaults | {symbols[n]: float(v) for n, v in zip(names, row, strict=True)}
        try:
            check_inertia(body.inertia, at, field)
        except ModelError as error:
            given = ", ".join(f"{n} = {v:g}" for n, v in zip(names, row, strict=True))
            raise ModelError(f"{error.message} (with {given})", field=field) from None

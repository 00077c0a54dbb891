"""3-D rigid bodies (:class:`~lagrangian.model.components.RigidBody`): their fields, checks
and the velocities their kinetic energy is made of.

A body of mass m, centre of mass r_c(q, t), inertia tensor I about the centre of
mass in the body frame and orientation R(q, t) has (König's theorem)

    T = m |r_c'|^2 / 2 + omega^T I omega / 2,

omega the body-frame angular velocity (:mod:`.rotation`): both terms are
quadratic forms of velocities linear in q', which :mod:`.energy` assembles as
it does for particles (:func:`rotation_piece`).  Checks made when the model is
built, each an error naming the field: the shape of every field; a known Euler
convention; a rotation matrix that is orthogonal with det 1 (at random points);
principal moments that are not negative and satisfy the triangle inequalities
I1 <= I2 + I3 (and cyclically) at the parameters' values; a symmetric tensor.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import replace

import numpy as np
import sympy

from ..algebra import as_expression, is_zero
from ..errors import ModelError
from .components import RigidBody
from .rotation import (
    CONVENTIONS,
    AngularVelocity,
    euler_angular_velocity,
    euler_matrix,
    matrix_angular_velocity,
    rotation_problem,
)

#: Relative tolerance of the triangle inequalities and of the symmetry of a tensor.
PHYSICAL_TOLERANCE = 1e-12


def _is_sequence(value: object) -> bool:
    return isinstance(value, Sequence) and not isinstance(value, str)


def _is_matrix(value: object) -> bool:
    return (
        _is_sequence(value)
        and len(value) == 3
        and all(_is_sequence(row) and len(row) == 3 for row in value)
    )


def body_fields(
    body: RigidBody, where: str, constant: frozenset[str], configuration: frozenset[str]
) -> Iterator[tuple[str, object, frozenset[str]]]:
    """Every expression field of ``body`` (named ``where``), after checking the shapes."""
    yield f"{where}.mass", body.mass, constant
    if not _is_sequence(body.position) or len(body.position) != 3:
        raise ModelError("a 3-D body's position has 3 components", field=f"{where}.position")
    for k, x in enumerate(body.position):
        yield f"{where}.position[{k}]", x, configuration
    inertia = body.inertia
    if _is_matrix(inertia):
        for j, row in enumerate(inertia):
            for k, x in enumerate(row):
                yield f"{where}.inertia[{j}][{k}]", x, constant
    elif _is_sequence(inertia) and len(inertia) == 3 and not any(map(_is_sequence, inertia)):
        for k, x in enumerate(inertia):
            yield f"{where}.inertia[{k}]", x, constant
    else:
        raise ModelError(
            "expected the 3 principal moments [I1, I2, I3] or a 3 x 3 tensor",
            field=f"{where}.inertia",
        )
    if (body.euler is None) == (body.rotation is None):
        raise ModelError(
            "give the orientation by Euler angles (euler, convention) or by a rotation "
            "matrix (rotation), one of them",
            field=f"{where}.orientation",
        )
    if body.euler is not None:
        if body.convention not in CONVENTIONS:
            raise ModelError(
                f"unknown convention {body.convention!r} (expected one of "
                f"{', '.join(sorted(CONVENTIONS))})",
                field=f"{where}.orientation.convention",
            )
        if not _is_sequence(body.euler) or len(body.euler) != 3:
            raise ModelError("expected 3 Euler angles", field=f"{where}.orientation.euler")
        for k, x in enumerate(body.euler):
            yield f"{where}.orientation.euler[{k}]", x, configuration
    else:
        if not _is_matrix(body.rotation):
            raise ModelError(
                "expected a 3 x 3 matrix (3 rows of 3)", field=f"{where}.orientation.rotation"
            )
        for j, row in enumerate(body.rotation):
            for k, x in enumerate(row):
                yield f"{where}.orientation.rotation[{j}][{k}]", x, configuration


def resolve_body(
    body: RigidBody,
    where: str,
    resolved: Mapping[str, sympy.Expr],
    values: Mapping[sympy.Symbol, float],
    symbols: Sequence[sympy.Symbol],
) -> RigidBody:
    """``body`` with every field a SymPy expression, ``inertia`` the full tensor and
    ``rotation`` given; checked (see the module docstring).  ``values``: the
    parameters' default values; ``symbols``: what R may depend on (q, t, parameters)."""
    if _is_matrix(body.inertia):
        tensor = tuple(
            tuple(resolved[f"{where}.inertia[{j}][{k}]"] for k in range(3)) for j in range(3)
        )
    else:
        moments = [resolved[f"{where}.inertia[{k}]"] for k in range(3)]
        zero = sympy.Integer(0)
        tensor = tuple(tuple(moments[j] if j == k else zero for k in range(3)) for j in range(3))
    check_inertia(tensor, values, f"{where}.inertia")
    if body.euler is not None:
        euler = tuple(resolved[f"{where}.orientation.euler[{k}]"] for k in range(3))
        matrix = euler_matrix(euler, body.convention)
    else:
        euler = None
        field = f"{where}.orientation.rotation"
        matrix = sympy.Matrix(3, 3, lambda j, k: resolved[f"{field}[{j}][{k}]"])
        problem = rotation_problem(matrix, symbols)
        if problem is not None:
            raise ModelError(f"the matrix {problem}", field=field)
    return replace(
        body,
        mass=resolved[f"{where}.mass"],
        position=tuple(resolved[f"{where}.position[{k}]"] for k in range(3)),
        inertia=tensor,
        euler=euler,
        rotation=tuple(tuple(matrix[j, k] for k in range(3)) for j in range(3)),
    )


def _numbers(expressions, values, field: str) -> np.ndarray | None:
    """The expressions at the parameters' values, or None where one has no value; a value
    that is not a finite double is an error (the checks compare numbers: inf and nan pass
    every comparison that refuses)."""
    try:
        numbers = np.array([float(as_expression(x).xreplace(values)) for x in expressions])
    except (TypeError, ValueError):
        return None
    if not np.all(np.isfinite(numbers)):
        k = int(np.argmin(np.isfinite(numbers)))
        raise ModelError(
            f"the inertia {expressions[k]} = {numbers[k]:g} at the parameters' values is not "
            "a finite number",
            field=field,
        )
    return numbers


def check_inertia(
    tensor: Sequence[Sequence[sympy.Expr]], values: Mapping[sympy.Symbol, float], field: str
) -> None:
    """ModelError (naming ``field``) unless the inertia ``tensor`` (3 x 3, body frame) is
    one some body has at the parameter ``values``: symmetric, principal moments not
    negative and within the triangle inequalities.  Entries without a value are not
    judged numerically.  The model's own check, and that of every value given later
    (:func:`lagrangian.model.values.check_parameter_values`)."""
    diagonal = all(tensor[j][k] == 0 for j in range(3) for k in range(3) if j != k)
    if diagonal:  # the principal moments themselves: checked symbolically as well
        _check_moments([tensor[k][k] for k in range(3)], values, field)
    else:
        _check_tensor(tensor, values, field)


def _check_moments(moments, values, field: str) -> None:
    for k, moment in enumerate(moments):
        if moment.is_negative:
            raise ModelError(f"principal moment {k + 1} ({moment}) is negative", field=field)
    numbers = _numbers(moments, values, field)
    if numbers is None:
        return
    if np.any(numbers < 0):
        k = int(np.argmin(numbers))
        raise ModelError(
            f"principal moment {k + 1} is negative ({moments[k]} = {numbers[k]:g})", field=field
        )
    _check_triangle(numbers, field)


def _check_triangle(numbers: np.ndarray, field: str) -> None:
    total = float(numbers.sum())
    for k in range(3):
        if numbers[k] > total - numbers[k] + PHYSICAL_TOLERANCE * max(total, 1.0):
            raise ModelError(
                f"the principal moments {', '.join(f'{x:g}' for x in numbers)} violate the "
                f"triangle inequality (I{k + 1} > the sum of the other two): no body has them",
                field=field,
            )


def _check_tensor(tensor, values, field: str) -> None:
    for j in range(3):
        for k in range(j + 1, 3):
            if not is_zero(tensor[j][k] - tensor[k][j]):
                raise ModelError(
                    f"the tensor is not symmetric (entries [{j}][{k}] and [{k}][{j}] differ)",
                    field=field,
                )
    numbers = _numbers([x for row in tensor for x in row], values, field)
    if numbers is None:
        return
    moments = np.linalg.eigvalsh(numbers.reshape(3, 3))
    scale = max(float(np.abs(moments).max()), 1e-300)
    if moments.min() < -PHYSICAL_TOLERANCE * scale:
        raise ModelError(
            f"the tensor has a negative principal moment ({moments.min():g})", field=field
        )
    _check_triangle(np.clip(moments, 0, None), field)


def rotation_matrix(body: RigidBody) -> sympy.Matrix:
    """R of a built body (body frame -> space frame)."""
    return sympy.Matrix(body.rotation)


def inertia_matrix(body: RigidBody) -> sympy.Matrix:
    """The inertia tensor about the centre of mass, body frame, of a built body."""
    return sympy.Matrix(body.inertia)


def angular_velocity(
    body: RigidBody, coordinates: Sequence[sympy.Symbol], time: sympy.Symbol, *, trig: bool = True
) -> AngularVelocity:
    """omega_body of a built body: the Euler closed form, else from R^T dR/dt (``trig``:
    with the trigonometric search when tidying its entries)."""
    if body.euler is not None:
        return euler_angular_velocity(body.euler, body.convention, coordinates, time)
    return matrix_angular_velocity(rotation_matrix(body), coordinates, time, trig=trig)


def rotation_piece(
    body: RigidBody, coordinates: Sequence[sympy.Symbol], time: sympy.Symbol, *, trig: bool = True
) -> tuple[sympy.Matrix, sympy.Matrix, sympy.Matrix]:
    """(I, A, b) with T_rot = (A q' + b)^T I (A q' + b) / 2 (omega_body = A q' + b)."""
    omega = angular_velocity(body, coordinates, time, trig=trig)
    return inertia_matrix(body), sympy.Matrix(omega.rates), sympy.Matrix(omega.explicit)


def moving_with(body: RigidBody) -> tuple[sympy.Expr, ...]:
    """The expressions whose coordinates the body moves with (for the work estimate)."""
    orientation = body.euler if body.euler is not None else sum(body.rotation, ())
    return (*body.position, *orientation)

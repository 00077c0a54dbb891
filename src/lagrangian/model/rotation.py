"""Rotation matrices and the body-frame angular velocity of a rigid body.

A body's orientation is the rotation R(q, t) that takes body-frame vectors to
the space frame (r_space = r_center + R r_body).  Its angular velocity in the
body frame is the axial vector of the skew-symmetric matrix

    Omega = R^T dR/dt,   omega_body = (Omega_32, Omega_13, Omega_21),

and, since dR/dt = sum_i dR/dq_i q_i' + dR/dt, it is linear in the velocities:
omega_body = A(q, t) q' + b(q, t) (:class:`AngularVelocity`).

Euler angles in a named convention (:data:`CONVENTIONS`): "zxz" means
R = R_z(a1) R_x(a2) R_z(a3), rotations about the moving (body) axes, so the
body-frame angular velocity has the closed form

    omega_body = R_3(a3)^T R_2(a2)^T e_1 a1' + R_3(a3)^T e_2 a2' + e_3 a3'

(e_k the unit vector of the k-th axis of the sequence; Goldstein, Classical
Mechanics, 3rd ed., section 4.9).  "zyx" is the Tait-Bryan yaw-pitch-roll sequence
(aircraft), regular at zero pitch; "zxz" is the classical convention of the
heavy top, singular at a2 = 0.  A matrix given by its entries is checked to be
a rotation numerically (R^T R = 1 and det R = 1 at random points, see
:func:`rotation_problem`) and its angular velocity is formed from R^T dR/dq_i,
each entry tidied (:func:`~lagrangian.algebra.tidy`, bounded).

>>> a, b, c = sympy.symbols("a b c")
>>> euler_matrix((a, b, c), "zyx")[2, 0]
-sin(b)
>>> sorted(CONVENTIONS)[:4]
['xyx', 'xyz', 'xzx', 'xzy']
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass

import sympy

from ..algebra import tidy

AXES = {"x": 0, "y": 1, "z": 2}
#: The twelve Euler-angle sequences: three axes, no two neighbours equal (proper Euler
#: angles such as zxz, and Tait-Bryan angles such as zyx).
CONVENTIONS = frozenset(a + b + c for a in "xyz" for b in "xyz" for c in "xyz" if a != b and b != c)
#: Largest deviation of R^T R from the identity (and of det R from 1) accepted at
#: a random point, relative to 1.
ORTHOGONALITY_TOLERANCE = 1e-9
#: Random points at which a given rotation matrix is checked.
CHECK_POINTS = 5


def axis_rotation(axis: int, angle: sympy.Expr) -> sympy.Matrix:
    """The rotation by ``angle`` about the coordinate axis ``axis`` (0, 1, 2), right-handed."""
    c, s = sympy.cos(angle), sympy.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    matrix = sympy.eye(3)
    matrix[i, i], matrix[i, j], matrix[j, i], matrix[j, j] = c, -s, s, c
    return matrix


def euler_matrix(angles: Sequence[sympy.Expr], convention: str) -> sympy.Matrix:
    """R = R_a(angle 1) R_b(angle 2) R_c(angle 3) for the convention "abc"."""
    result = sympy.eye(3)
    for name, angle in zip(convention, angles, strict=True):
        result = result * axis_rotation(AXES[name], angle)
    return result


def euler_rate_matrix(angles: Sequence[sympy.Expr], convention: str) -> sympy.Matrix:
    """E with omega_body = E (a1', a2', a3'): the columns R_3^T R_2^T e_1, R_3^T e_2, e_3."""
    first, second, third = (AXES[name] for name in convention)
    r2 = axis_rotation(second, angles[1])
    r3 = axis_rotation(third, angles[2])
    unit = sympy.eye(3)
    columns = [r3.T * r2.T * unit[:, first], r3.T * unit[:, second], unit[:, third]]
    return sympy.Matrix.hstack(*columns)


@dataclass(frozen=True)
class AngularVelocity:
    """omega_body = ``rates`` q' + ``explicit``: ``rates`` (3, n), ``explicit`` (3,)."""

    rates: sympy.ImmutableMatrix
    explicit: sympy.ImmutableMatrix

    def expression(self, velocities: Sequence[sympy.Symbol]) -> sympy.Matrix:
        """The three components as expressions of (q, q', t)."""
        return self.rates * sympy.Matrix(velocities) + self.explicit


def euler_angular_velocity(
    angles: Sequence[sympy.Expr],
    convention: str,
    coordinates: Sequence[sympy.Symbol],
    time: sympy.Symbol,
) -> AngularVelocity:
    """omega_body of Euler angles a_k(q, t): E(a) a', a' = sum_i da/dq_i q_i' + da/dt."""
    rate = euler_rate_matrix(angles, convention)
    jacobian = sympy.Matrix([[sympy.diff(a, q) for q in coordinates] for a in angles])
    explicit = sympy.Matrix([sympy.diff(a, time) for a in angles])
    rates = (rate * jacobian).applyfunc(sympy.expand)
    return AngularVelocity(
        sympy.ImmutableMatrix(rates), sympy.ImmutableMatrix((rate * explicit).applyfunc(tidy))
    )


def matrix_angular_velocity(
    rotation: sympy.Matrix,
    coordinates: Sequence[sympy.Symbol],
    time: sympy.Symbol,
    *,
    trig: bool = True,
) -> AngularVelocity:
    """omega_body from R^T dR/dq_i (column i of ``rates``) and R^T dR/dt, tidied entry by
    entry (``trig``: with the trigonometric search, bounded but ~10 ms an entry)."""
    rotation = sympy.Matrix(rotation)

    def axial(derivative: sympy.Matrix) -> list[sympy.Expr]:
        if derivative.is_zero_matrix:
            return [sympy.Integer(0)] * 3
        omega = rotation.T * derivative
        # the skew part only: (Omega_32 - Omega_23)/2 equals Omega_32 for a rotation
        pairs = ((2, 1), (0, 2), (1, 0))
        return [tidy((omega[i, j] - omega[j, i]) / 2, trig=trig) for i, j in pairs]

    columns = [axial(rotation.diff(q)) for q in coordinates]
    rates = sympy.Matrix(3, len(coordinates), lambda k, i: columns[i][k])
    return AngularVelocity(
        sympy.ImmutableMatrix(rates), sympy.ImmutableMatrix(axial(rotation.diff(time)))
    )


def rotation_problem(
    rotation: sympy.Matrix, symbols: Sequence[sympy.Symbol], *, seed: int = 20261125
) -> str | None:
    """Why ``rotation`` is not a rotation matrix (checked at random values of
    ``symbols``), or None.  Positive symbols get values in (0.5, 2), others in (-2, 2)."""
    import numpy as np

    rng = random.Random(seed)
    arguments = list(symbols)
    checked = 0
    try:
        function = sympy.lambdify(arguments, sympy.Matrix(rotation), "numpy")
    except Exception as error:  # an unspecified function cannot be evaluated
        return f"cannot be evaluated ({error})"
    for _ in range(CHECK_POINTS):
        values = [
            rng.uniform(0.5, 2.0) if s.is_positive else rng.uniform(-2.0, 2.0) for s in arguments
        ]
        try:
            with np.errstate(all="ignore"):  # a point outside the domain is skipped below
                matrix = np.array(function(*values), dtype=float)
        except (TypeError, ValueError, ZeroDivisionError):
            return "cannot be evaluated to numbers"
        if not np.all(np.isfinite(matrix)):
            continue  # a point outside the domain: try another
        deviation = float(np.abs(matrix.T @ matrix - np.eye(3)).max())
        if deviation > ORTHOGONALITY_TOLERANCE:
            point = ", ".join(f"{s}={v:.3g}" for s, v in zip(arguments, values, strict=True))
            return f"is not orthogonal (R^T R - 1 has an entry {deviation:.3g} at {point})"
        if np.linalg.det(matrix) < 0:
            return "is a reflection (det R = -1), not a rotation"
        checked += 1
    if checked == 0:
        return f"has no finite value at {CHECK_POINTS} random points"
    return None

"""The pieces a system can be assembled from: particles, rigid bodies (planar and 3-D),
springs, gravity.

Fields accept text (parsed by the safe parser when the system is built), SymPy
expressions or numbers; inside a built :class:`~lagrangian.model.System` every
field holds a SymPy expression.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Union

import sympy

#: What a user may give for one scalar field: text, a SymPy expression or a number.
ExprLike = Union[str, sympy.Expr, int, float]  # noqa: UP007  (a runtime alias)
#: One end of a spring: the name of a particle or body, or a fixed point.
Endpoint = Union[str, tuple[ExprLike, ...]]  # noqa: UP007


@dataclass(frozen=True)
class Particle:
    """A point mass at ``position`` (2-D or 3-D), a function of the coordinates and ``t``."""

    name: str
    mass: ExprLike
    position: tuple[ExprLike, ...]


@dataclass(frozen=True)
class RigidBody2D:
    """A planar rigid body: centre of mass ``center``, orientation ``angle``.

    ``inertia`` is the moment of inertia about the centre of mass, so that
    T = m |v_c|^2 / 2 + I (d angle/dt)^2 / 2 (König's theorem).
    """

    name: str
    mass: ExprLike
    inertia: ExprLike
    center: tuple[ExprLike, ExprLike]
    angle: ExprLike


@dataclass(frozen=True)
class RigidBody:
    """A rigid body in space: centre of mass ``position`` (3 components), ``inertia``
    about the centre of mass in the body frame, and its orientation.

    ``inertia``: the principal moments (I1, I2, I3) or the full 3 x 3 tensor.  The
    orientation is given by Euler angles ``euler`` in ``convention`` (see
    :data:`~lagrangian.model.rotation.CONVENTIONS`; "zxz" classical, "zyx" yaw-pitch-roll)
    or by the entries of the ``rotation`` matrix R (body frame -> space frame), all
    functions of the coordinates and ``t``.  T = m |v_c|^2 / 2 + omega^T I omega / 2 with
    omega the body-frame angular velocity (König's theorem; :mod:`.rigid_body`).
    Once built, ``inertia`` is the full tensor and ``rotation`` is always given.
    """

    name: str
    mass: ExprLike
    position: tuple[ExprLike, ...]
    inertia: tuple
    euler: tuple[ExprLike, ...] | None = None
    convention: str = "zxz"
    rotation: tuple[tuple[ExprLike, ...], ...] | None = None

    @property
    def center(self) -> tuple[ExprLike, ...]:
        """The centre of mass (the name planar bodies use, for springs and gravity)."""
        return self.position


@dataclass(frozen=True)
class Spring:
    """A linear spring between two ends, V = k (|r_a - r_b| - rest_length)^2 / 2."""

    stiffness: ExprLike
    ends: tuple[Endpoint, Endpoint]
    rest_length: ExprLike = 0
    name: str = ""


@dataclass(frozen=True)
class Gravity:
    """Uniform gravity ``g`` along ``direction``: V = -m g (direction . r).

    ``direction`` is normalised when the system is built; by default gravity
    points down the last axis (-y in 2-D, -z in 3-D).
    """

    g: ExprLike
    direction: tuple[ExprLike, ...] | None = None

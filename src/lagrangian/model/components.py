"""The pieces a system can be assembled from: particles, planar rigid bodies, springs, gravity.

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

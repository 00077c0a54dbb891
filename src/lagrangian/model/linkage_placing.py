"""Placing a linkage's links from ground through its tree joints, and the constraints of
the joints that close loops (conventions: :mod:`.linkages`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import sympy

from ..errors import ModelError

if TYPE_CHECKING:
    from .linkages import Linkage, ResolvedJoint, Side


@dataclass(frozen=True)
class Pose:
    """A link placed: its origin (start) and angle in the ground frame, as expressions."""

    origin: tuple[sympy.Expr, sympy.Expr]
    angle: sympy.Expr

    def point(self, local: tuple[sympy.Expr, sympy.Expr]) -> tuple[sympy.Expr, sympy.Expr]:
        c, s = sympy.cos(self.angle), sympy.sin(self.angle)
        x, y = local
        return (self.origin[0] + c * x - s * y, self.origin[1] + s * x + c * y)


def place(links, joints, resolved, cuts=None) -> tuple[dict[str, Pose], dict[int, int]]:
    """The poses of the links by the tree joints, and {joint index: side it places}.

    ``cuts`` ({joint index: (u1, u2)}) displaces what a tree joint places, for its reaction
    (:mod:`.linkage_reactions`): a revolute joint's child by (u1, u2) in the ground frame, a
    prismatic joint's by u1 along the axis's normal and u2 in angle about its joint point.
    """
    poses: dict[str, Pose] = {}
    tree: dict[int, int] = {}
    grown = True
    while grown:
        grown = False
        for i, joint in enumerate(joints):
            if i in tree:
                continue
            placed = [s.link is None or s.link in poses for s in joint.sides]
            if placed[0] == placed[1]:
                continue
            child = 0 if not placed[0] else 1
            cut = (cuts or {}).get(i)
            poses[joint.sides[child].link] = _pose(joint, child, poses, resolved, cut)
            tree[i] = child
            grown = True
    for i, link in enumerate(links):
        if link.name not in poses:
            raise ModelError(
                f"link '{link.name}' is not connected to ground through the joints",
                field=f"links[{i}]",
            )
    return poses, tree


def _pose(joint: ResolvedJoint, child: int, poses, links, cut) -> Pose:
    parent = joint.sides[1 - child]
    side = joint.sides[child]
    link = links[side.link]
    where = f"links[{list(links).index(side.link)}].angle"
    parent_point = parent.local if parent.link is None else poses[parent.link].point(parent.local)
    parent_angle = sympy.Integer(0) if parent.link is None else poses[parent.link].angle
    if joint.kind == "revolute":
        if link.angle is None:
            raise ModelError(
                f"link '{link.name}' is placed by the revolute joint '{joint.name}': name the "
                "coordinate of its angle",
                field=where,
            )
        angle = link.angle
        at = parent_point
        if cut is not None:
            at = (at[0] + cut[0], at[1] + cut[1])
    else:
        if link.angle is not None:
            raise ModelError(
                f"link '{link.name}' is placed by the prismatic joint '{joint.name}' and keeps "
                "the angle of the side it slides on: remove its angle",
                field=where,
            )
        angle = parent_angle
        axis = rotated(joint.axis, parent_angle)  # the axis turns with the first side
        sign = 1 if child == 1 else -1
        at = tuple(parent_point[k] + sign * joint.slide * axis[k] for k in range(2))
        if cut is not None:
            angle = angle + cut[1]
            at = (at[0] - cut[0] * axis[1], at[1] + cut[0] * axis[0])
    placed = Pose((sympy.Integer(0), sympy.Integer(0)), angle).point(side.local)
    return Pose((at[0] - placed[0], at[1] - placed[1]), angle)


def rotated(vector, angle) -> tuple[sympy.Expr, sympy.Expr]:
    c, s = sympy.cos(angle), sympy.sin(angle)
    return (c * vector[0] - s * vector[1], s * vector[0] + c * vector[1])


def _angle(side: Side, poses) -> sympy.Expr:
    return sympy.Integer(0) if side.link is None else poses[side.link].angle


def relative(joint: ResolvedJoint, poses) -> sympy.Expr:
    """A tree joint's relative angle (revolute, second side minus first) or slide."""
    if joint.kind == "prismatic":
        return joint.slide
    return _angle(joint.sides[1], poses) - _angle(joint.sides[0], poses)


def closure(joint: ResolvedJoint, linkage: Linkage) -> list[sympy.Expr]:
    """The constraints of a joint that closes a loop (module docstring)."""
    first, second = (linkage.world(s) for s in joint.sides)
    if joint.kind == "revolute":
        return [second[0] - first[0], second[1] - first[1]]
    axis = rotated(joint.axis, _angle(joint.sides[0], linkage.poses))
    offset = (second[0] - first[0], second[1] - first[1])
    return [
        axis[0] * offset[1] - axis[1] * offset[0],
        _angle(joint.sides[1], linkage.poses) - _angle(joint.sides[0], linkage.poses),
    ]

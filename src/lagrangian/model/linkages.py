"""Planar linkages: ``[[links]]`` and ``[[joints]]`` turned into bodies and constraints.

A *link* is a planar rigid body with its own frame: origin at its start, x along the link
(its end is at ``(length, 0)``), y to the left; its centre of mass at ``(center, 0)``
(default ``length/2``) and named points ``points = {P = [x, y]}`` in that frame.  A
*joint* connects two *sides*: ``ground`` (a point ``at`` of the fixed frame) or a point of a
link, written ``link.start``, ``link.end`` or ``link.P``.  ``kind`` is ``revolute`` (the
two points coincide) or ``prismatic`` (the second side's point slides along ``axis``, a
direction in the first side's frame, through the first side's point; the two sides keep
their relative angle).

**Coordinates.**  Each link is placed by the first joint, in the order the joints are
listed, that reaches it from ground through links already placed (passes over the list
repeat until nothing more can be placed).  That joint is a *tree joint* and gives the link
one coordinate: a revolute joint gives the link's absolute angle, named by the link's
``angle`` (the angle of its x axis from the ground's x axis, counter-clockwise, whatever
the joint connects it to); a prismatic joint gives the slide, named by the joint's
``slide`` (the distance from the first side's point to the second's along the axis), and
the link keeps the angle of the side it slides on (it has no ``angle`` of its own).  Every
other joint *closes a loop* and gives two holonomic constraints: a revolute one that its
points coincide (x and y), a prismatic one that the second point is on the axis and that
the relative angle is 0.  A tree joint with ``drive = "EXPR(t)"`` gives one more (its
relative angle or its slide equals the drive: a rheonomic constraint, whose multiplier is
the driving torque or force).

Grübler's count for the plane, DOF = 3 n_links - 2 n_joints (every joint here removes two
of the three freedoms of a planar pair), is what remains; the structure as built has the
same count (n tree coordinates minus 2 per closing joint), so a linkage with DOF <= 0 (a
structure) or with more drives than DOF is refused, and so is one whose closure
constraints are dependent at the initial configuration (checked when it is assembled,
:mod:`.linkage_assembly`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import sympy

from ..errors import ModelError
from .components import ExprLike, RigidBody2D
from .linkage_placing import Pose, closure, place, relative

GROUND = "ground"
KINDS = ("revolute", "prismatic")


@dataclass(frozen=True)
class Link:
    """A planar link as the user wrote it (see the module docstring for its frame)."""

    name: str
    length: ExprLike
    mass: ExprLike
    angle: str | None = None  # the coordinate of its absolute angle (revolute tree joint)
    inertia: ExprLike | None = None  # about the centre; None: a uniform rod, m length^2/12
    center: ExprLike | None = None  # along the link from its start; None: length/2
    points: Mapping[str, tuple[ExprLike, ExprLike]] = field(default_factory=dict)


@dataclass(frozen=True)
class Joint:
    """A revolute or prismatic joint between two sides (see the module docstring)."""

    name: str
    kind: str
    connects: tuple[str, str]
    at: tuple[ExprLike, ExprLike] | None = None  # the ground point, where a side is ground
    axis: tuple[ExprLike, ExprLike] | None = None  # prismatic: in the first side's frame
    slide: str | None = None  # prismatic tree joint: the coordinate of the slide
    drive: ExprLike | None = None  # a tree joint's relative angle or slide as a function of t


@dataclass(frozen=True)
class ResolvedLink:
    """A link with its fields as SymPy expressions."""

    name: str
    length: sympy.Expr
    mass: sympy.Expr
    inertia: sympy.Expr
    center: sympy.Expr
    points: Mapping[str, tuple[sympy.Expr, sympy.Expr]]
    angle: sympy.Symbol | None  # its coordinate, if it has one

    def local(self, point: str) -> tuple[sympy.Expr, sympy.Expr]:
        if point == "start":
            return (sympy.Integer(0), sympy.Integer(0))
        if point == "end":
            return (self.length, sympy.Integer(0))
        return self.points[point]


@dataclass(frozen=True)
class Side:
    """One side of a joint: ground (``link`` None) at ``local`` (ground frame), or a point
    of a link in that link's frame."""

    link: str | None
    local: tuple[sympy.Expr, sympy.Expr]
    text: str


@dataclass(frozen=True)
class ResolvedJoint:
    name: str
    kind: str
    sides: tuple[Side, Side]
    axis: tuple[sympy.Expr, sympy.Expr] | None  # unit, in the first side's frame
    slide: sympy.Symbol | None
    drive: sympy.Expr | None
    tree: bool  # places a link (else closes a loop)
    child: int | None  # the side a tree joint places (0 or 1)
    constraints: tuple[int, ...] = ()  # indices into Linkage.constraints
    drive_constraint: int | None = None  # index into Linkage.constraints


@dataclass(frozen=True)
class Linkage:
    """The linkage of a built system: links placed, joints, and the constraints they add.

    ``constraints`` are appended to the model's own (the first has index ``offset`` in
    ``System.constraints``); ``held`` are the coordinates kept at their given values when
    the linkage is assembled, the first ``degrees_of_freedom - drives`` of its coordinates in
    the model's order (:mod:`.linkage_assembly`); ``reactions`` maps an output column
    (``R_B_x``) to its expression in t, q, q', q'', the parameters and ``multipliers``
    (placeholders for the multipliers of ``constraints``, :mod:`.linkage_reactions`).
    """

    links: tuple[ResolvedLink, ...]
    poses: Mapping[str, Pose]
    joints: tuple[ResolvedJoint, ...]
    constraints: tuple[sympy.Expr, ...]
    coordinates: tuple[sympy.Symbol, ...]  # the linkage's own, in the model's order
    degrees_of_freedom: int
    held: tuple[sympy.Symbol, ...]
    offset: int = 0
    multipliers: tuple[sympy.Symbol, ...] = ()
    reactions: Mapping[str, sympy.Expr] = field(default_factory=dict)

    def world(self, side: Side) -> tuple[sympy.Expr, sympy.Expr]:
        """The ground-frame position of one side's point."""
        if side.link is None:
            return side.local
        return self.poses[side.link].point(side.local)


def link_fields(links, joints, constant, constant_or_time):
    """Every expression field of the links and joints, as :func:`.spec.expression_fields`."""
    for i, link in enumerate(links):
        where = f"links[{i}]"
        yield f"{where}.length", link.length, constant
        yield f"{where}.mass", link.mass, constant
        if link.inertia is not None:
            yield f"{where}.inertia", link.inertia, constant
        if link.center is not None:
            yield f"{where}.center", link.center, constant
        for name, point in link.points.items():
            for k, x in enumerate(point):
                yield f"{where}.points.{name}[{k}]", x, constant
    for i, joint in enumerate(joints):
        where = f"joints[{i}]"
        for key in ("at", "axis"):
            for k, x in enumerate(getattr(joint, key) or ()):
                yield f"{where}.{key}[{k}]", x, constant
        if joint.drive is not None:
            yield f"{where}.drive", joint.drive, constant_or_time


def build_linkage(
    links, joints, resolved: Mapping[str, sympy.Expr], coordinates: Mapping[str, sympy.Symbol]
) -> Linkage:
    """The linkage placed from ground (module docstring); ModelError naming the field."""
    if not joints:
        raise ModelError("links need joints to place them", field="joints")
    links_ = _resolve_links(links, resolved, coordinates)
    joints_ = [_resolve_joint(i, j, resolved, links_, coordinates) for i, j in enumerate(joints)]
    poses, tree = place(links, joints_, links_)
    constraints: list[sympy.Expr] = []
    finished = []
    for i, joint in enumerate(joints_):
        where = f"joints[{i}]"
        is_tree = i in tree
        if joint.drive is not None and not is_tree:
            raise ModelError(
                f"joint '{joint.name}' closes a loop: only a joint that places a link can be "
                "driven (list it before the joints that reach its link otherwise)",
                field=f"{where}.drive",
            )
        if joint.slide is not None and not is_tree:
            raise ModelError(
                f"joint '{joint.name}' closes a loop, so its slide is not a coordinate: "
                "remove 'slide'",
                field=f"{where}.slide",
            )
        if joint.kind == "prismatic" and is_tree and joint.slide is None:
            raise ModelError(
                f"joint '{joint.name}' places link '{joint.sides[tree[i]].link}' by sliding: "
                "name the coordinate of its slide",
                field=f"{where}.slide",
            )
        partial = Linkage((), poses, (), (), (), 0, ())
        indices: tuple[int, ...] = ()
        if not is_tree:
            rows = closure(joint, partial)
            indices = tuple(range(len(constraints), len(constraints) + len(rows)))
            constraints += rows
        drive_index = None
        if joint.drive is not None:
            drive_index = len(constraints)
            constraints.append(relative(joint, poses) - joint.drive)
        finished.append(
            replace(
                joint,
                tree=is_tree,
                child=tree.get(i),
                constraints=indices,
                drive_constraint=drive_index,
            )
        )
    own = {link.angle for link in links_.values() if link.angle is not None}
    own |= {j.slide for j in finished if j.slide is not None}
    ordered = tuple(q for q in coordinates.values() if q in own)
    dof = 3 * len(links_) - 2 * len(finished)
    drives = sum(j.drive is not None for j in finished)
    if dof <= 0:
        raise ModelError(
            f"the linkage has {dof} degrees of freedom by Grübler's count (3 x {len(links_)} "
            f"links - 2 x {len(finished)} joints): it is a structure, not a mechanism",
            field="joints",
        )
    if drives > dof:
        raise ModelError(
            f"{drives} drives for {dof} degrees of freedom (Grübler: 3 x {len(links_)} links "
            f"- 2 x {len(finished)} joints): the linkage is over-constrained",
            field="joints",
        )
    return Linkage(
        links=tuple(links_.values()),
        poses=poses,
        joints=tuple(finished),
        constraints=tuple(constraints),
        coordinates=ordered,
        degrees_of_freedom=dof,
        held=ordered[: dof - drives],
    )


def link_bodies(linkage: Linkage) -> tuple[RigidBody2D, ...]:
    """The links as planar rigid bodies (centre of mass and angle from their poses)."""
    return tuple(
        RigidBody2D(
            name=link.name,
            mass=link.mass,
            inertia=link.inertia,
            center=linkage.poses[link.name].point((link.center, sympy.Integer(0))),
            angle=linkage.poses[link.name].angle,
        )
        for link in linkage.links
    )


# -- resolving ------------------------------------------------------------------------
def _coordinate(name, coordinates, field):
    """The coordinate ``name`` names (None for no name), or ModelError at ``field``."""
    if name is None:
        return None
    if name not in coordinates:
        raise ModelError(f"'{name}' is not one of the coordinates", field=field)
    return coordinates[name]


def _resolve_links(links, resolved, coordinates) -> dict[str, ResolvedLink]:
    found: dict[str, ResolvedLink] = {}
    for i, link in enumerate(links):
        where = f"links[{i}]"
        if not isinstance(link.name, str) or not link.name.isidentifier():
            raise ModelError(f"invalid link name {link.name!r}", field=f"{where}.name")
        if link.name == GROUND or link.name in found:
            raise ModelError(f"the link name '{link.name}' is taken", field=f"{where}.name")
        angle = _coordinate(link.angle, coordinates, f"{where}.angle")
        mass = resolved[f"{where}.mass"]
        length = resolved[f"{where}.length"]
        for name in link.points:
            if name in ("start", "end"):
                raise ModelError(f"the point name '{name}' is taken", field=f"{where}.points")
        found[link.name] = ResolvedLink(
            name=link.name,
            length=length,
            mass=mass,
            inertia=resolved.get(f"{where}.inertia", mass * length**2 / 12),
            center=resolved.get(f"{where}.center", length / 2),
            points={
                name: (resolved[f"{where}.points.{name}[0]"], resolved[f"{where}.points.{name}[1]"])
                for name in link.points
            },
            angle=angle,
        )
    return found


def _resolve_joint(i, joint, resolved, links, coordinates) -> ResolvedJoint:
    where = f"joints[{i}]"
    if joint.kind not in KINDS:
        raise ModelError(
            f"unknown kind '{joint.kind}' (expected one of {', '.join(KINDS)})",
            field=f"{where}.kind",
        )
    sides = []
    for k, text in enumerate(joint.connects):
        sides.append(_side(text, f"{where}.connects[{k}]", joint, where, resolved, links))
    if sides[0].link is None and sides[1].link is None:
        raise ModelError("a joint connects at least one link", field=f"{where}.connects")
    if sides[0].link is not None and sides[0].link == sides[1].link:
        raise ModelError("a joint connects two different links", field=f"{where}.connects")
    axis = None
    if joint.kind == "prismatic":
        if joint.axis is None:
            raise ModelError("a prismatic joint needs an axis", field=f"{where}.axis")
        x, y = (resolved[f"{where}.axis[{k}]"] for k in range(2))
        norm = sympy.sqrt(x**2 + y**2)
        if norm == 0:
            raise ModelError("the axis is the zero vector", field=f"{where}.axis")
        axis = (x / norm, y / norm)
    elif joint.axis is not None or joint.slide is not None:
        raise ModelError("only a prismatic joint has an axis and a slide", field=where)
    slide = _coordinate(joint.slide, coordinates, f"{where}.slide")
    return ResolvedJoint(
        name=joint.name or f"joint{i + 1}",
        kind=joint.kind,
        sides=(sides[0], sides[1]),
        axis=axis,
        slide=slide,
        drive=resolved.get(f"{where}.drive"),
        tree=False,
        child=None,
    )


def _side(text, field_name, joint, where, resolved, links) -> Side:
    if not isinstance(text, str):
        raise ModelError(f"expected text such as 'crank.end', got {text!r}", field=field_name)
    if text == GROUND:
        if joint.at is None:
            raise ModelError("a joint to ground needs its point 'at'", field=f"{where}.at")
        return Side(None, (resolved[f"{where}.at[0]"], resolved[f"{where}.at[1]"]), text)
    name, _, point = text.partition(".")
    if name not in links:
        known = ", ".join(sorted(links)) or "none"
        raise ModelError(f"no link named '{name}' (links: {known})", field=field_name, text=text)
    link = links[name]
    if point not in ("start", "end", *link.points):
        named = ", ".join(["start", "end", *link.points])
        raise ModelError(
            f"link '{name}' has no point '{point}' (points: {named})", field=field_name, text=text
        )
    return Side(name, link.local(point), text)

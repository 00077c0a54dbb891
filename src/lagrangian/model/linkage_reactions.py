"""The reaction at each joint of a linkage, as expressions in the state, q'' and the
multipliers.

Every reaction is given as the force (and, for a prismatic joint, the moment) that the
joint's first side exerts on its second, in the ground frame: columns ``R_<joint>_x``,
``R_<joint>_y`` and ``M_<joint>``; a driven joint adds the torque ``tau_<joint>``
(revolute) or force ``F_<joint>`` (prismatic, along its axis) of its drive.

- A joint that closes a loop: its constraints are c = p2 - p1 (revolute) or
  (axis x (p2 - p1), angle2 - angle1) (prismatic), so the constraint force on the second
  side is the multipliers themselves: R = (lambda_x, lambda_y), or R = lambda_1 n (n the
  axis's normal) and M = lambda_2.
- A joint of the spanning tree has no multiplier.  It is *cut*: what it places is
  displaced by virtual coordinates u (a translation for a revolute joint; a translation
  along the normal and a rotation about the joint point for a prismatic one), and the
  reaction is the generalized force that holds u = 0, by d'Alembert's principle at u = 0:

      R_u = sum_links (m a . dr/du + I alpha dphi/du) + dV/du - sum_k lambda_k dc_k/du,

  with V the links' gravity and c the linkage's constraints (their multipliers are the
  forces of the loop joints and drives).  That is Newton-Euler for the part beyond the cut,
  with the loop forces that enter it.

The model's generalized forces, potential, dissipation and own constraints act on the
coordinates (absolute link angles and slides), which a cut leaves unchanged: they are
taken as loads applied through the coordinates (a torque from ground on a link, a force
along a slide) and add nothing to a joint's force.  Particles, bodies or springs that move
with the linkage's coordinates are loads at unknown points: a model with them gets no
reactions (the columns are left out).
"""

from __future__ import annotations

from dataclasses import replace

import sympy

from ..symbols import time_symbol
from .linkage_placing import closure, place, relative, rotated
from .linkages import Linkage


def with_reactions(
    linkage: Linkage, offset: int, coordinates, gravity, particles, bodies, springs
) -> Linkage:
    """``linkage`` with its constraints' place among the model's (``offset``), placeholders
    for their multipliers and its reactions (module docstring)."""
    multipliers = tuple(sympy.Dummy(f"lambda_link{k}") for k in range(len(linkage.constraints)))
    placed = replace(linkage, offset=offset, multipliers=multipliers)
    names = {link.name for link in linkage.links}
    own = set(linkage.coordinates)
    others = [*(p.position for p in particles)]
    others += [(*b.center, b.angle) for b in bodies if b.name not in names]
    others += [x for s in springs for end in s.ends for x in end]
    if any(sympy.Tuple(*item).free_symbols & own for item in others if item):
        return placed
    rates = {c.q: c.q_dot for c in coordinates} | {c.q_dot: c.q_ddot for c in coordinates}
    return replace(placed, reactions=_reactions(placed, gravity, rates))


def _reactions(linkage: Linkage, gravity, rates) -> dict[str, sympy.Expr]:
    lam = linkage.multipliers
    columns: dict[str, sympy.Expr] = {}
    tree = [j for j in linkage.joints if j.tree]
    cuts = {
        linkage.joints.index(j): (sympy.Dummy(f"u_{j.name}"), sympy.Dummy(f"v_{j.name}"))
        for j in tree
    }
    links = {link.name: link for link in linkage.links}
    poses, _ = place(linkage.links, linkage.joints, links, cuts)
    cut_linkage = replace(linkage, poses=poses)
    constraints = []
    for joint in linkage.joints:
        if not joint.tree:
            constraints += closure(joint, cut_linkage)
        if joint.drive is not None:
            constraints.append(relative(joint, poses) - joint.drive)
    at_rest = {u: 0 for pair in cuts.values() for u in pair}
    potential = _gravity_potential(linkage, poses, gravity)
    motion = {link.name: _second_derivatives(link, linkage, rates) for link in linkage.links}
    for index, (u, v) in cuts.items():
        joint = linkage.joints[index]
        forces = [
            _cut_force(w, linkage, poses, motion, potential, constraints, at_rest) for w in (u, v)
        ]
        sign = 1 if joint.child == 1 else -1
        if joint.kind == "revolute":
            columns[f"R_{joint.name}_x"] = sign * forces[0]
            columns[f"R_{joint.name}_y"] = sign * forces[1]
        else:
            normal = _normal(joint, linkage)
            columns[f"R_{joint.name}_x"] = sign * forces[0] * normal[0]
            columns[f"R_{joint.name}_y"] = sign * forces[0] * normal[1]
            columns[f"M_{joint.name}"] = sign * forces[1]
    for joint in linkage.joints:
        if not joint.tree:
            rows = [lam[k] for k in joint.constraints]
            if joint.kind == "revolute":
                columns[f"R_{joint.name}_x"], columns[f"R_{joint.name}_y"] = rows
            else:
                normal = _normal(joint, linkage)
                columns[f"R_{joint.name}_x"] = rows[0] * normal[0]
                columns[f"R_{joint.name}_y"] = rows[0] * normal[1]
                columns[f"M_{joint.name}"] = rows[1]
        if joint.drive_constraint is not None:
            name = "tau" if joint.kind == "revolute" else "F"
            columns[f"{name}_{joint.name}"] = lam[joint.drive_constraint]
    kinds = (("R", "_x"), ("R", "_y"), ("M", ""), ("tau", ""), ("F", ""))
    order = [f"{kind}_{j.name}{axis}" for j in linkage.joints for kind, axis in kinds]
    return {name: columns[name] for name in order if name in columns}  # joint by joint


def _normal(joint, linkage: Linkage) -> tuple[sympy.Expr, sympy.Expr]:
    """The unit normal of a prismatic joint's axis in the ground frame (axis turned +90°)."""
    side = joint.sides[0]
    angle = sympy.Integer(0) if side.link is None else linkage.poses[side.link].angle
    axis = rotated(joint.axis, angle)
    return (-axis[1], axis[0])


def _gravity_potential(linkage: Linkage, poses, gravity) -> sympy.Expr:
    if gravity is None:
        return sympy.Integer(0)
    total = sympy.Integer(0)
    for link in linkage.links:
        centre = poses[link.name].point((link.center, sympy.Integer(0)))
        total -= (
            link.mass
            * gravity.g
            * sum(d * x for d, x in zip(gravity.direction, centre, strict=True))
        )
    return total


def _second_derivatives(link, linkage: Linkage, rates) -> dict[str, sympy.Expr]:
    """Accelerations of a link's centre and its angular acceleration, in q, q', q'', t."""
    pose = linkage.poses[link.name]
    centre = pose.point((link.center, sympy.Integer(0)))
    twice = lambda x: _rate(_rate(x, rates), rates)  # noqa: E731
    return {"ax": twice(centre[0]), "ay": twice(centre[1]), "alpha": twice(pose.angle)}


def _rate(expr: sympy.Expr, rates) -> sympy.Expr:
    """d/dt along the motion (``rates``: q -> q', q' -> q'')."""
    rate = sympy.diff(expr, time_symbol())
    for symbol in expr.free_symbols & rates.keys():
        rate += sympy.diff(expr, symbol) * rates[symbol]
    return rate


def _cut_force(u, linkage, poses, motion, potential, constraints, at_rest) -> sympy.Expr:
    total = sympy.diff(potential, u).xreplace(at_rest)
    for link in linkage.links:
        pose = poses[link.name]
        centre = pose.point((link.center, sympy.Integer(0)))
        moved = [sympy.diff(x, u).xreplace(at_rest) for x in centre]
        turned = sympy.diff(pose.angle, u).xreplace(at_rest)
        a = motion[link.name]
        total += link.mass * (a["ax"] * moved[0] + a["ay"] * moved[1])
        total += link.inertia * a["alpha"] * turned
    for lam, c in zip(linkage.multipliers, constraints, strict=True):
        total -= lam * sympy.diff(c, u).xreplace(at_rest)
    return total

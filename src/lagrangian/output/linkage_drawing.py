"""A linkage in the mechanism drawing: links as bars from their start to their end, joints
as open circles, ground joints as hatched pins, a prismatic joint on ground as its guide
line, and (on request) each joint's reaction as an arrow at the joint.

The arrows show the force on the joint's second side from its first
(:mod:`lagrangian.model.linkage_reactions`), all at one scale: the largest reaction of the
run is drawn a quarter of the drawing's span long.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import sympy

from .mechanism import PIVOT_COLOR

if TYPE_CHECKING:
    from ..model import System
    from ..trajectory import Trajectory

LINK_COLOR, JOINT_COLOR, ARROW_COLOR = "#2f4b7c", "#000000", "#d62728"
#: The longest reaction arrow, as a fraction of the drawing's largest span.
ARROW_SPAN = 0.25


@dataclass(frozen=True, eq=False)
class LinkageFrames:
    """What moves, at the drawing's sample times T: ``ends`` (L, 2, 2, T) of the links,
    ``joints`` (J, 2, T); fixed: ``ground`` (G, 2) pins and ``guides`` (K, 2, 2) lines;
    ``forces`` (J, 2, T) the reactions (None when not asked for)."""

    ends: np.ndarray
    joints: np.ndarray
    ground: np.ndarray
    guides: np.ndarray
    forces: np.ndarray | None = None

    def extent(self) -> np.ndarray:
        """(2, 2): the box of the links, the joints and the pins."""
        points = np.concatenate(
            [
                self.ends.transpose(2, 0, 1, 3).reshape(2, -1),
                self.joints.transpose(1, 0, 2).reshape(2, -1),
                self.ground.T.reshape(2, -1),
            ],
            axis=1,
        )
        points = points[:, np.all(np.isfinite(points), axis=0)]
        return np.stack([points.min(axis=1), points.max(axis=1)], axis=1)


def linkage_frames(
    system: System,
    trajectory: Trajectory,
    times: np.ndarray,
    q: np.ndarray,
    parameters: dict[str, float],
    *,
    reactions: bool = False,
) -> LinkageFrames | None:
    """The :class:`LinkageFrames` of ``system``'s linkage at ``times`` (coordinates ``q``,
    (n, T)), or None for a system without one."""
    linkage = system.linkage
    if linkage is None:
        return None
    arguments = [system.time, *(c.q for c in system.coordinates)]
    arguments += [p.symbol for p in system.parameters]
    values = [parameters[p.name] for p in system.parameters]

    def along(points) -> np.ndarray:
        function = sympy.lambdify(arguments, sympy.Matrix(points), "numpy")
        rows = [
            np.asarray(function(t, *q[:, k], *values), dtype=float).ravel()
            for k, t in enumerate(times)
        ]
        return np.array(rows, dtype=float).T.reshape(len(points), 2, len(times))

    zero = sympy.Integer(0)
    ends = along(
        [
            linkage.poses[link.name].point(local)
            for link in linkage.links
            for local in ((zero, zero), (link.length, zero))
        ]
    ).reshape(len(linkage.links), 2, 2, len(times))
    joints = along([linkage.world(joint.sides[1]) for joint in linkage.joints])
    ground = [j.sides[k] for j in linkage.joints for k in (0, 1) if j.sides[k].link is None]
    numbers = {p.symbol: parameters[p.name] for p in system.parameters}
    pins = np.array([[float(x.xreplace(numbers)) for x in s.local] for s in ground]).reshape(-1, 2)
    guides = [
        [float(x.xreplace(numbers)) for x in (*j.sides[0].local, *j.axis)]
        for j in linkage.joints
        if j.kind == "prismatic" and j.sides[0].link is None
    ]
    forces = None
    if reactions:
        forces = _forces(linkage, trajectory, times)
    return LinkageFrames(
        ends, joints, pins, np.array(guides, dtype=float).reshape(-1, 2, 2), forces
    )


def links_as_bars(system: System) -> System:
    """``system`` with each link's body replaced, for drawing only, by the uniform bar from
    the link's start to its end (centre at the middle, inertia m length^2 / 12): the page
    draws a planar body as the bar of length sqrt(12 I / m) through its centre, which is the
    link itself only for a uniform rod (not a flywheel crank with its centre at the pivot)."""
    linkage = system.linkage
    if linkage is None:
        return system
    from dataclasses import replace

    zero = sympy.Integer(0)
    bars = {
        link.name: replace(
            next(b for b in system.bodies if b.name == link.name),
            inertia=link.mass * link.length**2 / 12,
            center=linkage.poses[link.name].point((link.length / 2, zero)),
        )
        for link in linkage.links
    }
    return replace(system, bodies=tuple(bars.get(b.name, b) for b in system.bodies))


def _forces(linkage, trajectory: Trajectory, times: np.ndarray) -> np.ndarray:
    """(J, 2, T) reactions resampled to ``times`` (zeros for a joint without them)."""
    names = set(trajectory.reactions)
    forces = np.zeros((len(linkage.joints), 2, len(times)))
    for j, joint in enumerate(linkage.joints):
        for axis, suffix in enumerate("xy"):
            name = f"R_{joint.name}_{suffix}"
            if name in names:
                forces[j, axis] = np.interp(times, trajectory.t, trajectory[name])
    return forces


def linkage_panel(ax, frames: LinkageFrames, span: float) -> dict:
    """Draw the fixed parts on ``ax``; return the moving ones (see :func:`update_linkage`)."""
    size = 0.04 * span
    for x, y in frames.ground:  # a pin: a triangle on a hatched base
        ax.fill([x, x - size, x + size], [y, y - 1.6 * size, y - 1.6 * size],
                facecolor="white", edgecolor=PIVOT_COLOR, lw=1.0, zorder=2)  # fmt: skip
        base = y - 1.6 * size
        ax.plot([x - 1.5 * size, x + 1.5 * size], [base, base], "-", color=PIVOT_COLOR, lw=1.2)
        for k in np.linspace(-1.3, 1.3, 6):
            ax.plot([x + k * size, x + (k - 0.5) * size], [base, base - 0.6 * size], "-",
                    color=PIVOT_COLOR, lw=0.8)  # fmt: skip
    for (x, y), (u, v) in frames.guides:  # a guide: its line, across the whole view
        norm = np.hypot(u, v)
        reach = 2.0 * span
        ax.plot([x - reach * u / norm, x + reach * u / norm],
                [y - reach * v / norm, y + reach * v / norm],
                "--", color=PIVOT_COLOR, lw=0.8, zorder=1)  # fmt: skip
    panel = {
        "links": [
            ax.plot(
                [], [], "-", color=LINK_COLOR, lw=5, alpha=0.9, solid_capstyle="round", zorder=3
            )[0]
            for _ in range(frames.ends.shape[0])
        ],
        "joints": ax.plot([], [], "o", ms=6, mfc="white", mec=JOINT_COLOR, mew=1.4, zorder=5)[0],
        "arrows": None,
    }
    if frames.forces is not None:
        largest = float(np.max(np.hypot(frames.forces[:, 0], frames.forces[:, 1]), initial=0.0))
        panel["scale"] = ARROW_SPAN * span / largest if largest > 0 else 0.0
        panel["arrows"] = ax.quiver(
            frames.joints[:, 0, 0], frames.joints[:, 1, 0],
            np.zeros(frames.joints.shape[0]), np.zeros(frames.joints.shape[0]),
            angles="xy", scale_units="xy", scale=1.0, color=ARROW_COLOR, width=0.006, zorder=6,
        )  # fmt: skip
    return panel


def moving_artists(panel: dict) -> list:
    artists = [*panel["links"], panel["joints"]]
    return artists + ([panel["arrows"]] if panel["arrows"] is not None else [])


def update_linkage(panel: dict, frames: LinkageFrames, j: int) -> None:
    """Move the links, joints and arrows of one panel to sample ``j``."""
    for line, ends in zip(panel["links"], frames.ends, strict=True):
        line.set_data(ends[:, 0, j], ends[:, 1, j])
    panel["joints"].set_data(frames.joints[:, 0, j], frames.joints[:, 1, j])
    if panel["arrows"] is not None:
        panel["arrows"].set_offsets(frames.joints[:, :, j])
        forces = frames.forces[:, :, j] * panel["scale"]
        panel["arrows"].set_UVC(forces[:, 0], forces[:, 1])

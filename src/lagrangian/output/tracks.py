"""The curves particles are held to: a hoop, a wire, a rail, drawn by the page and by
``animate`` (a bead on a turning wire was a bare dot, a bead on a turning hoop a
pendulum's rod from the origin, a cart a block in the air).

A particle whose position moves with one coordinate alone is held to the curve its
position traces as that coordinate runs (at the time of the frame: the curve moves where
the position has t).  It is drawn where it moves, or where no rod holds the particle
(:func:`~lagrangian.output.geometry.rods`: a pendulum's bob keeps its rod and no hoop);
a rod from the origin to a particle on a moving curve is dropped (the hoop holds it).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import sympy

from ..algebra import as_expression, is_zero
from ..model import System
from .geometry import ORIGIN, Geometry

#: Points along a drawn track.
TRACK_SAMPLES = 97
#: An open track is drawn over q -+ this many spans of the view (at its speed |dP/dq|).
OPEN_SPANS = 1.5


@dataclass(frozen=True)
class Track:
    """A particle held to a curve: its position moves with one ``coordinate`` alone (an
    index); ``moving``: the curve moves (the position has t: a turning hoop or wire);
    ``closed``: it is 2π-periodic in the coordinate (a hoop, drawn whole)."""

    particle: int
    coordinate: int
    moving: bool
    closed: bool

    def document(self) -> dict:
        return {
            "particle": self.particle,
            "coordinate": self.coordinate,
            "moving": self.moving,
            "closed": self.closed,
        }


def tracks(system: System) -> tuple[Track, ...]:
    """The :class:`Track` of each particle held to a curve (see the module docstring)."""
    found = []
    for k, particle in enumerate(system.particles):
        position = [as_expression(x) for x in particle.position]
        used = [i for i, c in enumerate(system.coordinates) if any(x.has(c.q) for x in position)]
        if len(used) != 1:
            continue
        q = system.coordinates[used[0]].q
        turned = {q: q + 2 * sympy.pi}
        # the curve moves where t enters more than a support's shift (a shaken pendulum's
        # a cos(w t) + l sin(theta) is a pendulum on a moving pivot: its rod, no track)
        moving = any(_beyond_support(x, q, system.time) for x in position)
        closed = all(is_zero(x.xreplace(turned) - x) for x in position)
        found.append(Track(k, used[0], moving, closed))
    return tuple(found)


def held(found: Sequence[Track], links: Sequence[tuple[int, int]]) -> tuple[list[Track], tuple]:
    """The tracks drawn, and the rods left once a moving track holds its particle."""
    moving = {t.particle for t in found if t.moving}
    links = tuple(link for link in links if not (link[0] == ORIGIN and link[1] in moving))
    far_ends = {b for _, b in links}
    return [t for t in found if t.moving or t.particle not in far_ends], links


def track_curves(
    scene: Geometry, drawn: Sequence[Track], t: np.ndarray, q: np.ndarray, span: float
) -> list[np.ndarray]:
    """Each drawn track at the times ``t`` (T,) of the coordinates ``q`` (n, T): (D, S, T),
    S points along it at each time (a closed one whole; an open one over q -+ a range that
    crosses a view ``span`` wide)."""
    curves = []
    steps = np.linspace(-1.0, 1.0, TRACK_SAMPLES)
    for track in drawn:
        i = track.coordinate
        if track.closed:
            along = np.pi + np.pi * steps[:, None] + 0 * q[i][None, :]
        else:
            h = 1e-6 * max(1.0, float(np.abs(q[i, 0])))
            ahead, behind = q[:, :1].copy(), q[:, :1].copy()
            ahead[i] += h
            behind[i] -= h
            moved = scene.at(t[:1], ahead).particles - scene.at(t[:1], behind).particles
            speed = float(np.linalg.norm(moved[track.particle, :, 0])) / (2 * h)
            half = OPEN_SPANS * span / speed if speed > 0 else 1.0
            along = q[i][None, :] + half * steps[:, None]
        times = np.broadcast_to(t[None, :], along.shape).ravel()
        coordinates = np.repeat(q[:, None, :], TRACK_SAMPLES, axis=1)
        coordinates[i] = along
        points = scene.at(times, coordinates.reshape(q.shape[0], -1)).particles[track.particle]
        curves.append(points.reshape(points.shape[0], TRACK_SAMPLES, t.shape[0]))
    return curves


def _beyond_support(component: sympy.Expr, q: sympy.Symbol, t: sympy.Symbol) -> bool:
    """Whether ``component`` has t outside its terms in t alone (a moving support)."""
    moving = sympy.Add(*[term for term in sympy.Add.make_args(component) if term.has(q)])
    return moving.has(t)

"""How a 3-D rigid body is drawn: a box (or a disc) with its orientation.

A body of mass m with principal moments I1, I2, I3 (the eigenvalues of its inertia
tensor at the parameter values) is drawn as the uniform box of the same mass and
moments, along its principal axes, with half-sides

    a_k^2 = 3 (I_i + I_j - I_k) / (2 m)    ({i, j, k} = {1, 2, 3}),

so a long rod is a long thin box and a cube a cube.  A flat body with two
equal moments (a thin disc: I1 = I2 = I3 / 2) is drawn as a disc of radius
r = sqrt(2 I3 / m) with one spoke, so that its spin shows.  The outline is a
set of polylines through points fixed in the body frame (:class:`SolidShape`);
in space a point is r_c + R p (:func:`solid_points`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: A body whose smallest half-side is below this fraction of its largest is flat.
FLAT = 0.05
#: Relative difference below which two principal moments are equal.
EQUAL = 1e-6
#: Points on the rim of a disc.
RIM_POINTS = 32


@dataclass(frozen=True, eq=False)
class SolidShape:
    """Points of a body's outline in the body frame, ``points`` (K, 3), joined by the
    polylines ``paths`` (tuples of point indices)."""

    points: np.ndarray
    paths: tuple[tuple[int, ...], ...]
    kind: str  # "box", "disc" or "point"


def solid_shape(mass: float, inertia: np.ndarray) -> SolidShape:
    """The box or disc of ``mass`` with the inertia tensor ``inertia`` (3, 3), body frame."""
    inertia = (np.asarray(inertia, float) + np.asarray(inertia, float).T) / 2
    moments, axes = np.linalg.eigh(inertia)
    if not mass > 0 or not np.all(np.isfinite(moments)):
        return SolidShape(np.zeros((1, 3)), (), "point")
    total = moments.sum()
    half = np.sqrt(np.clip(3 * (total - 2 * moments) / (2 * mass), 0, None))
    if half.max() <= 0:
        return SolidShape(np.zeros((1, 3)), (), "point")
    flat = int(np.argmin(half))
    others = [k for k in range(3) if k != flat]
    a, b = moments[others]
    if half[flat] < FLAT * half.max() and abs(a - b) <= EQUAL * max(a, b):
        radius = np.sqrt(2 * moments[flat] / mass)
        angle = np.linspace(0, 2 * np.pi, RIM_POINTS, endpoint=False)
        u, v = axes[:, others[0]], axes[:, others[1]]
        rim = radius * (np.outer(np.cos(angle), u) + np.outer(np.sin(angle), v))
        points = np.vstack([rim, np.zeros((1, 3))])
        circle = (*range(RIM_POINTS), 0)
        return SolidShape(points, (circle, (RIM_POINTS, 0)), "disc")
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    points = (signs * half) @ axes.T  # corner k = sum_j s_j a_j e_j
    paths = []
    for k, corner in enumerate(signs):
        for axis in range(3):
            if corner[axis] < 0:  # each edge once: from the corner with the minus sign
                other = corner.copy()
                other[axis] = 1
                paths.append((k, int(np.flatnonzero((signs == other).all(axis=1))[0])))
    return SolidShape(points, tuple(paths), "box")


def solid_points(shape: SolidShape, center: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """(K, 3, T): the outline in space, r_c + R p, for ``center`` (3, T) and ``rotation``
    (3, 3, T) along a motion."""
    return np.einsum("jkt,pk->pjt", rotation, shape.points) + center[None, :, :]

"""Small oscillations where the coordinates are singular: the regular directions only.

Spherical coordinates degenerate on the axis: at theta = 0 every value of phi
is the same point, so M(q0) has a zero row and column for phi (T = m l^2
(theta'^2 + sin^2 theta phi'^2)/2) and det(K0 - w^2 M0) = 0 says nothing.  The
point is still an equilibrium (the bob hanging straight down).  Here the
coordinates whose rows of M0 vanish are named *degenerate*, and the modes are
those of the block of the remaining (regular) coordinates,

    M_rr x_r'' + C_rr x_r' + K_rr x_r = 0,

which is the motion in the regular directions with the degenerate coordinates
held (for the spherical pendulum at the bottom: w^2 = g/l, phi degenerate).
The motion across the axis mixes theta and phi and is not described by this
block; a chart regular there (x = l sin theta cos phi, y = l sin theta sin phi)
gives the full set, here g/l twice.
"""

from __future__ import annotations

import dataclasses

import sympy

from .linear import LinearizedSystem, NormalModes, vanishes


def degenerate_coordinates(linear: LinearizedSystem) -> tuple[int, ...]:
    """Indices of the coordinates whose row of M0 vanishes (at the default values, if any)."""
    mass, n = linear.mass, linear.mass.rows
    return tuple(
        i
        for i in range(n)
        if all(vanishes(mass[i, j], linear.system, linear.values) for j in range(n))
    )


def regular_modes(linear: LinearizedSystem) -> tuple[NormalModes, tuple[str, ...]] | None:
    """The modes in the regular directions and the names of the degenerate coordinates.

    None when no row of M0 vanishes, when every one does, or when the regular
    block is itself singular (a degeneracy that is not along coordinate axes).
    Mode shapes are given over every coordinate, 0 in the degenerate ones.
    """
    n = linear.mass.rows
    degenerate = degenerate_coordinates(linear)
    if not degenerate or len(degenerate) == n:
        return None
    keep = [i for i in range(n) if i not in degenerate]

    def block(matrix: sympy.Matrix) -> sympy.ImmutableMatrix:
        return sympy.ImmutableMatrix(matrix.extract(keep, keep))

    regular = LinearizedSystem(
        linear.system,
        linear.point,
        block(linear.mass),
        block(linear.damping),
        block(linear.stiffness),
        linear.values,
    )
    modes = regular.normal_modes()
    if modes.note.startswith("the mass matrix is singular"):
        return None
    shapes = tuple(_embedded(shape, keep, n) for shape in modes.shapes)
    names = linear.system.coordinate_names
    return dataclasses.replace(modes, shapes=shapes), tuple(names[i] for i in degenerate)


def _embedded(shape: sympy.Matrix, keep: list[int], n: int) -> sympy.ImmutableMatrix:
    entries = [sympy.Integer(0)] * n
    for i, value in zip(keep, shape, strict=True):
        entries[i] = value
    return sympy.ImmutableMatrix(entries)

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
from dataclasses import dataclass

import sympy

from .linear import LinearizedSystem, NormalModes


@dataclass(frozen=True, eq=False)
class Reduced:
    """The stiffness in the directions used for the modes (the columns of ``basis``), and
    whether the motion there is damped."""

    stiffness: sympy.Matrix
    basis: sympy.Matrix
    damped: bool = False


def degenerate_directions(linear: LinearizedSystem) -> list[sympy.Matrix]:
    """A basis of the null space of M0 (exact; at the default values when that fails)."""
    try:
        return linear.mass.nullspace(simplify=True)
    except (TypeError, ValueError, ZeroDivisionError):
        return []


def regular_modes(
    linear: LinearizedSystem,
) -> tuple[NormalModes, tuple[str, ...], Reduced] | None:
    """The modes in the regular directions and the names of the degenerate coordinates.

    The regular directions are the coordinates whose rows of M0 do not vanish
    when the null space of M0 is spanned by coordinate axes (phi at the pole of
    spherical coordinates); otherwise (phi - psi at theta = 0 of Euler angles,
    where only phi + psi is defined) the orthogonal complement of the null space,
    and the degenerate coordinates are those the null vectors move.  None when
    M0 is regular, or the reduced M0 is still singular.  Mode shapes are given
    over every coordinate, 0 along the degenerate directions.
    """
    n = linear.mass.rows
    null = degenerate_directions(linear)
    if not null or len(null) == n:
        return None
    names = linear.system.coordinate_names
    axes = [next((i for i in range(n) if v[i] != 0), None) for v in null]
    if all(sum(1 for x in v if x != 0) == 1 for v in null):
        keep = [i for i in range(n) if i not in axes]
        basis = sympy.Matrix.hstack(*(sympy.eye(n)[:, i] for i in keep))
    else:
        complement = sympy.Matrix.hstack(*null).T.nullspace()
        basis = sympy.Matrix.hstack(*complement)
    degenerate = tuple(names[i] for i in range(n) if any(v[i] != 0 for v in null))

    def reduced(matrix: sympy.Matrix) -> sympy.ImmutableMatrix:
        return sympy.ImmutableMatrix(basis.T * matrix * basis)

    regular = LinearizedSystem(
        linear.system,
        linear.point,
        reduced(linear.mass),
        reduced(linear.damping),
        reduced(linear.stiffness),
        linear.values,
    )
    modes = regular.normal_modes()
    if modes.note.startswith("the mass matrix is singular"):
        return None
    shapes = tuple(sympy.ImmutableMatrix(basis * shape) for shape in modes.shapes)
    return (
        dataclasses.replace(modes, shapes=shapes),
        degenerate,
        Reduced(regular.stiffness, basis, not regular.dissipative.is_zero_matrix),
    )

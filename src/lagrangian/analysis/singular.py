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

from ..algebra import as_expression
from ..model import RigidBody
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


#: Steps along a null direction of M0 at which a singular point is tried under other names.
FIBER_STEPS = (0.7, -1.3, 2.1)


def at_rest_under_every_name(eom, linear: LinearizedSystem) -> bool:
    """Whether the configuration of a singular rest point is at rest under all its names.

    Where the coordinates are singular one configuration has many names: moving along
    a null vector n of M0 moves nothing (phi at the pole of spherical coordinates,
    phi - psi at theta = 0 of Euler angles).  A configuration at rest is at rest under
    each name, so the forces at rest G(q0 + s n) vanish for every s; where they do
    not, G(q0) = 0 was an accident of the names (a gimbal lock), not an equilibrium:
    a bob at the pole of spherical coordinates whose axis is horizontal.

    Checked at a few s, at the default parameter values, where the particles' and
    bodies' positions show that q0 + s n is the same configuration; True (an
    equilibrium, as G(q0) = 0 says) when that cannot be shown.
    """
    system = eom.system
    values = {p.symbol: sympy.Float(v) for p, v in _values(system, linear).items()}
    if len(values) < len(system.parameters):
        return True
    rest = {c.q_dot: 0 for c in system.coordinates}
    forces = [g.xreplace(rest).xreplace(values) for g in eom.forcing]
    q0 = [as_expression(linear.point.get(c.name, 0)) for c in system.coordinates]
    names = [c.q for c in system.coordinates]
    here = _configuration(system, dict(zip(names, q0, strict=True)), values)
    if here is None:
        return True
    for direction in degenerate_directions(linear):
        for step in FIBER_STEPS:
            named = {
                c.q: x + step * d.xreplace(values)
                for c, x, d in zip(system.coordinates, q0, direction, strict=True)
            }
            there = _configuration(system, named, values)
            if there is None or max(abs(a - b) for a, b in zip(here, there, strict=True)) > 1e-9:
                return True  # not the same configuration: the names say nothing more
            pushed = [complex(g.xreplace(named).evalf()) for g in forces]
            if max(abs(g) for g in pushed) > 1e-9:
                return False
    return True


def _values(system, linear: LinearizedSystem) -> dict:
    """Parameter -> value: the point's own, else the defaults."""
    given = {**system.parameter_values, **linear.values}
    return {p: given[p.name] for p in system.parameters if p.name in given}


def _configuration(system, named: dict, values: dict) -> list[float] | None:
    """Every particle's position and every body's placement at the coordinates ``named``
    (at t = 0), as numbers; None where the model has no geometry or they are not numbers."""
    parts: list[sympy.Expr] = []
    for particle in system.particles:
        parts += particle.position
    for body in system.bodies:
        if isinstance(body, RigidBody):
            parts += [*body.position, *(x for row in body.rotation for x in row)]
        else:
            parts += [*body.center, sympy.cos(body.angle), sympy.sin(body.angle)]
    if not parts:
        return None
    at = {**named, **values, system.time: 0}
    numbers = [as_expression(x).xreplace(at).evalf() for x in parts]
    if not all(x.is_number for x in numbers):
        return None
    return [complex(x) for x in numbers]

"""Kinetic and potential energy from the geometry of particles, bodies, springs and gravity.

The kinetic energy of points r_k(q, t) is assembled in the quadratic form

    T = 1/2 q'^T M q' + b . q' + c,
    M = sum_k m_k J_k^T J_k,  b = sum_k m_k J_k^T dr_k/dt,  c = 1/2 sum_k m_k |dr_k/dt|^2,

with J_k = dr_k/dq, so each (small) entry is simplified on its own: the double
pendulum's T comes out as in the textbook, and the cost grows with the number
of entries, not with the size of an expanded sum of squares.

Above ``FAST_MIN_COORDINATES`` coordinates the same sums are formed with SymEngine
(:mod:`.energy_large`): each distinct product J_k[:, i] . J_k[:, j] is simplified once by
a targeted rule (:func:`~lagrangian.algebra.combine_angles`, sum of angles) and the
masses sharing it are added, M_ij = (m_j + ... + m_n) l_i l_j cos(theta_i - theta_j) for
a chain.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import sympy

from ..algebra import (
    FAST_MIN_COORDINATES,
    is_zero,
    tidy,
)
from ..errors import ModelError
from ..lazy import value_of
from ..symbols import Coordinate
from .components import Gravity, Particle, RigidBody, RigidBody2D, Spring
from .energy_large import Converted, gravity_potential_large, kinetic_energy_large
from .rigid_body import rotation_piece

#: 3-D bodies whose rotational terms get the trigonometric search (the rest are grouped
#: only, so that hundreds of bodies build in seconds).
TRIG_TIDIED_BODIES = 6


def kinetic_energy(
    coordinates: Sequence[Coordinate],
    time: sympy.Symbol,
    particles: Sequence[Particle],
    bodies: Sequence[RigidBody2D | RigidBody],
    known: dict | None = None,
    converted: dict | None = None,
) -> sympy.Expr | Converted:
    """T of the particles and rigid bodies (translation of the centre + rotation).

    ``known``, where given, gains {SymPy expression: its SymEngine form} of what the large
    route assembled in SymEngine (so that L converts back at the cost of its top level);
    T is then a :class:`~.energy_large.Converted`, made in SymPy on first read.
    ``converted`` gains the SymEngine forms of the positions the large route converts
    (V's large route starts from them: :func:`gravity_potential`).

    A 3-D body's rotation adds omega^T I omega / 2 with omega = A q' + b its body-frame
    angular velocity (:mod:`.rigid_body`): M += A^T I A, linear += A^T I b,
    c += b^T I b / 2, tidied with the translation, entry by entry, for the first
    :data:`TRIG_TIDIED_BODIES` bodies; the rotation of further bodies is added
    grouped only (as on the large route), so that hundreds of bodies build in seconds.
    """
    q = [c.q for c in coordinates]
    n = len(q)
    solids = [b for b in bodies if isinstance(b, RigidBody)]
    bodies = [b for b in bodies if not isinstance(b, RigidBody)]
    if n >= FAST_MIN_COORDINATES:
        centers = [Particle(b.name, b.mass, b.position) for b in solids]
        points = [*particles, *centers]
        fast = kinetic_energy_large(coordinates, time, points, bodies, known, converted)
        if fast is not None and not solids:
            return fast  # made in SymPy on first read where ``known`` is given
        if fast is not None:
            return value_of(fast) + _rotational_energy(coordinates, time, solids)
    mass_matrix = [[sympy.Integer(0)] * n for _ in range(n)]
    linear = [sympy.Integer(0)] * n
    constant = sympy.Integer(0)
    state = (*q, time)
    for body in solids[:TRIG_TIDIED_BODIES]:  # each entry tidied on its own first
        inertia, rates, explicit = rotation_piece(body, q, time)
        weighted = inertia * rates  # I A
        active = [i for i in range(n) if any(x != 0 for x in rates[:, i])]
        for a, i in enumerate(active):
            for j in active[a:]:
                entry = (rates[:, i].T * weighted[:, j])[0, 0]
                mass_matrix[i][j] += tidy(entry, state, trig=True)
            linear[i] += tidy((weighted[:, i].T * explicit)[0, 0], state, trig=True)
        constant += tidy((explicit.T * inertia * explicit)[0, 0] / 2, state, trig=True)

    # (mass or inertia, position components): a body's rotation is a 1-D "point" at its angle.
    points = [(p.mass, p.position) for p in particles]
    points += [(b.mass, b.center) for b in [*bodies, *solids]]
    points += [(b.inertia, (b.angle,)) for b in bodies]
    for mass, position in points:
        jacobian = [[sympy.diff(x, qj) for qj in q] for x in position]
        explicit = [sympy.diff(x, time) for x in position]
        for i in range(n):
            for j in range(i, n):
                mass_matrix[i][j] += mass * sum(row[i] * row[j] for row in jacobian)
            linear[i] += mass * sum(row[i] * v for row, v in zip(jacobian, explicit, strict=True))
        constant += mass * sum(v**2 for v in explicit) / 2

    velocities = [c.q_dot for c in coordinates]
    state = (*q, time)
    terms = []
    for i in range(n):
        terms.append(tidy(mass_matrix[i][i], state, trig=True) * velocities[i] ** 2 / 2)
        terms += [
            tidy(mass_matrix[i][j], state, trig=True) * velocities[i] * velocities[j]
            for j in range(i + 1, n)
        ]
        terms.append(tidy(linear[i], state, trig=True) * velocities[i])
    terms.append(tidy(constant, state, trig=True))
    terms.append(_rotational_energy(coordinates, time, solids[TRIG_TIDIED_BODIES:]))
    return sympy.Add(*terms)


def _rotational_energy(
    coordinates: Sequence[Coordinate], time: sympy.Symbol, solids: Sequence[RigidBody]
) -> sympy.Expr:
    """sum over 3-D bodies of omega^T I omega / 2 for the large route and for bodies past
    :data:`TRIG_TIDIED_BODIES`: each coefficient of q_i' q_j' grouped, without the
    trigonometric search (~15 ms an entry, which many bodies do not repay: 20 tops build
    in 0.4 s, with it 3 s)."""
    q = [c.q for c in coordinates]
    velocities = [c.q_dot for c in coordinates]
    state = (*q, time)
    terms = []
    for body in solids:
        inertia, rates, explicit = rotation_piece(body, q, time, trig=False)
        weighted = inertia * rates
        active = [i for i in range(len(q)) if any(x != 0 for x in rates[:, i])]
        for a, i in enumerate(active):
            for j in active[a:]:
                entry = tidy((rates[:, i].T * weighted[:, j])[0, 0], state)
                weight = velocities[i] ** 2 / 2 if i == j else velocities[i] * velocities[j]
                terms.append(entry * weight)
            terms.append(tidy((weighted[:, i].T * explicit)[0, 0], state) * velocities[i])
        terms.append(tidy((explicit.T * inertia * explicit)[0, 0] / 2, state))
    return sympy.Add(*terms)


def gravity_potential(
    gravity: Gravity,
    particles: Sequence[Particle],
    bodies: Sequence[RigidBody2D | RigidBody],
    known: dict | None = None,
    converted: dict | None = None,
) -> sympy.Expr | Converted:
    """V = -g sum_k m_k (direction . r_k): height measured against the direction of gravity
    (``known``, ``converted``: as for :func:`kinetic_energy`)."""
    points = [(p.mass, p.position) for p in particles] + [(b.mass, b.center) for b in bodies]
    large = len(points) >= FAST_MIN_COORDINATES  # tidy costs more than it gives there
    if large:
        fast = gravity_potential_large(gravity, points, known, converted)
        if fast is not None:
            return fast
    terms = []
    for mass, position in points:
        height = -sum(d * x for d, x in zip(gravity.direction, position, strict=True))
        terms.append(mass * gravity.g * (height if large else tidy(height)))
    return sympy.Add(*terms)


def spring_potential(spring: Spring) -> sympy.Expr:
    """V = k (|r_a - r_b| - rest)^2 / 2; with zero rest length, k |r_a - r_b|^2 / 2."""
    a, b = spring.ends
    squared = tidy(sum((x - y) ** 2 for x, y in zip(a, b, strict=True)), trig=True)
    if spring.rest_length == 0:
        return spring.stiffness * squared / 2
    return spring.stiffness * (sympy.sqrt(squared) - spring.rest_length) ** 2 / 2


def conservative_potential(
    coordinates: Sequence[Coordinate], forces: Mapping[str, sympy.Expr], where: str
) -> sympy.Expr:
    """V with Q_i = -dV/dq_i for generalized forces that derive from a potential.

    Checks dQ_i/dq_j = dQ_j/dq_i, then integrates coordinate by coordinate:
    Phi = int Q_1 dq_1, Phi += int (Q_i - dPhi/dq_i) dq_i, V = -Phi.  Only
    integrals SymPy's rule-based integrator finds are accepted, so the time is
    bounded; otherwise the user is asked for the potential itself.
    """
    from sympy.integrals.manualintegrate import manualintegrate

    q = {c.name: c.q for c in coordinates}
    force = {name: forces.get(name, sympy.Integer(0)) for name in q}
    names = list(q)
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            if not is_zero(sympy.diff(force[a], q[b]) - sympy.diff(force[b], q[a])):
                raise ModelError(
                    f"the forces on '{a}' and '{b}' do not derive from a potential "
                    f"(dQ_{a}/d{b} != dQ_{b}/d{a}); give them under 'forces'",
                    field=where,
                )
    phi = sympy.Integer(0)
    for name in names:
        integrand = tidy(force[name] - sympy.diff(phi, q[name]))
        if integrand == 0:
            continue
        if integrand.is_polynomial(q[name]):
            primitive = sympy.integrate(sympy.expand(integrand), q[name])
        else:
            primitive = manualintegrate(integrand, q[name])
        if primitive.has(sympy.Integral):
            raise ModelError(
                f"cannot integrate the force on '{name}'; give the potential instead",
                field=f"{where}.{name}",
            )
        phi += primitive
    return tidy(-phi, q.values())

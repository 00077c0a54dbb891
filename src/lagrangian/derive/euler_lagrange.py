"""Lagrange's equations by the chain rule on symbols q, q', t.

For each coordinate, with p_i = dL/dq_i',

    d/dt p_i = sum_j (dp_i/dq_j' q_j'' + dp_i/dq_j q_j') + dp_i/dt,

so the equation d/dt p_i - dL/dq_i - Q_i + dF/dq_i' = 0 is linear in the
accelerations, with coefficients M_ij = dp_i/dq_j' (the Hessian of L in the
velocities).  No symbolic inverse and no unbounded simplification is used.
"""

from __future__ import annotations

import sympy

from ..algebra import positive_content, tidy
from ..errors import ModelError
from ..model import System
from .equations import CoordinateDerivation, EquationsOfMotion
from .solve import check_regular, solve_accelerations


def derive(system: System) -> EquationsOfMotion:
    """The equations of motion M(q, t) q'' = f(q, q', t) of ``system``."""
    coordinates = system.coordinates
    time = system.time
    lagrangian = system.lagrangian
    accelerations = [c.q_ddot for c in coordinates]
    for part, where in [(lagrangian, "lagrangian"), (system.dissipation, "dissipation")] + [
        (q, f"forces.{name}") for name, q in system.forces.items()
    ]:
        if part.has(*accelerations):
            raise ModelError("accelerations (q_ddot) are not allowed", field=where)

    n = len(coordinates)
    state = _state_symbols(system)
    mass_rows = []
    forcing = []
    steps = []
    for i, c in enumerate(coordinates):
        momentum = tidy(sympy.diff(lagrangian, c.q_dot), state)
        row = [tidy(sympy.diff(momentum, other.q_dot), state, trig=True) for other in coordinates]
        velocity_terms = sum(
            (sympy.diff(momentum, other.q) * other.q_dot for other in coordinates),
            sympy.diff(momentum, time),
        )
        force_gradient = tidy(sympy.diff(lagrangian, c.q), state)
        generalized_force = system.forces.get(c.name, sympy.Integer(0))
        dissipation_force = tidy(sympy.diff(system.dissipation, c.q_dot), state)
        rest = tidy(velocity_terms - force_gradient - generalized_force + dissipation_force, state)
        inertia = sympy.Add(*(m * a for m, a in zip(row, accelerations, strict=True)))
        mass_rows.append(row)
        forcing.append(tidy(-rest, state))
        steps.append(
            CoordinateDerivation(
                coordinate=c,
                momentum=momentum,
                momentum_rate=inertia + tidy(velocity_terms, state),
                force_gradient=force_gradient,
                generalized_force=generalized_force,
                dissipation_force=dissipation_force,
                equation=tidy((inertia + rest) / positive_content(inertia + rest, state), state),
            )
        )
    mass_matrix = sympy.ImmutableMatrix(n, n, [m for row in mass_rows for m in row])
    check_regular(mass_matrix, coordinates)
    forcing_vector = sympy.ImmutableMatrix(n, 1, forcing)
    return EquationsOfMotion(
        system=system,
        equations=tuple(step.equation for step in steps),
        mass_matrix=mass_matrix,
        forcing=forcing_vector,
        accelerations=solve_accelerations(mass_matrix, forcing_vector, coordinates, state),
        steps=tuple(steps),
    )



def _state_symbols(system: System) -> tuple[sympy.Symbol, ...]:
    """Everything that varies along a motion: q, q', q'' and t."""
    symbols = [system.time]
    for c in system.coordinates:
        symbols += [c.q, c.q_dot, c.q_ddot]
    return tuple(symbols)


"""The Hamiltonian by Legendre transform, and Hamilton's equations.

With p = dL/dq' = M(q, t) q' + b(q, t) for a Lagrangian quadratic in the
velocities, q' = M^-1 (p - b) and

    H(q, p, t) = p . q' - L,
    q' = dH/dp,   p' = -dH/dq + Q - dF/dq'   (Q and F expressed in p).

When H is too large to differentiate readably (a 5-link chain: M^-1 untidied,
minutes for dH/dq), Hamilton's equations are written with the identities
dH/dp = q'(q, p, t) and dH/dq|_p = -dL/dq|_q' at q' = q'(q, p, t), which are
equal and cost one substitution.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy

from ..algebra import tidy, tidy_fraction
from ..derive import EquationsOfMotion
from ..derive.solve import diagonal_blocks, solve_linear
from ..errors import ModelError
from ..provided import Provided
from ..sizes import exceeds

#: Largest H (tree nodes) whose derivatives are formed and tidied.
DIFFERENTIATE_MAX_NODES = 5_000


@dataclass(frozen=True)
class Hamiltonian:
    """H(q, p, t) with the velocities q'(q, p, t) used to build it."""

    # the LaTeX of output/, given by the facade (see lagrangian.provided)
    _repr_latex_ = Provided()

    expression: sympy.Expr
    momenta: Mapping[str, sympy.Symbol]  # coordinate name -> p_q
    velocities: Mapping[str, sympy.Expr]  # coordinate name -> q'(q, p, t)
    equations: Mapping[str, tuple[sympy.Expr, sympy.Expr]]  # name -> (q', p')

    def __repr__(self) -> str:  # the REPL shows H, not the dataclass fields
        return f"<Hamiltonian H = {self.expression}>"


def hamiltonian(eom: EquationsOfMotion) -> Hamiltonian:
    """The Legendre transform of L (requires a Lagrangian at most quadratic in q')."""
    system = eom.system
    coordinates = system.coordinates
    velocities = [c.q_dot for c in coordinates]
    if eom.mass_matrix.has(*velocities):
        raise ModelError(
            "the Legendre transform needs a Lagrangian quadratic in the velocities",
            field="lagrangian",
        )
    zero_velocity = dict.fromkeys(velocities, 0)
    linear_part = sympy.Matrix([step.momentum.xreplace(zero_velocity) for step in eom.steps])
    momenta = sympy.Matrix([c.p for c in coordinates])
    phase_state = (system.time, *(c.q for c in coordinates), *momenta)
    solved = solve_linear(eom.mass_matrix, momenta - linear_part, phase_state)
    if solved is None:
        raise ModelError("too many coupled coordinates for a symbolic Legendre transform")
    in_momenta = dict(zip(velocities, solved, strict=True))
    # H = (p - b) . M^-1 (p - b) / 2 - L(q, 0, t); each independent block of M over its
    # own denominator, so a diagonal M gives p_1^2/(2 M_11) + p_2^2/(2 M_22) + ...
    shifted = momenta - linear_part
    kinetic = sympy.Integer(0)
    for block in diagonal_blocks(eom.mass_matrix):
        part = sum((shifted[i] * solved[i] for i in block), sympy.Integer(0)) / 2
        kinetic += tidy_fraction(part, phase_state, trig=True)
    expression = kinetic + tidy(-system.lagrangian.xreplace(zero_velocity), phase_state)
    large = exceeds(expression, DIFFERENTIATE_MAX_NODES)
    equations = {}
    for c, velocity in zip(coordinates, solved, strict=True):
        forces = system.forces.get(c.name, sympy.Integer(0)) - sympy.diff(
            system.dissipation, c.q_dot
        )
        if large:  # the identities of the module docstring
            q_rate = velocity
            p_rate = (sympy.diff(system.lagrangian, c.q) + forces).xreplace(in_momenta)
        else:
            q_rate = tidy(sympy.diff(expression, c.p), phase_state)
            p_rate = tidy(-sympy.diff(expression, c.q) + forces.xreplace(in_momenta), phase_state)
        equations[c.name] = (q_rate, p_rate)
    return Hamiltonian(
        expression=expression,
        momenta={c.name: c.p for c in coordinates},
        velocities={c.name: v for c, v in zip(coordinates, solved, strict=True)},
        equations=equations,
    )

"""Equilibria of systems with holonomic constraints, and their small oscillations.

At rest (q' = 0) the equations M q'' = f + A^T lambda, with A = dc/dq for the
constraints c(q, t) = 0, leave q'' = 0 when

    G(q) + A(q)^T lambda = 0,   c(q) = 0,       G(q) = f(q, 0, t),

n + m equations for q and the multipliers lambda (the constraint forces that
hold the system at rest: for a pendulum in Cartesian coordinates, -2 l lambda
is the tension m g).  Small motions stay on the constraint surface: with N a
basis of the null space of A(q0) (the tangent directions), q = q0 + N s and

    N^T M0 N s'' + N^T C0 N s' + N^T K N s = 0,   K = -dG/dq - sum_j lambda_j d^2 c_j/dq^2,

the curvature of the constraints entering through the multipliers (the bordered
Hessian of W = V - lambda . c) [Goldstein, ch. 6; Arnold, Mathematical Methods, §22].
Constraints linear in the velocities that do not come from a c(q) are not handled.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import sympy

from ..algebra import tidy
from ..budget import checked_seconds, remaining
from ..derive import EquationsOfMotion
from ..errors import ModelError
from .conditions import stability_verdict
from .equilibria import Equilibrium, PointWithModes, equilibria
from .linear import LinearizedSystem, NormalModes
from .search import number_at
from .solving import in_child, solve_factored


@dataclass(frozen=True)
class ConstrainedEquilibrium(PointWithModes):
    """A rest point on the constraint surface, its multipliers and small oscillations."""

    point: Mapping[str, sympy.Expr]
    multipliers: Mapping[str, sympy.Expr]
    modes: NormalModes
    numeric: bool = False  # always symbolic (as for Equilibrium, where it may be numeric)
    at_defaults: bool = False  # the stability verdict holds at the default values only
    stability_condition: sympy.Basic | None = None  # for stability, when found (.conditions)


def rest_points(eom: EquationsOfMotion) -> tuple[Equilibrium | ConstrainedEquilibrium, ...]:
    """The equilibria of ``eom``: with holonomic constraints on the constraint surface with
    the multipliers (:func:`constrained_equilibria`), else :func:`equilibria`."""
    return constrained_equilibria(eom) if eom.constraints is not None else equilibria(eom)


def constrained_equilibria(
    eom: EquationsOfMotion, *, timeout: float = 10.0
) -> tuple[ConstrainedEquilibrium, ...]:
    """Rest points of a system with holonomic constraints (see the module docstring)."""
    timeout = checked_seconds(timeout, "timeout")
    system, forms = eom.system, eom.constraints
    if forms is None:
        raise ModelError("the system has no constraints: use equilibria()")
    if not all(forms.holonomic):
        raise ModelError("equilibria with constraints linear in the velocities are not computed")
    if not system.is_autonomous:
        return ()
    q = [c.q for c in system.coordinates]
    at_rest = {c.q_dot: sympy.Integer(0) for c in system.coordinates}
    rest_force = eom.forcing.xreplace(at_rest)
    gradients = forms.matrix.xreplace(at_rest)
    lambdas = list(forms.multipliers)
    equations = [
        tidy(rest_force[i] + sum(lam * gradients[j, i] for j, lam in enumerate(lambdas)))
        for i in range(len(q))
    ] + [tidy(c) for c in system.constraints]
    left = remaining()  # a stage's deadline, when sooner
    solutions = in_child(
        solve_factored, (equations, q + lambdas), timeout if left is None else min(timeout, left)
    )
    if not solutions:
        return ()
    results = []
    for solution in solutions:
        if set(solution) != set(q + lambdas):
            continue  # a family of rest points: not a single equilibrium
        if any(value.is_real is False for value in solution.values()):
            continue
        if not _real_at_defaults(system, solution.values()):
            continue  # as for unconstrained equilibria: a point that is not real at the defaults
        results.append(_equilibrium(eom, solution))
    return tuple(results)


def _real_at_defaults(system, values) -> bool:
    defaults = dict(system.parameter_values)
    if len(defaults) < len(system.parameters):
        return True  # no values to judge by
    for value in values:
        number = number_at(value, defaults)
        if number is not None and abs(number.imag) > 1e-9 * (1 + abs(number.real)):
            return False
    return True


def _equilibrium(eom: EquationsOfMotion, solution: Mapping) -> ConstrainedEquilibrium:
    system, forms = eom.system, eom.constraints
    q = [c.q for c in system.coordinates]
    at_rest = {c.q_dot: sympy.Integer(0) for c in system.coordinates}
    here = {s: solution[s] for s in q} | at_rest
    lambdas = [solution[lam] for lam in forms.multipliers]
    gradients = forms.matrix.xreplace(at_rest)
    stiffness = -eom.forcing.jacobian(q)
    for lam, constraint in zip(lambdas, system.constraints, strict=True):
        stiffness -= lam * sympy.hessian(constraint, q)
    tangent = gradients.xreplace(here).nullspace()
    basis = sympy.Matrix.hstack(*tangent) if tangent else sympy.zeros(len(q), 0)

    def reduced(matrix: sympy.Matrix) -> sympy.ImmutableMatrix:
        product = basis.T * matrix.xreplace(here) * basis
        return sympy.ImmutableMatrix(product.applyfunc(lambda e: tidy(e, trig=True)))

    damping = -eom.forcing.jacobian([c.q_dot for c in system.coordinates])
    point = {c.name: solution[c.q] for c in system.coordinates}
    linear = LinearizedSystem(
        system,
        point,
        reduced(eom.mass_matrix),
        reduced(damping),
        reduced(stiffness),
        dict(system.parameter_values),
    )
    modes = linear.normal_modes() if basis.cols else NormalModes.undetermined("no free direction")
    multipliers = {
        lam.name: tidy(value) for lam, value in zip(forms.multipliers, lambdas, strict=True)
    }
    verdict = stability_verdict(modes, damped=not linear.dissipative.is_zero_matrix)
    return ConstrainedEquilibrium(
        point, multipliers, modes, False, verdict.at_defaults, verdict.condition
    )

"""Lagrange's equations by the chain rule on symbols q, q', t.

For each coordinate, with p_i = dL/dq_i',

    d/dt p_i = sum_j (dp_i/dq_j' q_j'' + dp_i/dq_j q_j') + dp_i/dt,

so the equation d/dt p_i - dL/dq_i - Q_i + dF/dq_i' = 0 is linear in the
accelerations, with coefficients M_ij = dp_i/dq_j' (the Hessian of L in the
velocities).  No symbolic inverse and no unbounded simplification is used.
Systems with ``FAST_MIN_COORDINATES`` coordinates or more are derived by
:func:`lagrangian.derive.fast.derive_large`: the same equations, untidied.

Every symbolic step is bounded (:mod:`lagrangian.budget`): tidying by size, the
readable route by ``READABLE_SECONDS`` (past it, the large route: the same M and
f, untidied), and solving for q'' (and lambda) by ``SOLVE_SECONDS`` twice over:
first tidied, then as the untidied LU solution, and past that q'' is left to
the numerical solve (``accelerations`` is None, as on the large route).
"""

from __future__ import annotations

import dataclasses

import sympy

from ..algebra import FAST_MIN_COORDINATES, positive_content, tidy
from ..budget import attempt, within
from ..errors import ModelError, SingularMassMatrixError
from ..model import System
from .constraints import ConstraintForms, constraint_forms, solve_constrained
from .equations import CoordinateDerivation, EquationsOfMotion
from .fast import derive_large
from .solve import check_independent, check_regular, plain_solution, solve_accelerations

#: Seconds for the readable route's M, f and steps before the large route takes over.
READABLE_SECONDS = 10.0
#: Seconds for each attempt at q'' (and lambda): tidied, then untidied.
SOLVE_SECONDS = 5.0
#: Seconds for the large route, the last one: past it the model is refused.  The size
#: limits (model.limits) count the work of T before it starts, but not how many distinct
#: terms each entry of M gathers: 4 particles each moving with the sines of the same 200
#: coordinates took 80 s, where the 100-link chain (more pairs, alike terms) takes 5.
LARGE_SECONDS = 60.0


def derive(system: System) -> EquationsOfMotion:
    """The equations of motion M(q, t) q'' = f(q, q', t) of ``system``."""
    coordinates = system.coordinates
    accelerations = [c.q_ddot for c in coordinates]
    if _lagrangian_holds_any(system, accelerations):
        raise ModelError("accelerations (q_ddot) are not allowed", field="lagrangian")
    for part, where in [(system.dissipation, "dissipation")] + [
        (q, f"forces.{name}") for name, q in system.forces.items()
    ]:
        if part.has(*accelerations):
            raise ModelError("accelerations (q_ddot) are not allowed", field=where)

    forms = constraint_forms(system) if system.constraints else None
    if forms is not None:
        check_independent(forms.matrix, [f"constraints[{j}]" for j in range(forms.matrix.rows)])
    parts = None
    if len(coordinates) >= FAST_MIN_COORDINATES:
        large = _bounded_large(system, forms)
        if large is not None:
            return large
    else:
        parts = within(READABLE_SECONDS, "derive", lambda: _parts(system, forms), _none)
        large = None if parts is not None else _bounded_large(system, forms)
        if large is not None:  # the readable route was too slow: the same M and f, untidied
            solved = _solved(large.mass_matrix, large.forcing, forms, system)
            return dataclasses.replace(large, accelerations=solved[0], multipliers=solved[1])
    if parts is None:  # SymEngine cannot hold the model: readable, bounded by size alone
        parts = _parts(system, forms)
    mass_matrix, forcing_vector, steps = parts
    accelerations, multipliers = _solved(mass_matrix, forcing_vector, forms, system)
    return EquationsOfMotion(
        system=system,
        equations=tuple(step.equation for step in steps),
        mass_matrix=mass_matrix,
        forcing=forcing_vector,
        accelerations=accelerations,
        steps=tuple(steps),
        constraints=forms,
        multipliers=multipliers,
    )


def _none() -> None:
    return None


def _lagrangian_holds_any(system: System, symbols: list) -> bool:
    """Whether L holds one of ``symbols``: for the Lagrangian the build assembled in
    SymEngine, read from that form's free symbols (0.015 s for the 100-link chain's, where
    SymPy's ``has`` walks its tree in 0.056 s, and its SymPy form is not made); symbols
    are told apart by name, as the model has one symbol per name."""
    built = system.built_lagrangian
    if built is not None:
        names = {symbol.name for symbol in symbols}
        return any(symbol.name in names for symbol in built.free_symbols)
    return system.lagrangian.has(*symbols)


def _bounded_large(system: System, forms: ConstraintForms | None) -> EquationsOfMotion | None:
    large, undecided = attempt("derive", LARGE_SECONDS, lambda: derive_large(system, forms))
    if undecided is not None:
        raise ModelError(
            f"the equations of motion were not derived within {LARGE_SECONDS:g} s "
            f"({len(system.coordinates)} coordinates): the model is too large to derive"
        )
    return large


def _parts(system: System, forms: ConstraintForms | None) -> tuple:
    """M, f and the steps by the readable route: each part tidied."""
    coordinates = system.coordinates
    time = system.time
    lagrangian = system.lagrangian
    accelerations = [c.q_ddot for c in coordinates]
    n = len(coordinates)
    state = system.state_symbols
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
        constraint_force = (
            sum((lam * a for lam, a in zip(forms.multipliers, forms.matrix.col(i), strict=True)), 0)
            if forms
            else sympy.Integer(0)
        )
        rest = tidy(velocity_terms - force_gradient - generalized_force + dissipation_force, state)
        inertia = sympy.Add(*(m * a for m, a in zip(row, accelerations, strict=True)))
        mass_rows.append(row)
        forcing.append(tidy(-rest, state))
        equation, factor = _readable_equation(inertia + rest - constraint_force, state)
        steps.append(
            CoordinateDerivation(
                coordinate=c,
                momentum=momentum,
                momentum_rate=inertia + tidy(velocity_terms, state),
                force_gradient=force_gradient,
                generalized_force=generalized_force,
                dissipation_force=dissipation_force,
                constraint_force=constraint_force,
                equation=equation,
                divided_by=factor,
            )
        )
    mass_matrix = sympy.ImmutableMatrix(n, n, [m for row in mass_rows for m in row])
    try:
        check_regular(mass_matrix, coordinates)
    except SingularMassMatrixError as error:
        located = f"{system.source}: {error}" if system.source else str(error)
        raise SingularMassMatrixError(located) from None
    return mass_matrix, sympy.ImmutableMatrix(n, 1, forcing), steps


def _solved(mass_matrix, forcing, forms: ConstraintForms | None, system: System) -> tuple:
    """(q'', lambda) by name: tidied, else untidied, else (None, None); each try bounded."""
    coordinates, state = system.coordinates, system.state_symbols

    def named(solved) -> tuple:
        if solved is None:
            return None, None
        accelerations = {c.name: a for c, a in zip(coordinates, solved[0], strict=True)}
        if forms is None:
            return accelerations, None
        multipliers = {s.name: lam for s, lam in zip(forms.multipliers, solved[1], strict=True)}
        return accelerations, multipliers

    def tidied():
        if forms is None:
            solved = solve_accelerations(mass_matrix, forcing, coordinates, state)
            return None if solved is None else (list(solved.values()), None)
        return solve_constrained(mass_matrix, forcing, forms, state)

    def untidied():
        work = lambda: plain_solution(mass_matrix, forcing, forms)  # noqa: E731
        return within(SOLVE_SECONDS, "accelerations", work, _none)

    return named(within(SOLVE_SECONDS, "accelerations", tidied, untidied))


def _readable_equation(expr: sympy.Expr, state) -> tuple[sympy.Expr, sympy.Expr]:
    """The equation expr = 0 divided by its positive constant factor, terms grouped, and
    that factor (shown by ``derive --steps``: a step done by hand is said)."""
    factor = positive_content(expr, state)
    return tidy(expr / factor, state), factor

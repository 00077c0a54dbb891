"""Constraints by Lagrange multipliers.

A constraint c_j(q, q', t) = 0 is either holonomic, f_j(q, t) = 0, or linear in
the velocities, sum_k a_jk(q, t) q_k' + a_j0(q, t) = 0 (a holonomic one is used
through its time derivative).  With A_jk = dc_j/dq_k', Lagrange's equations gain
the constraint forces A^T lambda and the constraints, differentiated once, close
the system:

    M q'' = f + A^T lambda,
    A q'' = beta,   beta_j = -(sum_k dc_j/dq_k q_k' + dc_j/dt).

The multipliers lambda_j measure the constraint forces (for a pendulum in
Cartesian coordinates with x^2 + y^2 - l^2 = 0, the tension is -2 l lambda).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy

from ..algebra import tidy, tidy_fraction
from ..errors import ModelError
from ..model import System
from .solve import CRAMER_MAX_SIZE, solve_linear

#: Largest Schur complement A M^-1 A^T (in operations) whose solution is tidied.
SCHUR_MAX_OPS = 120
#: Largest entry (in operations, untidied) of the Schur complement and of beta - A M^-1 f
#: that trigonometric identities are tried on.  Those of a four-bar linkage's loop closure
#: (51-53 operations) took 0.8-3.2 s each in trigsimp and came out longer (78-94); the
#: Cartesian pendulum's and the rolling disc's (5-7) are where the identities pay.  The
#: driven four-bar's (12-30) took 0.15-0.3 s each, 1.4 s of its 1.7 s derivation, and
#: none came out shorter (its q'' and lambda are the same without them).
SCHUR_TRIG_MAX_OPS = 10


@dataclass(frozen=True)
class ConstraintForms:
    """The constraints as A q' + a0 = 0 and their differentiated form A q'' = beta."""

    multipliers: tuple[sympy.Symbol, ...]  # lambda1, lambda2, ...
    holonomic: tuple[bool, ...]
    matrix: sympy.ImmutableMatrix  # A, one row per constraint
    bias: sympy.ImmutableMatrix  # beta


def multiplier_symbols(count: int, taken: set[str]) -> tuple[sympy.Symbol, ...]:
    """lambda1, lambda2, ... (with a suffix where the model already uses the name)."""
    symbols = []
    for index in range(count):
        name = f"lambda{index + 1}"
        while name in taken:
            name += "_c"
        symbols.append(sympy.Symbol(name, real=True))
    return tuple(symbols)


def constraint_forms(system: System) -> ConstraintForms:
    """A and beta of the system's constraints; checks they are linear in the velocities."""
    velocities = [c.q_dot for c in system.coordinates]
    rows, bias, holonomic = [], [], []
    for j, constraint in enumerate(system.constraints):
        where = f"constraints[{j}]"
        is_holonomic = not constraint.has(*velocities)
        velocity_form = constraint_velocity_form(constraint, system)
        row = [tidy(sympy.diff(velocity_form, v), system.state_symbols) for v in velocities]
        if any(entry.has(*velocities) for entry in row):
            raise ModelError("a constraint must be linear in the velocities", field=where)
        if all(entry == 0 for entry in row):
            raise ModelError("the constraint involves no coordinate", field=where)
        rows.append(row)
        rate_without_accelerations = _time_derivative(velocity_form, system, skip_velocities=True)
        bias.append(tidy(-rate_without_accelerations, system.state_symbols))
        holonomic.append(is_holonomic)
    return ConstraintForms(
        multipliers=multiplier_symbols(len(rows), set(system.symbols)),
        holonomic=tuple(holonomic),
        matrix=sympy.ImmutableMatrix(rows),
        bias=sympy.ImmutableMatrix(len(bias), 1, bias),
    )


def constraint_velocity_form(constraint: sympy.Expr, system: System) -> sympy.Expr:
    """A q' + a0 of one constraint: itself when it has velocities, else its time derivative."""
    if constraint.has(*(c.q_dot for c in system.coordinates)):
        return constraint
    return _time_derivative(constraint, system)


def _time_derivative(expr: sympy.Expr, system: System, *, skip_velocities: bool = False):
    """d/dt by the chain rule; with ``skip_velocities`` the q'' terms are left out."""
    rate = sympy.diff(expr, system.time)
    for c in system.coordinates:
        rate += sympy.diff(expr, c.q) * c.q_dot
        if not skip_velocities:
            rate += sympy.diff(expr, c.q_dot) * c.q_ddot
    return rate


def solve_constrained(
    mass_matrix: sympy.Matrix,
    forcing: sympy.Matrix,
    forms: ConstraintForms,
    state: Sequence[sympy.Symbol],
) -> tuple[list[sympy.Expr], list[sympy.Expr]] | None:
    """(q'', lambda) of M q'' = f + A^T lambda, A q'' = beta; None if M is too large.

    By the Schur complement, which keeps the small systems small:
    x_f = M^-1 f, X = M^-1 A^T, (A X) lambda = beta - A x_f, q'' = x_f + X lambda.
    The Schur complement A X is dense and its entries are long: with more than
    ``CRAMER_MAX_SIZE`` constraints, or more than ``SCHUR_MAX_OPS`` operations in it,
    lambda is its LU solution, untidied.  Tidying into one fraction is what costs
    there: a chain of three particles in Cartesian coordinates (181 operations) took
    5 s for multipliers of 11,000 characters, untidied 0.04 s and 2,000 characters.
    Trigonometric identities are tried only on short entries (:data:`SCHUR_TRIG_MAX_OPS`).
    """
    columns = [sympy.Matrix(forcing)] + [
        sympy.Matrix(forms.matrix.row(j)).T for j in range(forms.matrix.rows)
    ]
    solved = []
    for column in columns:
        x = solve_linear(mass_matrix, column, state)
        if x is None:
            return None
        solved.append(sympy.Matrix(x))
    free, response = solved[0], sympy.Matrix.hstack(*solved[1:])

    def tidied(entry: sympy.Expr) -> sympy.Expr:
        return tidy(entry, state, trig=sympy.count_ops(entry) <= SCHUR_TRIG_MAX_OPS)

    schur = (forms.matrix * response).applyfunc(tidied)
    residual = (sympy.Matrix(forms.bias) - forms.matrix * free).applyfunc(tidied)
    small = schur.rows <= CRAMER_MAX_SIZE
    if not small or sum(sympy.count_ops(entry) for entry in schur) > SCHUR_MAX_OPS:
        multipliers = schur.LUsolve(residual)
        return list(free + response * multipliers), list(multipliers)
    multipliers = solve_linear(schur, residual, state, trig=True)
    accelerations = free + response * sympy.Matrix(multipliers)
    return (
        [tidy_fraction(a, state, trig=True) for a in accelerations],
        [tidy_fraction(lam, state, trig=True) for lam in multipliers],
    )

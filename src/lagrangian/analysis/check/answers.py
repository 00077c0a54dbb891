"""Each kind of answer against what the toolkit derives: right, equivalent or wrong.

What does not change the physics is equivalent, and said: a potential or Hamiltonian up
to a constant; a Lagrangian up to a constant factor and a total time derivative (the
Euler-Lagrange expressions of the student's L are those of the right one times a
constant); an equation up to a non-zero factor, or a combination of the equations (a
rank test on the rows [M_i | f_i] of M q'' = f at random points).  Anything else is
wrong, with the terms at fault (:mod:`.terms`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import sympy

from ...derive import EquationsOfMotion
from .reference import raw_equations
from .result import AnswerCheck, readable
from .sampling import PARAMETER_SETS, STATES, Points, close, per_set, state_free
from .terms import compare, groups, total_scale

NOUNS = {
    "kinetic": "the kinetic energy",
    "potential": "the potential energy",
    "lagrangian": "the Lagrangian",
    "hamiltonian": "the Hamiltonian",
    "momentum": "the momentum",
}


def euler_lagrange(lagrangian: sympy.Expr, eom: EquationsOfMotion) -> list[sympy.Expr]:
    """d/dt (dL/dq') - dL/dq for each coordinate, the time derivative by the chain rule."""
    coordinates, time = eom.coordinates, eom.system.time
    result = []
    for c in coordinates:
        momentum = sympy.diff(lagrangian, c.q_dot)
        rate = sympy.diff(momentum, time) + sum(
            (sympy.diff(momentum, d.q) * d.q_dot + sympy.diff(momentum, d.q_dot) * d.q_ddot
             for d in coordinates), sympy.S.Zero)  # fmt: skip
        result.append(rate - sympy.diff(lagrangian, c.q))
    return result


def by_terms(
    quantity: str,
    given_text: str,
    given: sympy.Expr,
    right: sympy.Expr,
    state: frozenset,
    at: Points,
    *,
    up_to_constant: bool = False,
) -> AnswerCheck:
    """An expression that must equal ``right`` (or differ by a constant)."""
    mine, theirs = groups(given, state, at), groups(right, state, at)
    if up_to_constant:  # a constant term is no fault where the constant does not matter
        mine, theirs = _moving(mine), _moving(theirs)
    scale = total_scale([*mine, *theirs])
    difference = at.evaluate(given - right)
    if close(difference, np.zeros_like(difference), scale):
        return AnswerCheck(quantity, given_text, "right", "right")
    if up_to_constant and state_free(difference, scale):
        constant = sympy.simplify(given - right)
        return AnswerCheck(
            quantity,
            given_text,
            "equivalent",
            f"right up to a constant ({readable(str(constant))}), which changes no motion",
        )
    return wrong(quantity, given_text, compare(mine, theirs).problems)


def _moving(found):
    return [group for group in found if not state_free(group.key_values)]


def wrong(quantity: str, given_text: str, problems, prefix: str = "") -> AnswerCheck:
    sentences = "; ".join(problem.sentence() for problem in problems)
    reason = prefix + (sentences or "it differs from the right one")
    return AnswerCheck(quantity, given_text, "wrong", reason, tuple(problems))


def lagrangian(
    given_text: str, given: sympy.Expr, eom: EquationsOfMotion, state: frozenset, at: Points
) -> AnswerCheck:
    """L up to a constant factor and a total time derivative (same equations of motion)."""
    right = eom.lagrangian
    plain = by_terms("lagrangian", given_text, given, right, state, at, up_to_constant=True)
    if plain.verdict != "wrong":
        return plain
    mine = [at.evaluate(e) for e in euler_lagrange(given, eom)]
    theirs = [at.evaluate(e) for e in euler_lagrange(right, eom)]
    factor = _common_factor(mine, theirs)
    if factor is None:
        return plain
    values, symbolic = factor
    if close(values, np.ones_like(values)):
        how = "a total time derivative"
    else:
        how = f"the constant factor {readable(str(symbolic))} and a total time derivative"
        difference = at.evaluate(given - symbolic * right) if symbolic.is_number else None
        if difference is not None and close(
            difference, np.zeros_like(difference), np.abs(at.evaluate(given))
        ):
            how = f"the constant factor {readable(str(symbolic))}"
    return AnswerCheck(
        "lagrangian",
        given_text,
        "equivalent",
        f"right up to {how}: the same equations of motion",
    )


def _common_factor(mine: Sequence[np.ndarray], theirs: Sequence[np.ndarray]):
    """(values per parameter set, the factor) with mine_i = factor * theirs_i for every i,
    the factor non-zero and free of the state; None when there is none."""
    stacked_mine, stacked_theirs = np.concatenate(mine, axis=1), np.concatenate(theirs, axis=1)
    usable = np.abs(stacked_theirs) > 1e-9 * np.nanmax(np.abs(stacked_theirs), initial=0.0)
    ratio = np.where(usable, stacked_mine / np.where(usable, stacked_theirs, 1.0), np.nan)
    factor = per_set(ratio)
    if not np.all(np.isfinite(factor)) or np.any(np.abs(factor) < 1e-9):
        return None
    scale = per_set(np.abs(stacked_theirs))
    if not close(stacked_mine, factor * stacked_theirs, scale * np.abs(factor)):
        return None
    return factor, _nice_number(factor)


def _nice_number(values: np.ndarray) -> sympy.Expr:
    """A factor the same in every parameter set as a short fraction, else its word."""
    value = float(values.flat[0])
    if close(values, np.full_like(values, value)):
        return sympy.nsimplify(value, rational=True, tolerance=1e-9)
    return sympy.Symbol("c")


def equation(
    given_text: str,
    given: sympy.Expr,
    eom: EquationsOfMotion,
    state: frozenset,
    at: Points,
) -> AnswerCheck:
    """One equation (expr = 0) against the Euler-Lagrange equations M q'' - f = 0."""
    coordinates = eom.coordinates
    raw = raw_equations(eom)
    shown = [step.equation for step in eom.steps]
    value = at.evaluate(given)
    for i, c in enumerate(coordinates):
        for reference in (raw[i], shown[i]):
            for sign in (1, -1):
                difference = value - sign * at.evaluate(reference)
                if close(difference, np.zeros_like(difference), np.abs(value)):
                    return AnswerCheck(
                        "equation", given_text, "right", f"right: the equation of {c.name}"
                    )
    used = _combination(given, raw, eom, at)
    if used:
        names = [coordinates[i].name for i in used]
        if len(used) == 1:
            factor = sympy.factor(sympy.cancel(given / raw[used[0]]))
            reason = (
                f"right up to a factor: the equation of {names[0]} times {readable(str(factor))}"
            )
        else:
            reason = f"right: a combination of the equations of {' and '.join(names)}"
        return AnswerCheck("equation", given_text, "equivalent", reason)
    mine = groups(given, state, at)
    best = None
    for i in range(len(coordinates)):
        accelerations = frozenset(c.q_ddot for c in coordinates)
        comparison = compare(mine, groups(raw[i], state, at), rescale=True, leading=accelerations)
        rank = (comparison.ok, -len(comparison.problems))
        if best is None or rank > best[0]:
            best = (rank, i, comparison)
    _, i, comparison = best
    if comparison.ok == 0:
        equations = ", ".join(c.name for c in coordinates)
        return AnswerCheck(
            "equation",
            given_text,
            "wrong",
            f"not related to the equations of motion (of {equations})",
        )
    return wrong(
        "equation",
        given_text,
        comparison.problems,
        prefix=f"the equation of {coordinates[i].name} with errors (all terms on the left): ",
    )


def _combination(
    given: sympy.Expr, raw: Sequence[sympy.Expr], eom: EquationsOfMotion, at: Points
) -> list[int]:
    """The equations whose combination (with coefficients that may depend on the state,
    not on the accelerations) the given one is; [] when it is none."""
    accelerations = [c.q_ddot for c in eom.coordinates]
    zero = dict.fromkeys(accelerations, 0)

    def rows(expr):  # [d expr/d q''_j ..., expr at q'' = 0] at every point
        parts = [sympy.diff(expr, a) for a in accelerations] + [expr.xreplace(zero)]
        return np.stack([at.evaluate(p) for p in parts], axis=-1)

    mine = rows(given)
    linear = at.evaluate(given) - at.evaluate(
        sum((sympy.diff(given, a) * a for a in accelerations), given.xreplace(zero))
    )
    if not close(linear, np.zeros_like(linear), np.abs(at.evaluate(given))):
        return []  # not linear in the accelerations: no combination of the equations
    theirs = np.stack([rows(e) for e in raw], axis=-2)  # (P, S, n, n + 1)
    used = np.zeros(len(raw), bool)
    for p in range(PARAMETER_SETS):
        for s in range(STATES):
            a, b = theirs[p, s].T, mine[p, s]
            if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
                continue
            size = np.abs(b).max()
            if size == 0:
                return []
            weights, *_ = np.linalg.lstsq(a, b, rcond=None)
            if np.abs(a @ weights - b).max() > 1e-7 * (
                size + np.abs(a).max() * np.abs(weights).max()
            ):
                return []
            used |= np.abs(weights) > 1e-9 * np.abs(weights).max()
    return [i for i in range(len(raw)) if used[i]]


def conserved(
    given_text: str,
    given: sympy.Expr,
    eom: EquationsOfMotion,
    known: Sequence[tuple[str, sympy.Expr]],
    state: frozenset,
    at: Points,
) -> AnswerCheck:
    """A quantity conserved along every motion: dC/dt = 0 with q'' of M q'' = f."""
    coordinates, time = eom.coordinates, eom.system.time
    value = at.evaluate(given)
    if state_free(value, np.abs(value)):
        return AnswerCheck(
            "conserved", given_text, "wrong", "a constant: it does not depend on the motion"
        )
    accelerations = _accelerations(eom, at)
    pieces = [at.evaluate(sympy.diff(given, time))]
    for j, c in enumerate(coordinates):
        pieces.append(at.evaluate(sympy.diff(given, c.q) * c.q_dot))
        pieces.append(at.evaluate(sympy.diff(given, c.q_dot)) * accelerations[..., j])
    rate = sum(pieces)
    scale = sum(np.abs(np.nan_to_num(piece)) for piece in pieces)
    if close(rate, np.zeros_like(rate), scale):
        return AnswerCheck(
            "conserved", given_text, "right", "right: its rate of change along every motion is 0"
        )
    mine = _moving(groups(given, state, at))
    best = None
    for name, expression in known:
        comparison = compare(mine, _moving(groups(expression, state, at)), rescale=True)
        rank = (comparison.ok, -len(comparison.problems))
        if best is None or rank > best[0]:
            best = (rank, name, comparison)
    prefix = "not conserved: its rate of change along the motion is not 0"
    if best is None or best[2].ok == 0:
        return AnswerCheck("conserved", given_text, "wrong", prefix)
    return wrong("conserved", given_text, best[2].problems, prefix=f"{prefix}; as {best[1]}: ")


def _accelerations(eom: EquationsOfMotion, at: Points) -> np.ndarray:
    """q'' solved from M q'' = f at every point, shape (P, S, n)."""
    n = len(eom.coordinates)
    mass = np.stack(
        [np.stack([at.evaluate(eom.mass_matrix[i, j]) for j in range(n)], -1) for i in range(n)],
        -2,
    )
    forcing = np.stack([at.evaluate(eom.forcing[i]) for i in range(n)], -1)
    result = np.full(forcing.shape, np.nan)
    for index in np.ndindex(forcing.shape[:-1]):
        try:
            result[index] = np.linalg.solve(mass[index], forcing[index])
        except np.linalg.LinAlgError:
            continue
    return result

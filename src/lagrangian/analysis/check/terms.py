"""A student's expression and the right one, term by term: missing, extra, factor, sign.

Both are expanded into sums of products; each product is split into its *key*, the
factors that depend on the state (q, q', q'', p, t), and its *coefficient*, the
parameters and numbers.  Terms whose keys are proportional with a ratio that does not
depend on the state are one group (``m1 l1^2 theta1'^2/2 + m2 l1^2 theta1'^2/2``), and a
student's group is matched with the right group of proportional key.  Keys and
coefficients are compared numerically (:mod:`.sampling`), so that ``cos(theta1 -
theta2)`` and ``cos(theta2 - theta1)`` or ``sqrt(m x^2)`` and ``sqrt(m) Abs(x)`` match
however they were written; the page's checker does the same in JavaScript.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import sympy

from ...errors import ModelError
from .result import TermProblem
from .sampling import Points, close, magnitude, per_set, state_free


@dataclass(frozen=True, eq=False)
class Group:
    """Terms with proportional keys: ``term`` (their sum), ``key`` (the first one's) and
    the values of the key (per point) and of the coefficient (per parameter set)."""

    term: sympy.Expr
    key: sympy.Expr
    key_values: np.ndarray
    coefficient_values: np.ndarray
    scale: np.ndarray  # sum of |term| over the pieces (for rounding)


#: A sum raised to a larger power is kept whole (as the page's checker keeps it), and an
#: answer of more terms than MAX_TERMS once expanded is refused: the diagnosis is for
#: what a student writes, and neither may cost more than a moment.
MAX_POWER, MAX_TERMS = 6, 500


def split(expr: sympy.Expr, state: frozenset[sympy.Symbol]) -> list[tuple[sympy.Expr, sympy.Expr]]:
    """(coefficient, key) of each term of ``expr`` expanded (products multiplied out,
    integer powers of sums up to :data:`MAX_POWER`; function arguments, other powers and
    logarithms kept as written).  Raises ModelError past :data:`MAX_TERMS` terms."""
    whole = {
        power: sympy.Dummy()
        for power in expr.atoms(sympy.Pow)
        if power.base.is_Add and power.exp.is_Integer and power.exp > MAX_POWER
    }
    expanded = sympy.expand(
        expr.xreplace(whole),
        deep=True, power_exp=False, power_base=False, log=False, multinomial=True, mul=True,
    )  # fmt: skip
    terms = sympy.Add.make_args(expanded)
    if len(terms) > MAX_TERMS:
        raise ModelError(f"too many terms to compare one by one ({len(terms)} once multiplied "
                         f"out, at most {MAX_TERMS})")  # fmt: skip
    back = {dummy: power for power, dummy in whole.items()}
    state = state | frozenset(d for p, d in whole.items() if p.free_symbols & state)
    pieces = []
    for term in terms:
        coefficient, key = [], []
        for factor in sympy.Mul.make_args(term):
            (key if factor.free_symbols & state else coefficient).append(factor)
        pieces.append((sympy.Mul(*coefficient).xreplace(back), sympy.Mul(*key).xreplace(back)))
    return pieces


def groups(expr: sympy.Expr, state: frozenset[sympy.Symbol], at: Points) -> list[Group]:
    """The groups of ``expr`` (those whose terms cancel dropped)."""
    found: list[list] = []  # [key, key values, terms, coefficient values, scale]
    for coefficient, key in split(expr, state):
        key_values = at.evaluate(key)
        coefficient_values = per_set(at.evaluate(coefficient))
        size = np.abs(coefficient_values * key_values)
        for entry in found:
            ratio = key_values / entry[1]
            if state_free(ratio):
                entry[2].append(coefficient * key)
                entry[3] = entry[3] + coefficient_values * per_set(ratio)
                entry[4] = entry[4] + np.nan_to_num(size)
                break
        else:
            found.append([key, key_values, [coefficient * key], coefficient_values, size])
    result = []
    for key, key_values, terms, coefficient_values, scale in found:
        value = coefficient_values * key_values
        if close(value, np.zeros_like(value), scale):
            continue  # the terms cancel
        term = sympy.factor_terms(sympy.Add(*terms))
        result.append(Group(term, key, key_values, coefficient_values, scale))
    return result


@dataclass(frozen=True)
class Comparison:
    """The problems of the student's groups against the right ones, ``ok`` the groups
    that agree, after the student's expression was multiplied by ``scale`` (1 or the
    factor of an equation or conserved quantity written with another normalisation)."""

    problems: tuple[TermProblem, ...]
    ok: int
    scale: sympy.Expr


def compare(
    given: Sequence[Group],
    right: Sequence[Group],
    *,
    rescale: bool = False,
    leading: frozenset[sympy.Symbol] = frozenset(),
) -> Comparison:
    """Match groups by proportional keys and say what is wrong with each.

    With ``rescale``, the student's expression may be the right one times any factor,
    even one that depends on the state (an equation divided by m r): each ratio of a
    student's term to a right one is tried as the factor, those of terms with the same
    ``leading`` symbols only when there are such (an equation's accelerations: one
    normalises the equation of q by its q'' term, even by a function of the state), else
    the ratios free of the state that make at least two groups agree; the one that makes
    the most groups agree is kept; the
    expected terms are printed times it, in the student's scale.
    """
    unit = np.ones_like(right[0].key_values) if right else np.ones((1, 1))
    if not rescale or not given or not right:
        return _matched(given, right, unit, sympy.S.One)
    led = _factors(given, right, leading) if leading else []
    candidates = led or [
        (values, symbolic)
        for values, symbolic in _factors(given, right, frozenset())
        if state_free(values)
    ]
    best = (None, _matched(given, right, unit, sympy.S.One))
    for values, symbolic in candidates:
        comparison = _matched(given, right, values, symbolic)
        if not led and comparison.ok < 2:  # one term alike is no evidence of a scale
            continue
        rank = (comparison.ok, -len(comparison.problems))
        if best[0] is None or rank > best[0]:
            best = (rank, comparison)
    return best[1]


def _factors(given: Sequence[Group], right: Sequence[Group], leading: frozenset) -> list:
    """(values, expression) of student term / right term, for pairs with the same leading
    symbols (every pair when ``leading`` is empty)."""
    found = []
    for mine in given:
        for theirs in right:
            symbols = theirs.key.free_symbols & leading
            if leading and (not symbols or symbols != mine.key.free_symbols & leading):
                continue
            values = (mine.coefficient_values * mine.key_values) / (
                theirs.coefficient_values * theirs.key_values
            )
            found.append((values, sympy.cancel(mine.term / theirs.term)))
    return found


def _matched(
    given: Sequence[Group], right: Sequence[Group], factor: np.ndarray, symbolic: sympy.Expr
) -> Comparison:
    """The student's groups against the right ones times ``factor`` (values per point)."""
    pairs = []  # (student group, right group, student coefficient in the right key's terms)
    unmatched_right = list(right)
    extra = []
    for group in given:
        for candidate in unmatched_right:
            ratio = group.key_values / (candidate.key_values * factor)
            if state_free(ratio):
                pairs.append((group, candidate, group.coefficient_values * per_set(ratio)))
                unmatched_right.remove(candidate)
                break
        else:
            extra.append(group)
    problems, ok = [], 0
    for student, expected, mine in pairs:
        theirs = expected.coefficient_values
        wanted = printed_term(expected.term * symbolic)
        if close(mine, theirs):
            ok += 1
        elif close(mine, -theirs):
            problems.append(TermProblem(str(student.term), "sign", wanted))
        else:
            problems.append(TermProblem(str(student.term), "factor", wanted))
    for group in unmatched_right:
        wanted = printed_term(group.term * symbolic)
        problems.append(TermProblem(wanted, "missing", wanted))
    for group in extra:
        problems.append(TermProblem(str(group.term), "extra", None))
    return Comparison(tuple(problems), ok, symbolic)


def printed_term(expr: sympy.Expr) -> str:
    """A term as the diagnosis prints it (SymPy syntax, common factors taken out)."""
    return str(sympy.factor_terms(sympy.cancel(expr)))


def total_scale(parts: Sequence[Group]) -> np.ndarray:
    return magnitude([group.scale for group in parts])

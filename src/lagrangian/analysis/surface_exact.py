"""Exact forms of the rest points a numerical search found on a constraint surface.

The multi-start search (:mod:`.surface_search`) gives every rest point at the parameter
values; SymPy then tries, within :data:`EXACT_SECONDS` of CPU for all the points of a
model together, to give them their exact forms (in the parameters).  The equations
F(q, lambda) = 0 of :mod:`.constrained` are hard to solve whole (a four-bar's loop
closures: not within minutes; a slider-crank's: 5 s), but a point's coordinates at 0, its
angles at a multiple of pi/12 and its multipliers at 0 are very likely exact values: with
them put in ("pinned") the equations left are smaller, and SymPy solves them at once (the
slider-crank's: 0.2 s for two of its points).  So is a length at the value of a parameter
(a bead on a turning hoop at r = R, at the angle acos(g/(Omega^2 R)): SymPy takes 2.3 s
for the whole system, 0.1 s with r = R put in).  A pin that holds at these values only, not
for all values of the parameters, leaves the equations without a solution, and SymPy
says so: an exact solution is one for every value.  A solution is the exact form of a
point where its numbers at the values are the point's.  Points no pinned system gives
are tried with the whole system in the time left, where at most one unknown appears
inside a function: SymPy's solve decides a system trigonometric in one unknown (it
factors, then inverts), not one coupled in several (a four-bar's, or a two-link chain's
loop closure: no answer in 30 s), whose points stay numerical at once.

The numerical point is always there; what runs out of time is only its exact form, and
each point says which one it is (``numeric``).  The budget is CPU time (the child's own,
:mod:`lagrangian.budget`), so the same machine gives the same answer at any load.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import sympy

from ..algebra import as_expression, is_zero, tidy
from ..budget import cpu_seconds
from .search import number_at
from .solving import in_child, solve_factored
from .surface_search import SurfaceRoot

#: CPU seconds for SymPy's solves that give the exact forms of a model's rest points (all
#: together, every model alike; and again for the closed-form modes of each exact point,
#: :mod:`.constrained`): the built-in slider-crank's two pinned systems take 0.6 s.
EXACT_SECONDS = 1.0
#: The part of them the whole system, nothing pinned, may take: SymPy solves a simple one
#: whole in 0.07-0.23 s (a bead on a turning tilted wire, a Cartesian or spherical
#: pendulum, two masses on a rod); one it cannot solve would take any budget, and costs
#: this much before its points are given numerically.
UNPINNED_SECONDS = 0.3
#: A coordinate or multiplier within this of a pin (relative to 1 + its size) is pinned.
PIN_TOLERANCE = 1e-10
#: Angles are pinned at the multiples of pi / PI_DIVISIONS (pi/12: 15 degrees, and with it
#: pi/2, pi/3, pi/4, pi/6).
PI_DIVISIONS = 12
#: Distance (relative) below which an exact solution's numbers are a numerical point's.
SAME_POINT = 1e-6


def exact_solutions(
    equations: Sequence[sympy.Expr],
    q: Sequence[sympy.Symbol],
    lambdas: Sequence[sympy.Symbol],
    roots: Sequence[SurfaceRoot],
    angles: Sequence[bool],
    values: Mapping[str, float],
    seconds: float,
) -> dict[int, dict]:
    """SymPy's solutions of ``equations`` (= 0, in ``q`` and ``lambdas``) that are the
    exact forms of ``roots`` (found at the parameter ``values``), by the index of the root
    (each a dict from the unknowns, as SymPy's solve gives; a multiplier missing where
    SymPy left it free), found within ``seconds`` of CPU.  The solutions that are none of
    the roots are left out: the search's points are the answer, SymPy gives their forms."""
    begun = cpu_seconds()
    unknowns = {*q, *lambdas}
    symbols = {s for e in equations for s in e.free_symbols} - unknowns
    parameters = {s: values[s.name] for s in symbols if s.name in values}
    systems: dict[tuple, list[int]] = {}
    for index, root in enumerate(roots):
        key = tuple(pinned(root, q, lambdas, angles, parameters).items())
        if key:
            systems.setdefault(key, []).append(index)
    # most pins first: the smallest systems, the quickest to solve
    order = sorted(systems, key=lambda key: -len(key))
    if len(_inside_functions(equations, unknowns)) <= 1:
        order.append(())
    matched: dict[int, dict] = {}
    for key in order:
        wanted = systems.get(key, range(len(roots)))
        wanted = [i for i in wanted if i not in matched]
        left = seconds - (cpu_seconds() - begun)
        if not key:
            left = min(left, UNPINNED_SECONDS)
        if not wanted or left <= 0:
            continue
        for solution in _solved(equations, [*q, *lambdas], dict(key), left):
            index = _root_of(solution, q, roots, angles, values)
            if index is not None and index not in matched:
                matched[index] = solution
    return matched


def _inside_functions(equations: Sequence[sympy.Expr], unknowns: set) -> set:
    """The unknowns that appear inside a function (sin, cos, exp, ...) of ``equations``."""
    inside: set = set()
    for equation in equations:
        for call in equation.atoms(sympy.Function):
            inside |= call.free_symbols & unknowns
    return inside


def pinned(
    root: SurfaceRoot,
    q: Sequence[sympy.Symbol],
    lambdas: Sequence[sympy.Symbol],
    angles: Sequence[bool],
    parameters: Mapping[sympy.Symbol, float],
) -> dict[sympy.Symbol, sympy.Expr]:
    """The exact values ``root`` very likely has: a coordinate at 0, (an angle) at a
    multiple of pi/PI_DIVISIONS, or (a length) at plus or minus the value of one of the
    ``parameters`` and of no other (a bead held on a hoop at r = R); a multiplier at 0
    (where A has full rank: elsewhere the least-squares multipliers are one choice of
    many)."""
    pins: dict[sympy.Symbol, sympy.Expr] = {}
    scale = 1.0 + float(np.abs(root.q).max(initial=0.0))
    for symbol, x, angle in zip(q, root.q, angles, strict=True):
        steps = x / (math.pi / PI_DIVISIONS) if angle else 0.0
        if abs(x) <= PIN_TOLERANCE * scale:
            pins[symbol] = sympy.Integer(0)
        elif angle and abs(steps - round(steps)) <= PIN_TOLERANCE * scale:
            pins[symbol] = sympy.pi * sympy.Rational(round(steps), PI_DIVISIONS)
        elif not angle:
            same = [
                sign * p
                for p, v in parameters.items()
                for sign in (1, -1)
                if abs(x - sign * v) <= PIN_TOLERANCE * scale
            ]
            if len(same) == 1:  # two parameters of that value: which one it is, is unknown
                pins[symbol] = same[0]
    if root.rank == len(lambdas):
        size = 1.0 + float(np.abs(root.multipliers).max(initial=0.0))
        for symbol, x in zip(lambdas, root.multipliers, strict=True):
            if abs(x) <= PIN_TOLERANCE * size:
                pins[symbol] = sympy.Integer(0)
    return pins


def _solved(
    equations: Sequence[sympy.Expr], unknowns: list, pins: dict, seconds: float
) -> list[dict]:
    """The solutions of ``equations`` with ``pins`` put in (each with the pins), by SymPy
    in a child process given ``seconds`` of CPU; none where it ran out of time."""
    left = [tidy(e.xreplace(pins)) for e in equations]
    left = [e for e in left if not is_zero(e)]  # held by the pins (solve_factored: no root)
    free = [u for u in unknowns if u not in pins]
    solutions = in_child(_solved_tidily, (left, free), seconds) if left else [{}]
    return [pins | solution for solution in solutions or []]


def _solved_tidily(equations: list[sympy.Expr], unknowns: list) -> list[dict]:
    """:func:`solve_factored` without SymPy's simplification of each solution (most of its
    time), the values tidied instead (cheaper, and only those kept)."""
    solutions = solve_factored(equations, unknowns, simplify=False)
    return [{k: tidy(v) for k, v in solution.items()} for solution in solutions]


def covered(
    solutions: Sequence[dict],
    q: Sequence[sympy.Symbol],
    roots: Sequence[SurfaceRoot],
    angles: Sequence[bool],
    values: Mapping[str, float],
) -> bool:
    """Every one of ``roots`` (found at ``values``) is one of SymPy's ``solutions`` there."""
    found = {_root_of(solution, q, roots, angles, values) for solution in solutions}
    return found >= set(range(len(roots)))


def _root_of(
    solution: dict,
    q: Sequence[sympy.Symbol],
    roots: Sequence[SurfaceRoot],
    angles: Sequence[bool],
    values: Mapping[str, float],
) -> int | None:
    """The index of the root ``solution`` gives at ``values`` (angles modulo 2 pi), or None
    (a solution that leaves a coordinate free, or not real there, or not one of them)."""
    if not set(q) <= set(solution):
        return None
    numbers = [number_at(as_expression(solution[s]), values) for s in q]
    if any(z is None or abs(z.imag) > SAME_POINT * (1 + abs(z.real)) for z in numbers):
        return None
    point = [z.real for z in numbers]
    for index, root in enumerate(roots):
        if all(
            _distance(x, y, angle) <= SAME_POINT * max(1.0, abs(x), abs(y))
            for x, y, angle in zip(point, root.q, angles, strict=True)
        ):
            return index
    return None


def _distance(x: float, y: float, angle: bool) -> float:
    return abs(math.remainder(x - y, 2 * math.pi)) if angle else abs(x - y)

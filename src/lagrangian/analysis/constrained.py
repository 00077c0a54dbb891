"""Equilibria of systems with holonomic constraints, and their small oscillations.

At rest (q' = 0) the equations M q'' = f + A^T lambda, with A = dc/dq for the
constraints c(q, t) = 0, leave q'' = 0 when

    G(q) + A(q)^T lambda = 0,   c(q) = 0,       G(q) = f(q, 0, t),

n + m equations for q and the multipliers lambda (the constraint forces that
hold the system at rest: for a pendulum in Cartesian coordinates, -2 l lambda
is the tension m g).  A numerical multi-start search on the constraint surface
(:mod:`.surface_search`) finds the points at the default parameter values first: they
are always the answer.  SymPy then gives their exact forms where it can within a small
CPU budget, the same for every model (:mod:`.surface_exact`: the values a point very
likely has exactly, 0 or a multiple of pi/12, put in first); a point it does not give
in time stays numerical (``numeric=True``: a four-bar's loop closures are beyond it),
so that what runs out of time is only the exact form, never a point.  Where some
parameters have no value there is nothing to search at: SymPy solves the whole system
then (a share of the stage's time), and a search at random values checks the answer.

Small motions stay on the constraint surface: with N a basis of the null space of
A(q0) (the tangent directions), q = q0 + N s and

    N^T M0 N s'' + N^T C0 N s' + N^T K N s = 0,   K = -dG/dq - sum_j lambda_j d^2 c_j/dq^2,

the curvature of the constraints entering through the multipliers (the bordered
Hessian of W = V - lambda . c) [Goldstein, ch. 6; Arnold, Mathematical Methods, §22].
The mode shapes are given in the coordinates q (N s, first non-zero entry 1; computed in
:mod:`.surface_modes`).  Where
A loses rank at a point (constraints redundant there) the multipliers that hold it
are not determined and the null space of A is not the tangent space of the surface:
the point is reported with neither (``redundant`` > 0, and a note says so).
Constraints linear in the velocities that do not come from a c(q) are not handled.
"""

from __future__ import annotations

import random
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..algebra import is_zero, tidy
from ..budget import checked_seconds, remaining, within
from ..derive import EquationsOfMotion
from ..distributions import without_distributions
from ..errors import ModelError
from .continua import SAME_LEVEL
from .equilibria import SYMBOLIC_SHARE, Equilibrium, PointWithModes, equilibria
from .linear import NormalModes, Stability
from .search import number_at
from .solving import in_child, solve_factored
from .surface_exact import EXACT_SECONDS, covered, exact_solutions
from .surface_modes import SurfaceModes
from .surface_search import RANK_TOLERANCE, SurfaceRoot, SurfaceSearch


@dataclass(frozen=True)
class ConstrainedEquilibrium(PointWithModes):
    """A rest point on the constraint surface, its multipliers and small oscillations.

    ``numeric``: found numerically at the default parameter values; ``redundant``: how
    many constraints are redundant at the point (A's rank short of their number: then
    ``multipliers`` is empty, they are not determined, and the modes undetermined).
    """

    point: Mapping[str, sympy.Expr]
    multipliers: Mapping[str, sympy.Expr]
    modes: NormalModes
    numeric: bool = False
    at_defaults: bool = False  # the stability verdict holds at the default values only
    stability_condition: sympy.Basic | None = None  # for stability, when found (.conditions)
    redundant: int = 0


@dataclass(frozen=True)
class SurfaceRestPoints:
    """The rest points on a constraint surface and what was not reported (``notes``)."""

    points: tuple[ConstrainedEquilibrium, ...]
    notes: tuple[str, ...] = ()


def rest_points(eom: EquationsOfMotion) -> tuple[Equilibrium | ConstrainedEquilibrium, ...]:
    """The equilibria of ``eom``: with holonomic constraints on the constraint surface with
    the multipliers (:func:`constrained_equilibria`), else :func:`equilibria`."""
    return constrained_equilibria(eom) if eom.constraints is not None else equilibria(eom)


def constrained_equilibria(
    eom: EquationsOfMotion, *, timeout: float = 10.0
) -> tuple[ConstrainedEquilibrium, ...]:
    """Rest points of a system with holonomic constraints (see the module docstring)."""
    return surface_rest_points(eom, timeout=timeout).points


def surface_rest_points(eom: EquationsOfMotion, *, timeout: float = 10.0) -> SurfaceRestPoints:
    """:func:`constrained_equilibria` with the notes on what was not reported or not
    decided: a family of rest points (one member given), constraints redundant at a point,
    a gradient dc/dq that vanishes all over the surface.  ``timeout`` bounds SymPy's solve
    (at most :data:`~.surface_exact.EXACT_SECONDS` where every parameter has a value, and
    less when a deadline of :mod:`lagrangian.budget` ends sooner)."""
    timeout = checked_seconds(timeout, "timeout")
    system, forms = eom.system, eom.constraints
    if forms is None:
        raise ModelError("the system has no constraints: use equilibria()")
    if not all(forms.holonomic):
        raise ModelError("equilibria with constraints linear in the velocities are not computed")
    if not system.is_autonomous:
        return SurfaceRestPoints(
            (), ("equilibria: none in general, the system depends explicitly on t",)
        )
    q = [c.q for c in system.coordinates]
    at_rest = {c.q_dot: sympy.Integer(0) for c in system.coordinates}
    rest_force = eom.forcing.xreplace(at_rest)
    unspecified = sorted({str(a.func) for g in rest_force for a in g.atoms(AppliedUndef)})
    if unspecified:
        raise ModelError(
            "cannot locate equilibria: the forces at rest involve the unspecified "
            "function(s) " + ", ".join(unspecified)
        )
    if all(is_zero(g) for g in rest_force):
        return SurfaceRestPoints((_everywhere(eom, numeric=False),))
    gradients = forms.matrix.xreplace(at_rest)
    lambdas = list(forms.multipliers)
    equations = [
        tidy(rest_force[i] + sum(lam * gradients[j, i] for j, lam in enumerate(lambdas)))
        for i in range(len(q))
    ] + [tidy(c) for c in system.constraints]
    search = SurfaceSearch(eom)
    if len(system.parameter_values) < len(system.parameters):
        return _solved_first(eom, equations, search, timeout)
    defaults = dict(system.parameter_values)
    table = {p.symbol: sympy.Float(defaults[p.name]) for p in system.parameters}
    if all(is_zero(g.xreplace(table)) for g in rest_force):  # balanced at these values
        return SurfaceRestPoints((_everywhere(eom, numeric=True),))
    roots = search.roots(defaults)
    numeric = tuple(_numeric_equilibrium(eom, root) for root in roots)
    kept, families = _grouped(eom, numeric)
    alone = [i for i in kept if i not in families]  # a family's member has no exact form
    left = remaining()
    seconds = min(timeout, EXACT_SECONDS, *(() if left is None else (SYMBOLIC_SHARE * left,)))
    exact = exact_solutions(
        equations, q, lambdas, [roots[i] for i in alone], search.angles, defaults, seconds
    )
    by_root = {alone[j]: solution for j, solution in exact.items()}
    found = tuple(
        _exact_or(eom, by_root[i], numeric[i], seconds) if i in by_root else numeric[i]
        for i in kept
    )
    notes = (
        *families.values(),
        *redundancy_notes(found),
        *_degenerate(search, defaults, lambdas, found),
    )
    return SurfaceRestPoints(found, notes)


def _solved_first(
    eom: EquationsOfMotion, equations: list, search: SurfaceSearch, timeout: float
) -> SurfaceRestPoints:
    """The rest points where some parameters have no value: there is no number to give,
    and SymPy's solve of the whole system has the time (a share of the stage's); the
    numerical search at random values meanwhile checks that it missed none."""
    system = eom.system
    q, lambdas = [c.q for c in system.coordinates], list(eom.constraints.multipliers)
    values = _random_values(system)
    left = remaining()
    solutions = in_child(
        solve_factored,
        (equations, q + lambdas),
        timeout if left is None else min(timeout, SYMBOLIC_SHARE * left),
        meanwhile=lambda: search.roots(values),
    )
    symbolic, families = _symbolic_points(eom, solutions or [])
    roots = search.roots(values)
    if solutions is not None and (families or covered(solutions, q, roots, search.angles, values)):
        found = tuple(_equilibrium(eom, point, multipliers) for point, multipliers in symbolic)
        notes = (*families, *redundancy_notes(found), *_degenerate(search, values, lambdas, found))
        return SurfaceRestPoints(found, notes)
    missing = [p.name for p in system.parameters if p.default is None]
    said = "cannot solve for" if solutions is None else "found only some of"
    raise ModelError(
        f"SymPy {said} the equilibria on the constraint surface; give default values for "
        + ", ".join(missing)
        + " to locate them numerically"
    )


def _exact_or(
    eom: EquationsOfMotion, solution: dict, numeric: ConstrainedEquilibrium, seconds: float
) -> ConstrainedEquilibrium:
    """The point of SymPy's ``solution`` with its modes in closed form, found within
    ``seconds``; else the ``numeric`` one (the same point)."""
    points, _ = _symbolic_points(eom, [solution])
    if not points or seconds <= 0:
        return numeric
    point, multipliers = points[0]
    return within(
        seconds, "exact form", lambda: _equilibrium(eom, point, multipliers), lambda: numeric
    )


def _degenerate(search: SurfaceSearch, values, lambdas: list, found: tuple) -> tuple[str, ...]:
    """Why nothing was found, where dc/dq is rank-deficient wherever the search reached the
    surface (a point it does find there is said by :func:`redundancy_notes`)."""
    rank = None if found else search.surface_rank(values)
    if rank is None or rank >= len(lambdas):
        return ()
    count = f"{len(lambdas)} constraint{'s' if len(lambdas) > 1 else ''}"
    return (
        f"equilibria: dc/dq has rank {rank} for {count} all over the constraint surface (a"
        " constraint written squared, or one that repeats another there): its multipliers"
        " cannot hold the system at rest, and no point held by them is reported; write each"
        " constraint so that its gradient does not vanish",
    )


def _grouped(eom: EquationsOfMotion, found: tuple) -> tuple[list[int], dict[int, str]]:
    """Numerical roots on a continuum of rest points merged (a bead held on a sphere by a
    spring from its centre rests anywhere on it: a root per start), as :mod:`.continua`
    does without constraints: roots with omega^2 = 0 grouped by their count and the value
    of V, constant along a connected set of rest points; each group said once, by its
    member nearest the origin.  The indices of the points kept, and a note by the index of
    each that stands for a family."""
    system = eom.system
    values = system.parameter_values
    at_rest = {c.q_dot: 0 for c in system.coordinates}
    table = {p.symbol: sympy.Float(values[p.name]) for p in system.parameters}
    level = sympy.lambdify(
        [[c.q for c in system.coordinates]],
        without_distributions(-system.lagrangian.xreplace(at_rest).xreplace(table)),
        "numpy",
    )
    squares = [abs(complex(w)) for e in found for w in e.omega_squared]
    zero = SAME_LEVEL * (1.0 + max(squares, default=0.0))
    kept, families = [], {}
    for index, e in enumerate(found):
        count = sum(abs(complex(w)) <= zero for w in e.omega_squared)
        if not count or not e.point:
            kept.append(index)
            continue
        q = np.array([float(e.point[c.name]) for c in system.coordinates])
        u = float(level(list(q)))
        key = next(
            (k for k in families if k[0] == count and abs(k[1] - u) <= zero * max(1.0, abs(u))),
            (count, u),
        )
        families.setdefault(key, []).append((float(np.linalg.norm(q)), index))
    notes = {}
    for (count, _), members in families.items():
        _, nearest = min(members)
        kept.append(nearest)
        if len(members) > 1:
            point = ", ".join(f"{k} = {float(v):.6g}" for k, v in found[nearest].point.items())
            notes[nearest] = (
                f"equilibria: {point} is one member of a family of rest points on the"
                f" constraint surface (up to {count} free directions; {len(members)} roots"
                " found numerically, grouped by the value of V)"
            )
    return kept, notes


def _everywhere(eom: EquationsOfMotion, *, numeric: bool) -> ConstrainedEquilibrium:
    """Every configuration on the surface at rest (no force acts at rest, as for a linkage
    without gravity): an empty point, no constraint force, omega^2 = 0 in each free
    direction."""
    forms = eom.constraints
    free = len(eom.system.coordinates) - len(forms.multipliers)
    modes = NormalModes((sympy.Integer(0),) * free, Stability.MARGINAL, closed_form=True)
    multipliers = {lam.name: sympy.Integer(0) for lam in forms.multipliers}
    return ConstrainedEquilibrium({}, multipliers, modes, numeric)


def _symbolic_points(eom: EquationsOfMotion, solutions: list) -> tuple[list, tuple[str, ...]]:
    """(point, multipliers) of SymPy's solutions that may be real, and a note on each family
    of rest points (some coordinates left free)."""
    system, forms = eom.system, eom.constraints
    q = [c.q for c in system.coordinates]
    points, notes = [], []
    for solution in solutions:
        if any(value.is_real is False for value in solution.values()):
            continue
        if not _real_at_defaults(system, solution.values()):
            continue  # as for unconstrained equilibria: a point that is not real at the defaults
        if not set(q) <= set(solution):
            free = ", ".join(c.name for c in system.coordinates if c.q not in solution)
            notes.append(
                f"equilibria: a family of rest points on the constraint surface ({free} free)"
                " is not reported"
            )
            continue
        point = {c.name: solution[c.q] for c in system.coordinates}
        if any(point == seen for seen, _ in points):
            continue  # the same point with other multipliers: redundant constraints there
        multipliers = {lam: solution.get(lam) for lam in forms.multipliers}
        points.append((point, multipliers))
    return points, tuple(notes)


def _random_values(system) -> dict[str, float]:
    """The defaults, and random values for the parameters without one (as .search)."""
    rng = random.Random(11)
    values = dict(system.parameter_values)
    for p in system.parameters:
        if p.default is None:
            magnitude = rng.uniform(0.5, 2.0)
            values[p.name] = -magnitude if p.sign == "negative" else magnitude
    return values


def _real_at_defaults(system, values) -> bool:
    defaults = dict(system.parameter_values)
    if len(defaults) < len(system.parameters):
        return True  # no values to judge by
    for value in values:
        number = number_at(value, defaults)
        if number is not None and abs(number.imag) > 1e-9 * (1 + abs(number.real)):
            return False
    return True


def _equilibrium(
    eom: EquationsOfMotion, point: Mapping[str, sympy.Expr], multipliers: Mapping
) -> ConstrainedEquilibrium:
    """A point found by SymPy (a multiplier None where SymPy left it free)."""
    here = {c.q: point[c.name] for c in eom.system.coordinates}
    count = eom.constraints.matrix.rows
    rank = _rank(eom.constraints.matrix.xreplace(here), eom.system)
    if any(value is None for value in multipliers.values()):
        rank = min(rank, count - 1)  # SymPy left a multiplier free: they are not determined
    if rank < count:
        point = {name: tidy(value) for name, value in point.items()}
        return _redundant(point, count - rank, rank, numeric=False)
    modes, verdict = SurfaceModes(eom).at(point, list(multipliers.values()))
    values = {lam.name: tidy(value) for lam, value in multipliers.items()}
    return ConstrainedEquilibrium(point, values, modes, False, *_said(verdict))


def _rank(gradient: sympy.Matrix, system) -> int:
    """The rank of A at a point: of its numbers at the parameter values (random ones for
    those without), where every entry has one; else SymPy's."""
    values = _random_values(system)
    entries = [number_at(x, values) for x in gradient]  # a Matrix holds SymPy objects
    if any(z is None for z in entries):
        return gradient.rank()
    matrix = np.array([z.real for z in entries]).reshape(gradient.shape)
    singular = np.linalg.svd(matrix, compute_uv=False)
    largest = singular.max(initial=0.0)
    return int(np.sum(singular > RANK_TOLERANCE * largest)) if largest > 0 else 0


def _numeric_equilibrium(eom: EquationsOfMotion, root: SurfaceRoot) -> ConstrainedEquilibrium:
    system, forms = eom.system, eom.constraints
    point = {c.name: sympy.Float(x) for c, x in zip(system.coordinates, root.q, strict=True)}
    redundant = len(forms.multipliers) - root.rank
    if redundant:
        return _redundant(point, redundant, root.rank, numeric=True)
    multipliers = [sympy.Float(x) for x in root.multipliers]
    modes, verdict = SurfaceModes(eom).at(point, multipliers, numeric=True)
    values = {lam.name: x for lam, x in zip(forms.multipliers, multipliers, strict=True)}
    return ConstrainedEquilibrium(point, values, modes, True, *_said(verdict))


def _said(verdict) -> tuple:
    """(at_defaults, stability_condition) of a stability verdict."""
    return verdict.at_defaults, verdict.condition


def _redundant(point, redundant: int, rank: int, *, numeric: bool) -> ConstrainedEquilibrium:
    note = (
        f"the constraints are redundant here (dc/dq has rank {rank} for {rank + redundant}"
        " constraints): the null space of dc/dq is not the tangent space of the surface"
    )
    return ConstrainedEquilibrium(
        point, {}, NormalModes.undetermined(note), numeric, redundant=redundant
    )


def _redundancy_note(e: ConstrainedEquilibrium) -> str:
    point = ", ".join(f"{name} = {value}" for name, value in e.point.items())
    count = "one constraint" if e.redundant == 1 else f"{e.redundant} constraints"
    return (
        f"equilibria: at {point} the constraints are redundant ({count} beyond the rank of"
        " dc/dq): the constraint forces that hold it are not determined, and its small"
        " oscillations are not computed"
    )


def redundancy_notes(points) -> list[str]:
    """The notes of :func:`_redundancy_note` for the points it applies to."""
    return [_redundancy_note(e) for e in points if e.redundant]

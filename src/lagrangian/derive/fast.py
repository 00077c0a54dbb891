"""Lagrange's equations of large systems: the chain rule on SymEngine term tables.

The same equations as :mod:`lagrangian.derive.euler_lagrange` (the canonical form
is on :class:`~lagrangian.derive.equations.EquationsOfMotion`),

    p_i = dL/dq_i',  M_ij = dp_i/dq_j',
    f_i = dL/dq_i - sum_j dp_i/dq_j q_j' - dp_i/dt + Q_i - dF/dq_i',

but every expression is held as a table {state monomial: coefficient}, where the
monomial depends on (q, q', t) and the coefficient only on parameters.  A derivative
touches only the monomials that hold the symbol (an index finds them), equal
monomials are added as they appear (the q_i' q_j' terms of a chain cancel there),
and common factors of a coefficient are pulled out (g l_1 (m_1 + ... + m_n)), so an
n-link chain costs O(n^2) terms and no simplification is searched for.  SymEngine
does the arithmetic; the results are converted to SymPy once, at the end.

Used above ``FAST_MIN_COORDINATES`` coordinates for systems without constraints
whose expressions SymEngine can hold; the steps then hold the untidied terms, and
they and the equations are converted to SymPy only when first read (most uses
need M and f alone).
"""

from __future__ import annotations

import dataclasses
import functools
import random
from collections import defaultdict
from collections.abc import Iterator
from typing import NamedTuple

import numpy as np
import sympy

from ..algebra import holds_derivative, to_symengine, to_sympy
from ..collector import cycle_collector_paused
from ..lazy import Later
from ..model import System
from ..sizes import MAX_EXPANDED_TERMS, expanded_terms
from .constraints import ConstraintForms
from .equations import CoordinateDerivation, Deferred, EquationsOfMotion, SymEngineForms
from .solve import SYMBOLIC_MAX_SIZE, check_regular, diagonal_blocks, solve_accelerations
from .term_tables import TermTables, too_many_terms


def derive_large(
    system: System, constraints: ConstraintForms | None = None
) -> EquationsOfMotion | None:
    """The equations of motion of ``system`` by term tables; None where SymEngine cannot hold it.

    With ``constraints`` (the system's, as :func:`~.constraints.constraint_forms` gives
    them), each equation holds its constraint force A^T lambda; q'' and lambda are left
    to the numerical solve (their closed forms are out of reach at this size).
    """
    with cycle_collector_paused():  # the tables keep many objects alive
        return _derived_by_tables(system, constraints)


def _derived_by_tables(
    system: System, constraints: ConstraintForms | None
) -> EquationsOfMotion | None:
    coordinates = system.coordinates
    cache: dict = {}
    built = system.built_lagrangian  # L as the build made it in SymEngine, if it did
    converted = {
        "lagrangian": built if built is not None else to_symengine(system.lagrangian, cache),
        "dissipation": to_symengine(system.dissipation, cache),
    }
    forces = {name: to_symengine(q, cache) for name, q in system.forces.items()}
    if any(x is None for x in (*converted.values(), *forces.values())):
        return None
    import symengine as se

    given = {**converted, **{f"forces.{name}": x for name, x in forces.items()}}
    kinds: dict = {}  # field -> the types of its nodes, found by the same walk
    bounds: dict = {}  # field -> the terms its expansion makes at most
    for field, expr in given.items():
        kinds[field] = set()
        bounds[field] = expanded_terms(expr, kinds=kinds[field])
        if bounds[field] > MAX_EXPANDED_TERMS:
            raise too_many_terms(lagrangian_field(system) if field == "lagrangian" else field)

    q = [to_symengine(c.q, cache) for c in coordinates]
    v = [to_symengine(c.q_dot, cache) for c in coordinates]
    t = to_symengine(system.time, cache)
    accelerations = [to_symengine(c.q_ddot, cache) for c in coordinates]
    nonsmooth = any(kinds[x] & {se.Abs, se.sign} for x in ("lagrangian", "dissipation"))
    state = [*q, *v, t]

    def tables_of_coordinates():  # the derivation's tables, coordinate by coordinate
        return _coordinate_tables(
            TermTables(state, nonsmooth=nonsmooth, field=lambda: lagrangian_field(system)),
            {field: (expr, bounds[field]) for field, expr in given.items()},
            [f"forces.{c.name}" if c.name in forces else None for c in coordinates],
        )

    back: dict = {}

    @functools.cache
    def symbols() -> dict:  # the SymPy symbol of each name, with its assumptions
        known = dict(system.symbols)
        names = {s.name for x in (*converted.values(), *forces.values()) for s in x.free_symbols}
        if not names <= known.keys():  # a name the model did not declare: take it from the text
            given = (system.lagrangian, system.dissipation, *system.forces.values())
            known |= {s.name: s for x in given for s in x.free_symbols}
        return known

    def sympy_of(value) -> sympy.Expr:  # made only when M, f or the steps are read
        return to_sympy(value, symbols(), back)

    n = len(coordinates)
    numeric_rows, inertias, rest_terms = [], [], []
    for i, part in enumerate(tables_of_coordinates()):
        tables, momentum, row_parts = part.tables, part.momentum, part.row_parts
        row = [numeric_rows[j][i] for j in range(i)]
        row += [tables.expr(tables.table(row_parts.get(j, {}))) for j in range(i, n)]
        rest = tables.expr(tables.table(part.total))
        if tables.nonsmooth and any(
            holds_derivative(x) for x in (tables.expr(momentum), *row[i:], rest)
        ):
            return None  # d sign(u)/dx (a Dirac delta), which SymEngine leaves undone

        numeric_rows.append(row)
        inertias.append(se.Add(*(m * a for m, a in zip(row, accelerations, strict=True))))
        rest_terms.append(rest)
    equations = tuple(inertia - rest for inertia, rest in zip(inertias, rest_terms, strict=True))

    def constraint_force(i: int) -> sympy.Expr:
        if constraints is None:
            return sympy.Integer(0)
        column = constraints.matrix.col(i)
        return sympy.Add(*(lam * a for lam, a in zip(constraints.multipliers, column, strict=True)))

    def steps() -> tuple[CoordinateDerivation, ...]:
        # the parts' tables are made again: kept, their hundreds of thousands of objects
        # would cost the cycle collector more than making them again costs --steps
        made = []
        for i, part in enumerate(tables_of_coordinates()):
            c, force, expr = coordinates[i], constraint_force(i), part.tables.expr
            made.append(
                CoordinateDerivation(
                    coordinate=c,
                    momentum=sympy_of(expr(part.momentum)),
                    momentum_rate=sympy_of(inertias[i] + expr(part.rate)),
                    force_gradient=sympy_of(expr(part.gradient)),
                    generalized_force=system.forces.get(c.name, sympy.Integer(0)),
                    dissipation_force=sympy_of(expr(part.friction)),
                    constraint_force=force,
                    equation=sympy_of(equations[i]) - force,
                )
            )
        return tuple(made)

    # M and f in SymPy are made when first read: derive's documents print the SymEngine
    # forms, and the numeric stages compile from those too
    @functools.cache
    def mass_matrix() -> sympy.ImmutableMatrix:
        return sympy.ImmutableMatrix(n, n, [sympy_of(m) for row in numeric_rows for m in row])

    @functools.cache
    def forcing_vector() -> sympy.ImmutableMatrix:
        return sympy.ImmutableMatrix(n, 1, [sympy_of(f) for f in rest_terms])

    if not _regular_at_random_points(numeric_rows):
        check_regular(mass_matrix(), coordinates)  # raises with the diagnosis
    made = Deferred(steps)
    return EquationsOfMotion(
        system=system,
        equations=Deferred(lambda: tuple(step.equation for step in made)),
        mass_matrix=Later(mass_matrix),
        forcing=Later(forcing_vector),
        accelerations=None
        if constraints or _too_large_to_solve(numeric_rows)
        else solve_accelerations(
            mass_matrix(), forcing_vector(), coordinates, system.state_symbols
        ),
        steps=made,
        constraints=constraints,
        symengine=None
        if constraints
        else SymEngineForms(
            lagrangian=converted["lagrangian"],
            equations=equations,
            mass_matrix=tuple(tuple(row) for row in numeric_rows),
            forcing=tuple(rest_terms),
        ),
    )


class _Parts(NamedTuple):
    """The tables of one coordinate's equation (lists of coefficients where not summed)."""

    tables: TermTables
    momentum: dict  # p_i
    row_parts: dict  # j -> the lists of dp_i/dq_j', j >= i
    rate: dict  # sum_j dp_i/dq_j q_j' + dp_i/dt
    gradient: dict  # dL/dq_i
    friction: dict  # dD/dq_i'
    total: dict  # dL/dq_i - rate - friction + Q_i, the lists of f_i


def _coordinate_tables(tables: TermTables, given: dict, forces: list) -> Iterator[_Parts]:
    """The parts of each coordinate's equation in turn, from ``given`` {field: (SymEngine
    expression, its expansion's bound)} and the field of each coordinate's force (or None);
    the state symbols of ``tables`` are numbered q, q', t (n each of the first two)."""
    n = len(forces)

    def split(field: str, into=None) -> dict:
        expr, bound = given[field]
        return tables.split(expr, into, bound=bound)

    lagrangian = tables.table(split("lagrangian"), differentiated=True)
    lagrangian_index = tables.index(lagrangian)
    dissipation = tables.table(split("dissipation"), differentiated=True)
    for i, force in enumerate(forces):
        momentum = tables.table(
            tables.diff(lagrangian, n + i, lagrangian_index), differentiated=True
        )
        # One pass over the momentum's terms gives row i of M = dp_i/dq' and the part
        # sum_j dp_i/dq_j q_j' + dp_i/dt of dp_i/dt along the motion.  M is symmetric (a
        # Hessian): the entries left of the diagonal are known already.
        row_parts = {j: defaultdict(list) for j in range(i, n)}
        rate: dict = defaultdict(list)
        # the symbols by number: q_j (its derivative times q_j'), q_j', t
        routes = [(rate, n + j) for j in range(n)] + [None] * i
        routes += [(row_parts[j], None) for j in range(i, n)] + [(rate, None)]
        tables.differentiate(momentum, routes)
        velocity_terms = tables.table(rate)
        gradient = tables.table(tables.diff(lagrangian, i, lagrangian_index))
        friction = tables.table(tables.diff(dissipation, n + i))
        total = defaultdict(list)
        for monomial, coefficient in gradient.items():
            total[monomial].append(coefficient)
        for monomial, coefficient in velocity_terms.items():
            found = total.get(monomial)
            if found is not None and len(found) == 1 and found[0] == coefficient:
                del total[monomial]  # c - c: a chain's q_i' q_j' terms (the sum would be 0)
            else:
                total[monomial].append(-coefficient)
        for monomial, coefficient in friction.items():
            total[monomial].append(-coefficient)
        if force is not None:
            split(force, total)
        yield _Parts(tables, momentum, row_parts, velocity_terms, gradient, friction, total)


def lagrangian_field(system: System) -> str:
    """The field a refusal of L names: "lagrangian" where the model gives it (or its
    energies) as text, else the field of a particle, body or spring that expands to the
    most terms (``particles[0].position[0]``, as the model's other errors spell fields):
    the user wrote that, not L, which was assembled from it."""
    spec = system.spec
    if spec is None or any(
        getattr(spec, key) is not None for key in ("lagrangian", "kinetic", "potential")
    ):
        return "lagrangian"
    fields = [
        (where, expr)
        for kind in ("particles", "bodies", "springs")
        for i, component in enumerate(getattr(system, kind))
        for where, expr in _expressions(component, f"{kind}[{i}]")
    ]
    if not fields:
        return "lagrangian"
    counts = [expanded_terms(expr) for _, expr in fields]
    return fields[counts.index(max(counts))][0]


def _expressions(value, where: str):
    """(field, expression) of every SymPy expression in a component (a dataclass), its
    tuples and tuples of tuples indexed as the model file writes them."""
    if isinstance(value, sympy.Basic):
        yield where, value
    elif isinstance(value, tuple | list):
        for k, item in enumerate(value):
            yield from _expressions(item, f"{where}[{k}]")
    elif dataclasses.is_dataclass(value):
        for part in dataclasses.fields(value):
            yield from _expressions(getattr(value, part.name), f"{where}.{part.name}")


def _regular_at_random_points(rows) -> bool:
    """Full numeric rank of the symmetric matrix ``rows`` (SymEngine) at one of three random
    points (as in ``check_regular``, compiled).

    Only the upper triangle is evaluated, in one replacement of the symbols: that is most of
    the cost, and the lower triangle holds the same entries.  The entries are the arguments
    of one (undefined) function, so that the replacement visits each distinct subexpression
    once (a chain's entries share their sums of masses): 0.03 s at n = 100 where a matrix
    of them, replaced entry by entry, took 0.15 s.  The
    rank is counted from the eigenvalues, whose magnitudes are a symmetric matrix's singular
    values: LAPACK's symmetric solver takes about 3 ms of CPU at n = 100 where its SVD
    took 75-140 ms (OpenBLAS's threads waiting on each other on a busy machine).
    """
    import symengine as se

    n = len(rows)
    upper = [rows[i][j] for i in range(n) for j in range(i, n)]
    where = np.triu_indices(n)
    entries = se.Function("upper_triangle")(*upper)
    arguments = sorted(entries.free_symbols, key=str)
    rng = random.Random(20261122)
    for _ in range(3):
        values = {a: se.RealDouble(rng.uniform(0.5, 2.5)) for a in arguments}
        numeric = np.zeros((n, n))
        try:
            numeric[where] = np.array(entries.xreplace(values).args, dtype=float)
        except (TypeError, ValueError, RuntimeError):
            return False
        numeric.T[where] = numeric[where]
        if not np.all(np.isfinite(numeric)):
            return False
        diagonal = np.abs(np.diag(numeric))
        if np.any(diagonal == 0):
            return False
        scaled = numeric / np.sqrt(np.outer(diagonal, diagonal))
        magnitudes = np.abs(np.linalg.eigvalsh(scaled))
        if np.count_nonzero(magnitudes > 1e-9 * np.abs(scaled).max()) == n:
            return True
    return False


def _too_large_to_solve(rows) -> bool:
    """Whether M (SymEngine rows) has a diagonal block too large for q'' in closed form, as
    :func:`~.solve.solve_linear` would find from the SymPy M (the same zero entries)."""
    import symengine as se

    blocks = diagonal_blocks(se.DenseMatrix(rows))
    return any(len(block) > SYMBOLIC_MAX_SIZE for block in blocks)

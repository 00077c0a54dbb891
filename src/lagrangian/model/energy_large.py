"""The large route of the energies: T, V and L = T - V assembled with SymEngine.

Above ``FAST_MIN_COORDINATES`` coordinates (:mod:`.energy` decides) T is assembled in the
quadratic form of :mod:`.energy` from the Jacobian columns of the positions, in
SymEngine: each distinct term of the positions is differentiated once, each distinct
product of two columns simplified once by the sum-of-angles rule
(:func:`~lagrangian.algebra.combine_angles`) and the masses sharing it added,
M_ij = (m_j + ... + m_n) l_i l_j cos(theta_i - theta_j) for a chain.  The SymPy forms are
converted back at the cost of their top level, and ``known`` collects the SymEngine form
of each, so that L = T - V is made in SymEngine too (:func:`difference_in_symengine`).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence

import sympy

from ..algebra import (
    args_of,
    factor_common,
    holds_derivative,
    to_symengine,
    to_sympy,
)
from ..lazy import Later, value_of
from ..symbols import Coordinate
from .components import Gravity, Particle, RigidBody2D
from .energy_columns import Monomials


def kinetic_energy_large(
    coordinates: Sequence[Coordinate],
    time: sympy.Symbol,
    particles: Sequence[Particle],
    bodies: Sequence[RigidBody2D],
    known: dict | None = None,
    converted: dict | None = None,
) -> sympy.Expr | Converted | None:
    """T as in :func:`kinetic_energy`, assembled with SymEngine (None: not expressible there);
    with ``known``, its SymPy form is made on first read (:class:`Converted`); ``converted``
    (where given) is the conversion cache, kept for V (:func:`gravity_potential_large`)."""
    import symengine as se

    cache: dict = {} if converted is None else converted
    points = [(p.mass, p.position) for p in particles]
    points += [(b.mass, b.center) for b in bodies]
    points += [(b.inertia, (b.angle,)) for b in bodies]
    q = [to_symengine(c.q, cache) for c in coordinates]
    t = to_symengine(time, cache)
    # Equal Jacobian columns recur from point to point (every bob of a chain moves with
    # link 1 alike), so each distinct column gets a number once and the O(n^3) loop over
    # pairs of columns below hashes pairs of numbers, not of expressions.
    column_ids: dict = {}
    columns_by_id: list = []
    products: dict = {}

    def column_id(column) -> int:
        found = column_ids.get(column)
        if found is None:
            found = column_ids[column] = len(columns_by_id)
            columns_by_id.append(column)
        return found

    monomials: dict = {}  # column id -> its components' monomials (see Monomials)

    def expanded(c: int) -> Monomials:
        found = monomials.get(c)
        if found is None:
            found = monomials[c] = Monomials(columns_by_id[c])
        return found

    def dot(a: int, b: int):
        found = products.get((a, b))
        if found is None:
            found = products[a, b] = expanded(a).dot(expanded(b))
        return found

    linear: dict = defaultdict(lambda: defaultdict(list))
    constant: dict = defaultdict(list)
    masses: list = []  # of the points, in their order
    movers = _Movers()  # which points move with each (i, column id)
    terms_seen = _PositionTerms(q, t)  # each distinct term of the positions, looked at once
    for mass, position in points:
        m = to_symengine(mass, cache)
        r = [to_symengine(x, cache) for x in position]
        if m is None or any(x is None for x in r):
            return None
        columns, explicit, nonsmooth = terms_seen.columns(r)
        derivatives = [*explicit, *(x for column in columns.values() for x in column)]
        if nonsmooth and any(map(holds_derivative, derivatives)):
            return None  # d|u|/dq or d sign(u)/dq, which SymEngine leaves undone
        active = [(i, column_id(column)) for i, column in columns.items()]
        movers.add(len(masses), active)
        masses.append(m)
        if not all(x.is_zero for x in explicit):
            e = column_id(explicit)
            for i, ci in active:
                linear[i][ci, e].append(m)
            constant[e, e].append(m)
    quadratic: dict = defaultdict(dict)  # (i, j) -> {(column id, column id): point numbers}
    for ((i, ci), (j, cj)), together in movers.pairs():
        quadratic[i, j][ci, cj] = together

    grouped: dict = {}  # the sum of masses -> its common factor pulled out (lists recur)

    def mass_sum(masses):
        key = tuple(masses)
        found = grouped.get(key)
        if found is None:
            found = grouped[key] = factor_common(masses)
        return found

    summed: dict = {}  # the points (numbers) that move with a pair -> the sum of their masses

    def points_sum(together):
        found = summed.get(together)
        if found is None:
            found = summed[together] = mass_sum([masses[k] for k in together])
        return found

    def total(groups, sums=mass_sum):
        # the same product under several pairs of ids is added, not kept twice
        by_product: dict = defaultdict(list)
        for pair, group in groups.items():
            by_product[dot(*pair)].append(sums(group))
        return se.Add(*(mass_sum(found) * product for product, found in by_product.items()))

    velocities = [to_symengine(c.q_dot, cache) for c in coordinates]
    symbols = _converted_symbols(cache) | {c.q_dot.name: c.q_dot for c in coordinates}
    terms = [total(constant) / 2]
    for (i, j), groups in quadratic.items():
        weight = velocities[i] ** 2 / 2 if i == j else velocities[i] * velocities[j]
        terms.append(total(groups, points_sum) * weight)
    terms += [total(groups) * velocities[i] for i, groups in linear.items()]
    return _converted(se.Add(*terms), symbols, cache, known)


class _Movers:
    """Which points move with each Jacobian column (i, column id), and so the pairs of
    columns T pairs: each pair with the points that move with both, in the order the
    points meet them.

    Listing each point's pairs would be O(n^3) for a chain (171,700 at n = 100, a dict
    update each); here each column gets a number and its points a set, and a pair's
    points are the intersection of its columns' sets (in C).
    """

    def __init__(self):
        self.numbers: dict = {}  # (i, column id) -> its number
        self.columns: list = []  # number -> (i, column id)
        self.points: list = []  # number -> the set of points that move with it
        self.actives: list = []  # point -> the numbers of its columns, by i

    def add(self, point: int, active: list) -> None:
        numbers = []
        for column in active:
            number = self.numbers.get(column)
            if number is None:
                number = self.numbers[column] = len(self.columns)
                self.columns.append(column)
                self.points.append(set())
            self.points[number].add(point)
            numbers.append(number)
        self.actives.append(numbers)

    def pairs(self) -> list:
        """[((i, column id), (j, column id)), points] for i <= j, each pair of columns some
        point moves with, with the (sorted) numbers of the points that move with both; in
        the order a walk of each point's pairs (by i, then j) first meets them."""
        columns, points, actives = self.columns, self.points, self.actives
        found = []
        for a, holders in enumerate(points):
            beside: set = set()  # the columns some point moves with along with a
            for point in holders:
                beside.update(actives[point])
            i = columns[a][0]
            for b in beside:
                if columns[b][0] > i or b == a:
                    together = tuple(sorted(holders & points[b]))
                    found.append((together[0], i, columns[b][0], a, b, together))
        found.sort(key=lambda entry: entry[:3])
        return [((columns[a], columns[b]), together) for *_, a, b, together in found]


class Converted(Later):
    """A SymPy expression made on first read (:class:`~lagrangian.lazy.Later`) from
    ``form``, its SymEngine form, which is at hand before."""

    __slots__ = ("form",)

    def __init__(self, form, make):
        super().__init__(make)
        self.form = form


def _converted(form, symbols: dict, cache: dict, known: dict | None) -> sympy.Expr | Converted:
    """``form`` in SymPy; for the build (``known`` given) a :class:`Converted` that makes
    it on first read: a large model's T takes 0.08 s to convert (the 100-link chain's) and
    most commands never read it, L starting from the SymEngine forms."""
    if known is None:
        return _back_to_sympy(form, symbols, cache, None)
    return Converted(form, lambda: _back_to_sympy(form, symbols, cache, known))


class _PositionTerms:
    """The Jacobian columns of positions (SymEngine), each distinct term of them looked at once.

    Each term of r is differentiated by the coordinates it holds only: a chain's bob
    at depth k costs O(k) derivatives, not O(k n).  A term's derivatives, and whether it
    holds |u| or sign(u), are kept for the next points (a chain's bobs share their
    terms), and so is each column made of the same derivatives (their sums are made once).
    """

    def __init__(self, q, t):
        self.index = {qi: i for i, qi in enumerate(q)}
        self.time = self.index[t] = len(q)  # dr/dt is made as the columns are
        self.known: dict = {}  # term -> ([(i, d term/dq_i or dt)], whether it holds Abs or sign)
        self.made: dict = {}  # the derivatives a column adds up, per component -> the column

    def term(self, term) -> tuple[list, bool]:
        import symengine as se

        found = self.known.get(term)
        if found is None:
            index = self.index
            derivatives = [
                (index[symbol], se.diff(term, symbol))
                for symbol in term.free_symbols
                if symbol in index
            ]
            found = self.known[term] = (derivatives, bool(term.atoms(se.Abs, se.sign)))
        return found

    def columns(self, position) -> tuple[dict, tuple, bool]:
        """({i: dr/dq_i} for the q_i that r depends on, the partial dr/dt, whether r holds
        |u| or sign(u))."""
        import symengine as se

        nonsmooth = False
        parts: dict = defaultdict(lambda: [[] for _ in position])
        for k, x in enumerate(position):
            for term in x.args if type(x) is se.Add else (x,):
                derivatives, holds = self.term(term)
                nonsmooth = nonsmooth or holds
                for i, derivative in derivatives:
                    parts[i][k].append(derivative)
        explicit = tuple(se.Add(*terms) for terms in parts.pop(self.time, [[] for _ in position]))
        columns = {}
        for i in sorted(parts):
            key = tuple(map(tuple, parts[i]))
            column = self.made.get(key)
            if column is None:
                column = tuple(se.Add(*terms) for terms in parts[i])
                self.made[key] = column = None if all(x.is_zero for x in column) else column
            if column is not None:
                columns[i] = column
        return columns, explicit, nonsmooth


def gravity_potential_large(
    gravity: Gravity, points, known: dict | None, converted: dict | None = None
) -> sympy.Expr | Converted | None:
    """The same sum in SymEngine, which does not re-sort each partial sum as SymPy does
    (with ``known``, made in SymPy on first read, as T); ``converted``: T's conversions, so
    that the positions are converted once (a copy: V's own do not go into T's)."""
    import symengine as se

    cache: dict = {} if converted is None else dict(converted)
    given = [gravity.g, *gravity.direction] + [x for mass, r in points for x in (mass, *r)]
    if any(to_symengine(x, cache) is None for x in given):
        return None
    g = cache[gravity.g]
    direction = [cache[d] for d in gravity.direction]
    terms = [
        cache[mass] * g * se.Add(*(-d * cache[x] for d, x in zip(direction, r, strict=True)))
        for mass, r in points
    ]
    return _converted(se.Add(*terms), _converted_symbols(cache), cache, known)


def difference_in_symengine(kinetic, potential, known: dict):
    """(T - V, its SymEngine form) made in SymEngine, where T and V convert to it; else
    (None, None).  T - V is a :class:`~lagrangian.lazy.Later`: its SymPy form is made on
    first read (most commands derive and print from the SymEngine form).

    ``known`` is what :func:`kinetic_energy` and :func:`gravity_potential` collected (T and
    V are :class:`Converted` there, or convert at the cost of their top level), and L
    converts back reusing their SymPy terms.  SymPy's ``T - V`` would sort the terms of the
    sum anew (0.17 s for the 100-link chain's 5150); L's terms come in SymEngine's order
    instead, as T's do.
    """
    import symengine as se

    t = _symengine_form(kinetic, known)
    v = se.Integer(0) if potential is None else _symengine_form(potential, known)
    if t is None or v is None:
        return None, None
    # -V term by term, as SymPy distributes it (SymEngine would keep -(a + b) whole)
    difference = se.Add(*args_of(t, se.Add), *(-term for term in args_of(v, se.Add)))

    def made_in_sympy() -> sympy.Expr:
        value_of(kinetic)  # T's and V's conversions fill ``known`` with the terms L reuses
        value_of(potential)
        made = {node: expr for expr, node in known.items()}
        symbols = {expr.name: expr for expr in known if expr.is_Symbol}
        return to_sympy(difference, symbols, made)

    return Later(made_in_sympy), difference


def _symengine_form(expr, known: dict):
    return expr.form if isinstance(expr, Converted) else to_symengine(expr, known)


def _back_to_sympy(expr, symbols: dict, cache: dict, known: dict | None) -> sympy.Expr:
    """``to_sympy(expr)``; ``known`` (where given) gains every SymPy node made, or met in
    ``cache`` (a ``to_symengine`` cache), with its SymEngine form."""
    back: dict = {}
    result = to_sympy(expr, symbols, back)
    if known is not None:
        known.update(cache)
        known.update((sympy_node, node) for node, sympy_node in back.items())
    return result


def _converted_symbols(cache: dict) -> dict:
    """{name: SymPy symbol} of the symbols a ``to_symengine`` cache has met (their
    assumptions kept), without walking the expressions again."""
    return {node.name: node for node in cache if node.is_Symbol}

"""A large model's T, V and L as assembled in SymEngine: each distinct piece made once.

Above ``FAST_MIN_COORDINATES`` coordinates T is assembled from the Jacobian columns of
the positions: each distinct sum of masses is grouped once (a chain has n of them, under
n(n+1)/2 pairs of columns), each distinct term of the positions looked at once, and
L = T - V is made in SymEngine (SymPy would sort its thousands of terms anew).  The
values must still be the n-link pendulum's closed form.
"""

from __future__ import annotations

import math

import pytest
import sympy

from derive.test_chain_pendulum import chain_pendulum
from helpers import assert_close, counting, evaluate, random_point
from lagrangian.algebra import to_symengine


def _closed_form_energies(n: int, point: dict) -> tuple[float, float]:
    """T and V of the n-link pendulum at ``point`` (angles from the downward vertical)."""
    m = [point[f"m{k}"] for k in range(1, n + 1)]
    l = [point[f"l{k}"] for k in range(1, n + 1)]
    th = [point[f"theta{k}"] for k in range(1, n + 1)]
    w = [point[f"theta{k}_dot"] for k in range(1, n + 1)]
    kinetic = sum(
        sum(m[max(i, j) :]) * l[i] * l[j] * math.cos(th[i] - th[j]) * w[i] * w[j] / 2
        for i in range(n)
        for j in range(n)
    )
    potential = -point["g"] * sum(
        m[k] * sum(l[i] * math.cos(th[i]) for i in range(k + 1)) for k in range(n)
    )
    return kinetic, potential


def test_each_distinct_sum_of_masses_is_grouped_once(monkeypatch, rng):
    grouped = counting(monkeypatch, "lagrangian.model.energy_large", "factor_common")
    n = 12
    system = chain_pendulum(n)
    # n sums m_j + ... + m_n, each once, and once more as the coefficient of its products
    # (before: twice for each of the n(n+1)/2 pairs of links, 156 times)
    assert len(grouped) <= 2 * n
    point = random_point(system, rng)
    kinetic, potential = _closed_form_energies(n, point)
    assert_close(evaluate(system.kinetic, point), kinetic, scale=1.0)
    assert_close(evaluate(system.potential, point), potential, scale=1.0)
    assert_close(evaluate(system.lagrangian, point), kinetic - potential, scale=1.0)


def test_the_lagrangian_is_not_sorted_anew_by_sympy(monkeypatch, rng):
    flatten = sympy.Add.flatten.__func__
    sizes: list[int] = []

    def counted(cls, seq):
        made = flatten(cls, seq)
        sizes.append(len(made[0]))  # the terms of the sum made (nested sums flattened)
        return made

    sympy.core.cache.clear_cache()  # sums made by tests before are not made again
    monkeypatch.setattr(sympy.Add, "flatten", classmethod(counted))
    n = 20
    system = chain_pendulum(n)
    terms = len(system.lagrangian.args)  # made in SymPy on this first read
    monkeypatch.undo()
    assert terms == n * (n + 1) // 2 + n  # q_i' q_j' for i <= j, and gravity's n terms
    assert max(sizes, default=0) < terms  # before: T - V, 230 terms, sorted by SymPy's Add
    # L is T - V, and the SymEngine form the large route of derive starts from is L's
    converted = system.symengine_lagrangian[1]
    assert system.built_lagrangian is converted  # L is still the build's
    assert converted == to_symengine(system.lagrangian)
    difference = converted - (to_symengine(system.kinetic) - to_symengine(system.potential))
    assert difference.expand() == 0
    point = random_point(system, rng)
    assert_close(
        evaluate(system.lagrangian, point),
        evaluate(system.kinetic, point) - evaluate(system.potential, point),
        scale=1.0,
    )


def test_products_of_columns_by_their_monomials_are_combine_angles_of_the_product(rng):
    """u . v made from the columns' monomials equals ``combine_angles`` of u . v, for
    columns of monomials and for columns the shortcut leaves to it (sums inside powers,
    products of sums, |u|)."""
    import symengine as se

    from lagrangian.algebra import combine_angles
    from lagrangian.model.energy_columns import Monomials

    a, b, c, l1, l2 = se.symbols("a b c l1 l2")
    components = [
        l1 * se.cos(a),
        -l1 * se.sin(a),
        l2 * se.cos(b) + l1 * se.cos(a),
        2 * se.sin(a) * se.cos(b) ** 2,
        se.sqrt(l1) * se.sin(c),
        l1 * (se.cos(a) + se.sin(b)),  # a product holding a sum: expanded first
        (l1 + l2) ** se.Rational(3, 2) * se.cos(a),  # a power of a sum: left to combine_angles
        se.cos(a) / (l1 + se.sin(b)),
        se.Abs(a) * se.sin(a),
        se.Integer(0),
    ]
    shortcut = 0
    for _ in range(200):
        u = tuple(rng.choice(components) for _ in range(2))
        v = tuple(rng.choice(components) for _ in range(2))
        left, right = Monomials(u), Monomials(v)
        shortcut += left.terms is not None and right.terms is not None
        expected = combine_angles(se.Add(*(x * y for x, y in zip(u, v, strict=True))))
        assert left.dot(right) == expected, (u, v)
    assert 50 < shortcut < 200  # both ways were taken


def test_a_product_of_columns_paired_into_one_cosine_is_the_walks_term_for_term(rng):
    """c cos a cos b + c sin a sin b made as c cos(a - b) from the columns' monomials
    (``_paired``, no product or sum made) is the very expression ``combine_expanded_angles``
    makes of the expanded product: the same text, so cos(a - b) and not cos(b - a) (which
    SymEngine keeps apart); other products are left to it."""
    import symengine as se

    from lagrangian.algebra import combine_expanded_angles
    from lagrangian.model import energy_columns
    from lagrangian.model.energy_columns import Monomials

    t = se.Symbol("t")
    angles = [se.function_symbol(f"theta{k}", t) for k in range(1, 40)] + list(se.symbols("a b c"))
    l1, l2 = se.symbols("l1 l2")
    sin, cos = se.sin, se.cos

    def component(angle):
        coefficient = rng.choice([l1, l2, -l1, 2 * l1 * l2, se.Rational(1, 2), se.sqrt(l2)])
        return coefficient * rng.choice([sin, cos])(angle) ** rng.choice([1, 1, 1, 2, 3])

    def column():
        angle = rng.choice(angles)
        if rng.random() < 0.2:
            angle = angle + rng.choice(angles) / 2
        first = component(angle)
        second = component(angle)
        if rng.random() < 0.7:  # a link's column: (l cos a, l sin a) or (l sin a, -l cos a)
            coefficient = rng.choice([l1, l2, -l1, 3 * l2])
            first, second = coefficient * cos(angle), coefficient * sin(angle)
            if rng.random() < 0.5:
                first, second = second, -first
        extra = [rng.choice([se.Integer(0), first])] if rng.random() < 0.3 else []
        return (first, second, *extra)

    made = []
    real = energy_columns._paired
    paired = lambda left, right: made.append(real(left, right)) or made[-1]  # noqa: E731
    energy_columns._paired = paired
    try:
        for _ in range(600):
            u = column()
            v = column()
            if len(u) != len(v):
                continue
            left, right = Monomials(u), Monomials(v)
            got = left.dot(right)
            products = [x * y for x, y in zip(u, v, strict=True)]
            expected = combine_expanded_angles(se.expand(se.Add(*products)))
            assert str(got) == str(expected) and got == expected, (u, v)
    finally:
        energy_columns._paired = real
    taken = sum(result is not None for result in made)
    assert 40 < taken < len(made) - 40  # both ways were taken


def test_the_products_of_columns_are_not_counted_one_by_one(monkeypatch):
    """The expansion bound is taken once per column, not walked for each of the n(n+1)/2
    products (before: one expanded_terms walk per product)."""
    counted = counting(monkeypatch, "lagrangian.model.energy_columns", "expanded_terms")
    walked = counting(monkeypatch, "lagrangian.algebra", "expanded_terms")
    n = 12
    chain_pendulum(n)
    assert len(counted) + len(walked) <= 2 * n  # two components a column, n columns


def _chain_with_last_position(n: int, last_x: str) -> str:
    """The n-link pendulum's model file, the last bob's x written as ``last_x``."""
    lines = [f"coordinates = [{', '.join(f'{chr(34)}theta{i}{chr(34)}' for i in range(1, n + 1))}]"]
    lines += ["[parameters]", *(f"l{i} = 1.0" for i in range(1, n + 1)), "g = 9.81"]
    x = "0"
    for i in range(1, n + 1):
        x += f" + l{i}*sin(theta{i})"
        shown = last_x if i == n else x
        lines += ["[[particles]]", 'mass = "1"', f'position = ["{shown}", "l1*cos(theta1)"]']
    return "\n".join(lines)


def test_a_sum_of_terms_met_before_is_checked_whole():
    """The checks of a position see the sum SymPy made of its terms: a number the sum made
    beyond double precision is refused, a name that cancels is not there."""
    from lagrangian.errors import ModelError
    from lagrangian.model.toml_io import loads

    n = 8
    terms = " + ".join(f"l{i}*sin(theta{i})" for i in range(1, n + 1))
    beyond = f"{terms} + 1e308*l1 + 1e308*l1"  # each term a double, their sum 2e308 not
    with pytest.raises(ModelError, match=r"the number 2000.* is beyond double precision"):
        loads(_chain_with_last_position(n, beyond))
    cancelled = f"{terms} + theta1_dot - theta1_dot"  # a velocity, gone from the sum
    system = loads(_chain_with_last_position(n, cancelled))
    names = {s.name for s in system.particles[-1].position[0].free_symbols}
    assert names == {f"{kind}{i}" for kind in ("l", "theta") for i in range(1, n + 1)}


def _pairs_point_by_point(actives: list[list]) -> list:
    """The pairs of columns as each point's pairs list them (i <= j), in the order met,
    with the points that move with both: what ``_Movers.pairs`` must give."""
    from itertools import combinations_with_replacement

    pairs: dict = {}
    for point, active in enumerate(actives):
        for pair in combinations_with_replacement(active, 2):
            pairs.setdefault(pair, []).append(point)
    return [(pair, tuple(points)) for pair, points in pairs.items()]


def test_the_pairs_of_columns_are_each_points_pairs_in_the_order_met(rng):
    """``_Movers`` finds T's pairs of columns by intersecting the points of each column
    (not a dict update for each of a point's pairs, O(n^3) for a chain): the same pairs,
    the same points, the same order as listing each point's pairs."""
    from lagrangian.model.energy_large import _Movers

    for _ in range(200):
        coordinates = rng.randint(1, 8)
        actives = []
        for _ in range(rng.randint(1, 12)):
            chosen = sorted(rng.sample(range(coordinates), rng.randint(0, coordinates)))
            actives.append([(i, rng.randint(0, 2)) for i in chosen])  # column ids recur
        movers = _Movers()
        for point, active in enumerate(actives):
            movers.add(point, active)
        assert movers.pairs() == _pairs_point_by_point(actives)


def test_the_partial_time_derivative_is_made_with_the_columns(rng):
    """dr/dt of a position comes from its terms (those holding t), as the columns do:
    equal to SymEngine's derivative of the whole position."""
    import symengine as se

    from lagrangian.model.energy_large import _PositionTerms

    q = [se.Symbol(f"q{k}") for k in range(4)]
    t, w = se.Symbol("t"), se.Symbol("w")
    pieces = [q[0] * se.sin(w * t), se.cos(q[1] - t), t**2, q[2] * q[3], se.Integer(3), w * q[1]]
    terms = _PositionTerms(q, t)
    for _ in range(50):
        position = [se.Add(*rng.sample(pieces, rng.randint(0, 4))) for _ in range(2)]
        columns, explicit, _ = terms.columns(position)
        assert explicit == tuple(se.diff(x, t) for x in position)
        assert columns == {
            i: tuple(se.diff(x, q[i]) for x in position)
            for i in range(4)
            if any(se.diff(x, q[i]) != 0 for x in position)
        }


def test_the_positions_are_converted_to_symengine_once_for_t_and_v(monkeypatch, rng):
    """V's large route starts from the SymEngine forms T's made of the positions (before:
    each position, a sum of up to n terms, converted again for V)."""
    from lagrangian.model import energy_large

    convert = energy_large.to_symengine
    made: list = []

    def counted(expr, cache=None):
        if cache is not None and isinstance(expr, sympy.Add) and expr not in cache:
            made.append(expr)
        return convert(expr, cache)

    monkeypatch.setattr(energy_large, "to_symengine", counted)
    n = 9
    system = chain_pendulum(n)
    assert made and len(made) == len(set(made))
    point = random_point(system, rng)
    kinetic, potential = _closed_form_energies(n, point)
    assert_close(evaluate(system.potential, point), potential, scale=1.0)
    assert_close(evaluate(system.lagrangian, point), kinetic - potential, scale=1.0)

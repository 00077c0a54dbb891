"""The large route's term tables: {state monomial: parameter coefficient}, checked against
SymEngine's own expansion of the same expressions."""

from __future__ import annotations

from collections import defaultdict

import pytest
import symengine as se

from lagrangian.derive.term_tables import TermTables

x, y, v, t, a, b = se.symbols("x y v t a b")
STATE = (x, y, v, t)

EXPRESSIONS = [
    a * b * (a + b) * se.cos(x - y) * v**2,  # a chain's term: a sum among the coefficients
    -3 * a * se.sin(x) + b * se.sin(x) + 2 * a * b,  # one monomial twice, a constant
    a * (x + y) ** 2 * se.sin(y) + (b - a) * x * y,  # a power of a sum, expanded
    (x**2 + y**2) ** se.Rational(-1, 2) * a * v,  # a sum's negative power: a factor
    se.exp(a * x * t) * v + x,  # a single state factor
]


@pytest.mark.parametrize("expr", EXPRESSIONS, ids=str)
def test_a_table_is_the_expansion_grouped_by_state_monomial(expr):
    tables = TermTables(STATE)
    table = tables.table(tables.split(expr), differentiated=True)
    assert se.expand(tables.expr(table)) == se.expand(expr)
    for monomial, coefficient in table.items():
        assert not coefficient.free_symbols & set(STATE)  # parameters alone
        product = tables.expr_of(monomial)
        factors = product.args if type(product) is se.Mul else (product,)
        assert product == 1 or all(f.free_symbols & set(STATE) for f in factors)
        held = {STATE[s] for s in tables.symbols[monomial]}
        assert held == product.free_symbols & set(STATE)


def test_a_scaled_split_adds_to_what_is_there():
    tables = TermTables(STATE)
    into = tables.split(a * se.sin(x) * v)
    tables.split(b * se.sin(x) * v + se.cos(y), into, scale=a)
    table = {tables.expr_of(m): c for m, c in tables.table(into).items()}
    assert table[se.sin(x) * v] == a * (b + 1)  # a + a b, the common factor pulled out
    assert table[se.cos(y)] == a


def _random_terms(rng, count: int):
    """Sums of products of state factors as a model's L holds them: powers, sin, cos, exp,
    |u|, roots and powers of sums, with parameter coefficients."""
    pool = [
        x,
        y**2,
        v**3,
        t,
        x**-1,
        y ** se.Rational(1, 2),
        se.sin(x - y),
        se.cos(2 * x) ** 2,
        se.cos(a * x + y),
        se.exp(a * x * t),
        se.Abs(x - 2 * y),
        se.sin(x) ** 3,
        (x + y) ** 2,
        (x**2 + y**2 + 1) ** se.Rational(-1, 2),
        se.sin(y**2 + x),
        se.log(1 + v**2),
    ]
    terms = []
    for _ in range(count):
        factors = rng.sample(pool, rng.randint(1, 3))
        coefficient = rng.choice([a, b, 2 * a * b, se.Rational(3, 2), a + b, -b])
        terms.append(se.Mul(coefficient, *factors))
    return terms


@pytest.mark.parametrize("seed", range(6))
def test_derivatives_by_the_product_rule_are_symengines_derivative_split(seed):
    """Each term's derivative, made from its atoms' derivatives, is the split of SymEngine's
    derivative of the whole term (the same keys and coefficients, so the same printed
    equations), and SymPy's derivative in value at random points (with d|u|/dx =
    sign(u) du/dx for real u)."""
    import random

    import sympy

    rng = random.Random(seed)
    expr = se.Add(*_random_terms(rng, 8))
    tables = TermTables(STATE, nonsmooth=True)
    table = tables.table(tables.split(expr), differentiated=True)
    real = {s: sympy.Symbol(s.name, real=True) for s in (x, y, v, t, a, b)}
    point = {s: rng.uniform(0.5, 1.5) for s in real.values()}
    for number, symbol in enumerate(STATE):
        times = 2  # v's number: the rate's q' factor
        for monomial, coefficient in table.items():
            routes = [None] * len(STATE)
            fast: dict = defaultdict(list)
            routes[number] = (fast, times)
            tables.differentiate({monomial: coefficient}, routes, [monomial])
            slow = tables.split(
                tables.derivative(tables.expr_of(monomial), symbol) * v, scale=coefficient
            )
            assert tables.table(fast) == tables.table(slow)
        derivative = tables.expr(tables.table(tables.diff(table, number)))
        exact = sympy.diff(sympy.sympify(str(expr)).xreplace(_by_name(real)), real[symbol])
        value = sympy.sympify(str(derivative)).xreplace(_by_name(real)).subs(point)
        assert float(value) == pytest.approx(float(exact.subs(point)), rel=1e-12, abs=1e-12)


def _by_name(real: dict) -> dict:
    return {sympy_symbol(s.name): r for s, r in real.items()}


def sympy_symbol(name: str):
    import sympy

    return sympy.Symbol(name)

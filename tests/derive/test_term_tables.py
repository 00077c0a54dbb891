"""The large route's term tables: {state monomial: parameter coefficient}, checked against
SymEngine's own expansion of the same expressions."""

from __future__ import annotations

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
        factors = monomial.args if type(monomial) is se.Mul else (monomial,)
        assert monomial == 1 or all(f.free_symbols & set(STATE) for f in factors)
        assert tables.symbols[monomial] == monomial.free_symbols & set(STATE)


def test_a_scaled_split_adds_to_what_is_there():
    tables = TermTables(STATE)
    into = tables.split(a * se.sin(x) * v)
    tables.split(b * se.sin(x) * v + se.cos(y), into, scale=a)
    table = tables.table(into)
    assert table[se.sin(x) * v] == a * (b + 1)  # a + a b, the common factor pulled out
    assert table[se.cos(y)] == a

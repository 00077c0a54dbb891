"""is_zero: a nonzero value at a point decides "not zero" without simplifying; a zero is
still proved by simplification, never by numbers alone."""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from lagrangian import algebra
from lagrangian.algebra import is_zero, nonzero_at_a_point, tidy_fraction

x, y = sympy.symbols("x y", real=True)
m, length = sympy.symbols("m l", positive=True)
k = sympy.Symbol("k", negative=True)

IDENTITIES = [
    sympy.sin(x) ** 2 + sympy.cos(x) ** 2 - 1,
    m * sympy.sin(2 * x) - 2 * m * sympy.sin(x) * sympy.cos(x),
    m * (x + 1) - m * x - m,
    sympy.cos(x) ** 2 - (1 + sympy.cos(2 * x)) / 2,
    sympy.tan(x) * sympy.cos(x) - sympy.sin(x),
    sympy.Abs(m * length) - m * length,  # the signs: m, l > 0
    sympy.sqrt(k**2) + k,  # k < 0
    sympy.Integer(0),
    sympy.Float(0.0),
]


@pytest.mark.parametrize("expr", IDENTITIES, ids=str)
def test_an_identity_is_never_called_nonzero(expr):
    assert not nonzero_at_a_point(expr)
    assert is_zero(expr)


def test_a_nonzero_expression_is_decided_without_simplifying(monkeypatch):
    # the force gradient of a top in Tait-Bryan angles: trigsimp took seconds to give up
    gradient = m * length**2 * (
        sympy.sin(x) * sympy.cos(x) * sympy.cos(y) ** 2 - sympy.sin(x) * sympy.cos(y)
    ) + m * sympy.sin(y) ** 2 * sympy.cos(x)

    def no_simplifying(*arguments, **options):
        raise AssertionError("simplified")

    monkeypatch.setattr(algebra, "tidy", no_simplifying)
    assert nonzero_at_a_point(gradient)
    assert not is_zero(gradient)


@pytest.mark.parametrize(
    "expr",
    [
        sympy.Function("A")(x, y) - sympy.Function("A")(y, x),  # an unspecified function
        1 / (sympy.sin(x) - sympy.sin(x)),  # undefined everywhere
        sympy.sqrt(-m),  # not real at any point of m's domain
    ],
    ids=str,
)
def test_what_cannot_be_evaluated_is_left_to_simplification(expr):
    assert not nonzero_at_a_point(expr)


def test_the_point_is_the_same_in_every_run():
    values = {s: algebra._probe_value(s) for s in (x, y, m, length, k)}
    assert values[k] < 0 < min(values[m], values[length])
    assert values == {s: algebra._probe_value(s) for s in (x, y, m, length, k)}
    assert values[x] != values[y]


def test_a_denominator_with_a_squared_cosine_is_written_as_a_textbook_writes_it():
    # the cart-pole's determinant: M - m cos^2(theta) + m is M + m sin^2(theta); the double
    # pendulum's m1 - m2 cos^2(theta1 - theta2) + m2 is m1 + m2 sin^2(theta1 - theta2)
    M, m, l, theta = sympy.symbols("M m l theta", positive=True)
    expr = sympy.sin(theta) / (l * (M - m * sympy.cos(theta) ** 2 + m))
    tidied = tidy_fraction(expr, [theta])
    assert sympy.fraction(tidied)[1] == l * (M + m * sympy.sin(theta) ** 2)
    assert sympy.simplify(tidied - expr) == 0
    eom = lg.load("double_pendulum").equations_of_motion()
    m1, m2, t1, t2 = (eom.system.symbol(n) for n in ("m1", "m2", "theta1", "theta2"))
    denominator = sympy.fraction(eom.accelerations["theta1"])[1]
    assert m1 + m2 * sympy.sin(t1 - t2) ** 2 in sympy.Mul.make_args(denominator)


def test_to_symengine_looks_up_a_converted_node_once():
    """A large model's positions are sums of the same terms: each term met again costs one
    lookup of the cache (before: a membership test, then the item)."""
    from lagrangian.algebra import to_symengine

    class Counted(dict):
        lookups = 0

        def __contains__(self, key):
            Counted.lookups += 1
            return super().__contains__(key)

        def __getitem__(self, key):
            Counted.lookups += 1
            return super().__getitem__(key)

        def get(self, key, default=None):
            Counted.lookups += 1
            return super().get(key, default)

    x, y = sympy.symbols("x y", real=True)
    terms = [x * sympy.sin(y), y * sympy.cos(x), x**2]
    cache = Counted()
    first = to_symengine(sympy.Add(*terms), cache)
    Counted.lookups = 0
    again = to_symengine(sympy.Add(*terms[:2]), cache)
    assert Counted.lookups == 3  # the new sum, then its two terms once each
    assert str(again) == str(to_symengine(sympy.Add(*terms[:2])))
    assert first == to_symengine(sympy.Add(*terms))

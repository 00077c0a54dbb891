"""Terms of top-level sums built once across texts (``Terms``): the same values, the same limits.

A chain's positions repeat the same terms; ``parse_expression(..., terms=Terms())`` builds
each distinct term once.  What every text parses to, and where a hostile text is refused
(message and position), must be what parsing it afresh gives: the limits a term charged
are charged again at each use.
"""

from __future__ import annotations

import random

import pytest
import sympy

from lagrangian.errors import ParseError
from lagrangian.parsing import Namespace, Terms, parse_expression

X = sympy.Symbol("x")
Y = {f"y{i}": sympy.Symbol(f"y{i}") for i in range(500)}
NAMESPACE = Namespace(symbols={"x": X, **Y, "l": sympy.Symbol("l", positive=True)})


def _outcome(text: str, terms: Terms | None = None):
    try:
        return parse_expression(text, NAMESPACE, terms=terms)
    except ParseError as error:
        return str(error)


def test_texts_sharing_terms_parse_as_they_do_alone():
    rng = random.Random(7)
    pieces = ["l*sin(y1)", "-l*cos(y2)", "sqrt(2)*x", "x**2/3", "(x - y3)*y4", "exp(-x)", "7"]
    texts = [" + ".join(rng.choice(pieces) for _ in range(rng.randint(1, 12))) for _ in range(40)]
    texts += ["0 + l*sin(y1)", "0 + l*sin(y1) + l*sin(y2)", "0+l*sin(y1)", " l*sin(y1) - x "]
    terms = Terms()
    for text in texts:
        assert _outcome(text, terms) == _outcome(text), text
    assert terms.built  # the terms were kept


@pytest.mark.parametrize(
    ("first", "second"),
    [
        # one root of a number per term: 400 are allowed in a text, 501 are not
        (" + ".join(["sqrt(2)*x"] * 400), " + ".join(["sqrt(2)*x"] * 501)),
        # compound arguments of functions: 300 in the first text, 450 in the second
        (
            " + ".join(f"sin(x*y{i})" for i in range(300)),
            " - ".join(f"sin(x*y{i})" for i in range(450)),
        ),
    ],
)
def test_a_text_of_terms_built_before_is_refused_where_it_would_be_alone(first, second):
    terms = Terms()
    assert isinstance(_outcome(first, terms), sympy.Expr)
    alone = _outcome(second)
    assert isinstance(alone, str) and "too costly" in alone
    assert _outcome(second, terms) == alone  # same message, same position


def test_terms_are_put_in_the_order_sympy_sorts_a_sum_in():
    """``Terms.in_canonical_order`` sorts as SymPy's Add does (``Basic.compare``): Add then
    sorts a model's sums with n - 1 comparisons; the sum is the same whatever the order."""
    import functools

    rng = random.Random(3)
    x, l = X, NAMESPACE.symbols["l"]
    pool = [x, -x, 2 * x, l * sympy.sin(x), -l * sympy.cos(Y["y1"]), sympy.Rational(1, 3)]
    pool += [Y[f"y{i}"] * x**i for i in range(1, 30)] + [sympy.sqrt(2) * Y["y2"], sympy.exp(x)]
    terms = Terms()
    for _ in range(40):
        values = rng.sample(pool, rng.randint(1, 20))
        ordered = terms.in_canonical_order(values)
        assert ordered == sorted(values, key=functools.cmp_to_key(sympy.Basic.compare))
        assert sympy.Add(*ordered).args == sympy.Add(*values).args


def test_the_sizes_of_a_sums_numbers_are_estimated_alike_from_terms_seen_before():
    from lagrangian.parsing.limits import sum_size

    rng = random.Random(5)
    pool = [X / 3, X**2 / 7, sympy.Rational(10**30, 11) * X, sympy.sqrt(2) * Y["y1"] / 13]
    pool += [Y[f"y{i}"] / (i + 2) for i in range(40)] + [X, 2 ** (X + 1)]
    known: dict = {}
    for limit in (5, 50, 1000):
        for _ in range(30):
            values = rng.sample(pool, rng.randint(1, 30))
            assert sum_size(values, limit, known) == sum_size(values, limit)


def test_a_sum_of_plain_terms_is_the_sum_sympy_makes():
    """``sorted_sum`` makes Add's result without its evaluation where Add would only keep
    the terms in order; sums of numbers, like terms, nested sums, numeric powers are left
    to Add (None).  Whatever it makes is Add's sum, argument for argument."""
    import functools

    from lagrangian.parsing.terms import sorted_sum

    rng = random.Random(8)
    x, l, y1, y2 = X, NAMESPACE.symbols["l"], Y["y1"], Y["y2"]
    pool = [x, -x, 2 * x, l * sympy.sin(x), -l * sympy.cos(y1), sympy.Rational(1, 3), y1 + y2]
    pool += [y1 * x**2, sympy.sqrt(2) * y2, sympy.exp(x), sympy.Pow(2, 3, evaluate=False)]
    pool += [sympy.Integer(0), sympy.Function("f")(x), -3 * l * y1 / 7, x**y1, sympy.sqrt(l)]
    key = functools.cmp_to_key(sympy.Basic.compare)
    made = 0
    known: dict = {}  # each term's part, kept across the sums (a model's sums share terms)
    for _ in range(400):
        values = sorted(rng.sample(pool, rng.randint(1, 8)), key=key)
        fast = sorted_sum(values)
        remembered = sorted_sum(values, known)
        assert (fast is None and remembered is None) or fast.args == remembered.args
        if fast is not None:
            made += 1
            expected = sympy.Add(*values)
            assert type(fast) is type(expected) and fast.args == expected.args
            assert fast == expected and hash(fast) == hash(expected)
    assert 100 < made < 400


def _assumed_symbols() -> list[sympy.Symbol]:
    """Symbols of every kind a model declares, and a few it does not (not real, zero)."""
    kinds = [{}, {"real": True}, {"positive": True}, {"nonnegative": True}, {"negative": True}]
    kinds += [{"zero": True}, {"imaginary": True}, {"commutative": False}, {"integer": True}]
    return [sympy.Symbol(f"s{k}", **kind) for k, kind in enumerate(kinds)]


def test_sin_and_cos_of_a_symbol_are_sympys():
    """``plain_call`` makes sin(q) without SymPy's eval only where eval keeps it as it is
    (a real symbol not known to be zero), with SymPy's type, args, nargs, equality and hash;
    elsewhere it leaves the call to SymPy (None)."""
    from lagrangian.parsing.terms import plain_call

    made = 0
    for symbol in _assumed_symbols():
        for function in (sympy.sin, sympy.cos, sympy.tan, sympy.exp, sympy.Abs):
            fast = plain_call(function, symbol)
            expected = function(symbol)
            if fast is None:
                continue
            made += 1
            assert type(fast) is type(expected) and fast.args == expected.args
            assert fast == expected and hash(fast) == hash(expected)
            assert fast.nargs == expected.nargs and fast.is_real == expected.is_real
    assert made == 10  # sin and cos of the real, positive, nonnegative, negative, integer
    zero = sympy.Symbol("z", zero=True)
    assert plain_call(sympy.sin, zero) is None and sympy.sin(zero) == 0
    assert plain_call(sympy.sin, sympy.Symbol("x", imaginary=True)) is None
    assert plain_call(sympy.sin, 2 * X) is None and plain_call(sympy.sin, sympy.pi) is None


def test_a_product_of_plain_factors_is_the_product_sympy_makes():
    """``plain_product`` makes Mul's result without its evaluation for distinct symbols
    and sines and cosines of them; powers, numbers, like factors, exp are left to Mul."""
    import functools

    from lagrangian.parsing.terms import plain_product

    rng = random.Random(9)
    symbols = _assumed_symbols()
    pool = [*symbols, *(f(s) for s in symbols[:5] for f in (sympy.sin, sympy.cos))]
    pool += [sympy.Integer(2), sympy.Rational(-1, 3), X**2, sympy.exp(X), sympy.exp(Y["y1"])]
    pool += [X + Y["y1"], sympy.sqrt(X), sympy.Function("f")(X), sympy.pi, X * Y["y2"]]
    key = functools.cmp_to_key(sympy.Basic.compare)
    made = 0
    for _ in range(600):
        factors = [rng.choice(pool) for _ in range(rng.randint(1, 5))]
        fast = plain_product(factors)
        if fast is not None:
            made += 1
            expected = sympy.Mul(*factors)
            assert type(fast) is type(expected) and fast.args == expected.args
            assert fast == expected and hash(fast) == hash(expected)
            assert list(fast.args) == sorted(factors, key=key)
    assert 50 < made < 600


def test_the_parts_of_a_sum_are_found_by_identity(monkeypatch):
    """``Terms.union`` and ``sorted_sum``'s memo find a term met before by identity (the
    terms are built once per model): no SymPy hash, a Python call, per use of a term."""
    from lagrangian.parsing.terms import sorted_sum

    terms = Terms()
    values = [sympy.Symbol(f"y{i}") * sympy.sin(X) for i in range(30)]
    total = sympy.Add(*values)
    ordered = list(total.args)
    known: dict = {}
    assert terms.union(total, lambda term: {len(term.args)}) == {2}
    assert sorted_sum(ordered, known) == total
    hashed: list = []
    basic_hash = sympy.Basic.__hash__

    def counted(self):
        hashed.append(self)
        return basic_hash(self)

    monkeypatch.setattr(sympy.Basic, "__hash__", counted)
    assert terms.union(total, lambda term: {len(term.args)}) == {2}
    assert not hashed
    assert sorted_sum(ordered, known) == total
    assert len(hashed) == 2 * len(ordered)  # only the parts, in and into its set of seen

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

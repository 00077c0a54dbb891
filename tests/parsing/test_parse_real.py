"""Constants that are not real numbers are refused where they are written, naming them.

SymPy carries ``sqrt(-1)`` as ``I`` and ``acos(2)`` unevaluated; a model holding
one derived complex equations (or spent a minute simplifying them).
"""

from __future__ import annotations

import pytest
import sympy

from lagrangian.errors import ParseError
from lagrangian.parsing import Namespace, parse_expression
from lagrangian.parsing.constants import NotRealError, RealConstants

NOT_REAL = {
    "sqrt(-1)": ("sqrt(-1) is not a real number", 0),
    "acos(2)": ("acos(2) is not a real number", 0),
    "atan2(acos(2), acos(2))": ("acos(2) is not a real number", 6),
    "log(-1)": ("log(-1) is not a real number", 0),
    "(-1)^(1/2)": ("(-1)**(1/2) is not a real number", 4),
    "asin(3)": ("asin(3) is not a real number", 0),
    "(-8)^(1/3)": ("(-8)**(1/3) is not a real number", 4),
    "(-8)**(2/3)": ("(-8)**(2/3) is not a real number", 4),
    "(-2)**pi": ("(-2)**(pi) is not a real number", 4),
    "x*acos(1/2 + sqrt(2)/2)": ("acos(1/2 + sqrt(2)/2) is not a real number", 2),
    "sqrt(sin(1) - 1)": ("sqrt(-1 + sin(1)) is not a real number", 0),
    "exp(log(-2)/2)": ("log(-2) is not a real number", 4),
    "asin(exp(1))": ("asin(E) is not a real number", 0),
    "(1 - sqrt(3))^(1/2)": ("(1 - sqrt(3))**(1/2) is not a real number", 13),
    r"\sqrt{-2}": ("sqrt(-2) is not a real number", 0),
    r"\arccos(2) x": ("acos(2) is not a real number", 0),
    "log(0)": ("log(0) is infinite or undefined", 0),
    "1/0": ("division by zero", 1),
}

REAL = {
    "asin(1)": sympy.pi / 2,
    "acos(-1/2)": 2 * sympy.pi / 3,
    "log(exp(-3))": sympy.Integer(-3),
    "(-8)**3": sympy.Integer(-512),
    "(-2)**(-2)": sympy.Rational(1, 4),
    "sqrt(4)": sympy.Integer(2),
    "atan2(-1, -1)": -3 * sympy.pi / 4,
}


@pytest.mark.parametrize("text", NOT_REAL, ids=list(NOT_REAL))
def test_a_constant_that_is_not_real_is_refused_naming_it(parse_error, text):
    message, position = NOT_REAL[text]
    error = parse_error(text)
    assert (error.message, error.position) == (message, position)


@pytest.mark.parametrize("text", REAL, ids=list(REAL))
def test_real_constants_are_kept(parse, text):
    assert parse(text) == REAL[text]


def test_symbolic_roots_and_logarithms_stay(parse, s):
    x = s["x"]
    assert parse("sqrt(x) + log(x) + acos(x) + x**(1/3)") == (
        sympy.sqrt(x) + sympy.log(x) + sympy.acos(x) + x ** sympy.Rational(1, 3)
    )


def test_a_constant_that_rounding_cannot_decide_is_kept(parse):
    # zero, but SymPy does not simplify it: the interval straddles 0, so no refusal
    assert parse("sqrt(sin(1)^2 + cos(1)^2 - 1)").has(sympy.sin(1))
    assert parse("asin(sin(1)^2 + cos(1)^2)").has(sympy.cos(1))


def test_constants_beyond_double_precision_are_refused_where_made(parse):
    # SymPy deciding the sign of one evaluates it at ever higher precision (minutes)
    for text, made in [
        ("exp(exp(exp(10)))", "exp(exp(10))"),
        ("asin(exp(exp(20)))", "exp(exp(20))"),
        ("cosh(10**99)", "cosh(1000000000"),
        ("atan2(x, -cosh(cosh(123456789)))", "cosh(123456789)"),
        ("x*exp(-800)", "exp(-800)"),
        ("E**1000", "(E)**(1000)"),
        ("2**exp(700)", "(2)**(exp(700))"),
    ]:
        with pytest.raises(
            ParseError, match=r"the number (.*) is beyond double precision"
        ) as caught:
            parse(text)
        assert made in str(caught.value), text
    for text in ("sin(10**1000)", "exp(709)*x", "exp(-700)", "sinh(-700)"):
        assert isinstance(parse(text), sympy.Expr)


def test_the_checker_names_the_subexpression_of_a_sympy_expression():
    x = sympy.Symbol("x", real=True)
    checker = RealConstants()
    checker.check(x * sympy.sqrt(2) + sympy.exp(sympy.pi))
    with pytest.raises(NotRealError) as caught:
        checker.check(x + sympy.acos(3, evaluate=False))
    assert caught.value.subexpression == sympy.acos(3)
    with pytest.raises(NotRealError) as caught:
        checker.check(sympy.Float(2.5) * sympy.zoo * x)
    assert caught.value.reason == "is infinite or undefined"


def test_a_deep_sympy_expression_does_not_recurse():
    x = sympy.Symbol("x", real=True)
    deep = x
    for _ in range(3_000):
        deep = sympy.sin(deep, evaluate=False)
    RealConstants().check(deep)


def test_the_root_of_a_negative_parameter_is_refused():
    # SymPy writes sqrt(-g) as I*sqrt(g) for a positive g; a real g may be negative
    g, a = sympy.Symbol("g", positive=True), sympy.Symbol("a", real=True)
    namespace = Namespace({"g": g, "a": a})
    with pytest.raises(ParseError) as caught:
        parse_expression("a + sqrt(-g)", namespace)
    assert str(caught.value) == "sqrt(-g) is not a real number at position 5"
    assert parse_expression("sqrt(-a)", namespace) == sympy.sqrt(-a)


def test_a_checker_meeting_no_constant_makes_no_interval_context():
    """mpmath's contexts and the function table are made on the first constant met: the
    checker of an expression with none (a position's sin(q)) never needs them."""
    x = sympy.Symbol("x", real=True)
    checker = RealConstants()
    checker.check(sympy.Symbol("l", positive=True) * sympy.sin(x) + x * sympy.cos(x))
    assert not {"iv", "mp", "functions"} & set(vars(checker))
    with pytest.raises(NotRealError, match="acos"):
        checker.check(x * sympy.acos(2))
    assert {"iv", "mp", "functions"} <= set(vars(checker))

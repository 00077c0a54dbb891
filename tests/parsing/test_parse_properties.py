"""Properties: any text gives an expression or a ParseError, quickly; valid text parses right.

Every example runs under a hard deadline (SIGALRM raising a BaseException the
parser cannot swallow), so a hang fails with the text that caused it instead
of stalling the suite.  Examples are derandomized: CI sees the same ones.
"""

from __future__ import annotations

import math
import sys
import time

import pytest
import sympy
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from parsing_fixtures import NAMESPACE, ParseDeadline, S, hard_deadline

from lagrangian.errors import LagrangianError, ParseError
from lagrangian.parsing import parse_expression, referenced_names
from lagrangian.parsing.constants import NotRealError, RealConstants

SECONDS = 2.0  # a parse takes milliseconds; this is a hard stop for a hang
SETTINGS = settings(
    max_examples=250,
    deadline=None,  # ours is hard_deadline: Hypothesis' own cannot interrupt a hang
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)

PLAIN_TOKENS = [
    "x", "y", "theta", "theta_dot", "A", "V", "m", "pi", "E", "sin", "cos", "exp", "log",
    "sqrt", "atan2", "Abs", "unknown", "_x", "a__b", "0", "1", "2", "10", "0.5", ".5", "1e3",
    "2.5E-2", "9" * 40, "+", "-", "*", "/", "**", "^", "(", ")", ",", " ", "  ", "θ",
    "\u03b8\u0307", "²", "⁻¹", "·", "−", "×", "[", "]", ".", "=", "'", '"', ";", ":", "_",
    "9**9", "lambda", "__class__",
]  # fmt: skip
LATEX_TOKENS = [
    "\\frac", "{", "}", "\\dot", "\\ddot", "\\theta", "\\phi", "\\sin", "\\cos", "\\ln",
    "\\sqrt", "\\left(", "\\right)", "\\left[", "\\right]", "_1", "_{2}", "_", "\\cdot",
    "\\times", "\\,", "\\quad", "\\pi", "\\foo", "\\", "^{2}", "^", "\\input", "\\varphi",
]  # fmt: skip

token_text = st.lists(st.sampled_from(PLAIN_TOKENS + LATEX_TOKENS), max_size=40).map("".join)
plain_token_text = st.lists(st.sampled_from(PLAIN_TOKENS), max_size=40).map("".join)
language_text = st.text(
    alphabet=st.sampled_from(list("xyzmAV0123456789+-*/^().,eE_ \\{}[]θ²·sinco")), max_size=120
)


def check(text: str) -> None:
    """``text`` gives a real expression or a ParseError (nothing else), in time; names agree."""
    try:
        with hard_deadline(SECONDS, text):
            result = parse_expression(text, NAMESPACE)
    except ParseError:
        result = None
    if result is not None:
        assert isinstance(result, sympy.Expr)
        assert not result.has(sympy.zoo, sympy.nan, sympy.oo, sympy.I)
        RealConstants().check(result)  # no constant in it is certainly not real
    try:
        found = referenced_names(text)
    except ParseError:
        assert result is None  # what has no syntax cannot be parsed either
        return
    if result is not None:
        assert found.symbols <= set(NAMESPACE.symbols) | set(NAMESPACE.functions)
        assert found.functions <= set(NAMESPACE.functions)


@pytest.mark.slow
@SETTINGS
@given(st.text(max_size=200))
def test_any_text(text):
    check(text)


@SETTINGS
@given(language_text)
def test_text_from_the_alphabet_of_the_language(text):
    check(text)


@SETTINGS
@given(token_text)
def test_sequences_of_tokens(text):
    check(text)


@SETTINGS
@given(plain_token_text)
def test_sequences_of_plain_tokens(text):
    check(text)


# -- hostile soup: big exponents, deep calls, constants outside the real domain, LaTeX ----

HOSTILE_TOKENS = [
    "1e400", "9e999", "1e-400", "10**1000", "9**9**9", "(2**1000)", "**1000", "^999", "**-1",
    "**(1/3)", "^(1/2)", "^0.5", "**(1/1001)", "0", "-1", "-8", "2", "3", "1/0", "9" * 100,
    "sin(", "cos(", "tan(", "asin(", "acos(", "atan(", "atan2(", "sqrt(", "log(", "exp(",
    "sinh(", "cosh(", "Abs(", "sign(", "V(", "A(", "(", ")", ",", "+", "-", "*", "/", "x", "y",
    "theta", "pi", "E", "x_dot", "\\frac{", "}{", "}", "{", "\\sqrt{", "\\sqrt[3]{", "\\left(",
    "\\right)", "\\cdot", "\\dot{x}", "\\ddot{\\theta}", "\\arccos", "\\arcsin", "\\ln",
    "\\exp", "^{", "_{", "\\pi", "\\theta", " ",
]  # fmt: skip
hostile_soup = st.lists(st.sampled_from(HOSTILE_TOKENS), max_size=60).map("".join)

_FUNCTIONS = ["sin", "cos", "tan", "cot", "sec", "csc", "asin", "acos", "atan", "sinh",
              "cosh", "tanh", "exp", "log", "sqrt", "Abs", "sign"]  # fmt: skip
_LEAVES = st.sampled_from(
    ["x", "y", "theta", "pi", "E", "0", "1", "2", "-1", "-2", "1/2", "3", "10**300", "0.5",
     "1e-300", "(-8)", "V(x)", "A(x, y, 0)"]
)  # fmt: skip


def _compose(children):
    call = st.tuples(st.sampled_from(_FUNCTIONS), children).map(lambda c: f"{c[0]}({c[1]})")
    atan2 = st.tuples(children, children).map(lambda c: f"atan2({c[0]}, {c[1]})")
    binary = st.tuples(children, st.sampled_from(["+", "-", "*", "/", "**", "^"]), children).map(
        lambda c: f"({c[0]}){c[1]}({c[2]})"
    )
    root = st.tuples(children, st.sampled_from(["1/2", "1/3", "2/3", "-1/2", "pi", "x"])).map(
        lambda c: f"({c[0]})**({c[1]})"
    )
    return st.one_of(call, atan2, binary, root, children.map(lambda c: f"-({c})"))


random_expressions = st.recursive(_LEAVES, _compose, max_leaves=16)


@settings(SETTINGS, max_examples=400)
@given(hostile_soup)
def test_hostile_token_soup(text):
    check(text)


@pytest.mark.slow
@settings(SETTINGS, max_examples=400)
@given(random_expressions)
def test_random_expressions_with_constants_anywhere(text):
    check(text)


# -- huge constants under the functions whose value SymPy decides by evaluating ----------
# (atan2(x, -cosh(cosh(123456789))) evaluated at ever higher precision, for minutes)

_BIG = st.sampled_from(["123456789", "1000", "710", "-800", "10**99", "1e300", "x", "pi"])
_GROWTH = st.sampled_from(["exp", "cosh", "sinh", "-exp", "-cosh", "1 - cosh", "1/exp"])


def _grown(children):
    return st.tuples(_GROWTH, children).map(lambda c: f"{c[0]}({c[1]})")


huge_constants = st.recursive(_BIG, _grown, max_leaves=4)
deciders = st.one_of(
    st.tuples(st.sampled_from(["sign", "Abs", "acos", "asin", "log", "sqrt", "atan", "sin"]),
              huge_constants).map(lambda c: f"{c[0]}({c[1]})"),
    st.tuples(huge_constants, huge_constants).map(lambda c: f"atan2({c[0]}, {c[1]})"),
    st.tuples(huge_constants, st.sampled_from(["2", "(1/2)", "E", "x", "(-2)"])).map(
        lambda c: f"{c[1]}**({c[0]})"
    ),
)  # fmt: skip


@settings(SETTINGS, max_examples=300)
@given(deciders)
def test_huge_constants_where_sympy_decides_by_evaluating(text):
    check(text)


@settings(SETTINGS, max_examples=150)
@given(random_expressions)
def test_random_expressions_in_a_model(text):
    """Through the model builder: a System or a LagrangianError, in time, never anything else."""
    import lagrangian as lg

    try:
        with hard_deadline(SECONDS, text):
            lg.System.from_lagrangian(f"x_dot**2/2 + ({text})", coordinates=["x", "y", "theta"])
    except LagrangianError:
        pass


# -- valid expressions, built as text and as SymPy objects side by side ---------------------

x, y, theta = S["x"], S["y"], S["theta"]
NON_FINITE = (sympy.zoo, sympy.nan, sympy.oo, -sympy.oo)
LEAVES = st.sampled_from(
    [("x", x), ("y", y), ("theta", theta), ("pi", sympy.pi)]
    + [(str(n), sympy.Integer(n)) for n in range(6)]
    + [("0.25", sympy.Rational(1, 4)), ("1e-2", sympy.Rational(1, 100))]
).map(lambda leaf: (*leaf, False, False))
UNARY = {
    "sin": sympy.sin,
    "cos": sympy.cos,
    "exp": sympy.exp,
    "log": sympy.log,
    "sqrt": sympy.sqrt,
    "Abs": sympy.Abs,
}


def _node(text: str, value: sympy.Expr, *children) -> tuple[str, sympy.Expr, bool, bool]:
    """(text, value, whether an infinite, undefined or complex value arose on the way,
    whether a constant beyond double precision did)."""
    undefined = any(child[2] for child in children) or value.has(*NON_FINITE) or _not_real(value)
    beyond = any(child[3] for child in children) or (not undefined and _beyond_double(value))
    return text, value, undefined, beyond


def _beyond_double(value: sympy.Expr) -> bool:
    """``exp(pi**6)`` (about 10^417) is a real number SymPy keeps exact, but no double holds
    it, and the parser may refuse it (it does where its enclosure says so for certain)."""
    if not value.is_number or value.is_zero:
        return False
    bounds = RealConstants().bounds(value)
    if bounds is None:  # no enclosure: exp(exp(pi**3)) overflows mpmath's intervals
        magnitude = sympy.Abs(value).evalf(15)  # mpmath's exponents have no such limit
        return magnitude.is_Float and not (
            math.ulp(0.0) <= magnitude <= sys.float_info.max and math.isfinite(magnitude)
        )
    return max(abs(end) for end in bounds) == math.inf or bounds == (0.0, 0.0)


def _not_real(value: sympy.Expr) -> bool:
    """``sqrt(cos(2))`` has no ``I`` but is not real (cos(2) < 0): the parser refuses it."""
    try:
        RealConstants().check(value)
    except NotRealError:
        return True
    return False


def _extend(children):
    binary = st.tuples(st.sampled_from("+-*/"), children, children).map(_binary)
    power = st.tuples(children, st.integers(-3, 3)).map(
        lambda c: _node(f"({c[0][0]})**({c[1]})", sympy.Pow(c[0][1], c[1]), c[0])
    )
    unary = st.tuples(st.sampled_from(sorted(UNARY)), children).map(
        lambda c: _node(f"{c[0]}({c[1][0]})", UNARY[c[0]](c[1][1]), c[1])
    )
    negate = children.map(lambda c: _node(f"-({c[0]})", -c[1], c))
    return st.one_of(binary, power, unary, negate)


def _binary(parts):
    op, left, right = parts
    value = {"+": left[1] + right[1], "-": left[1] - right[1], "*": left[1] * right[1]}.get(op)
    if op == "/":
        value = left[1] / right[1]
    return _node(f"({left[0]}) {op} ({right[0]})", value, left, right)


expressions = st.recursive(LEAVES, _extend, max_leaves=12)


@settings(max_examples=300, deadline=None)
@given(expressions)
def test_valid_expressions_parse_to_the_same_object(node):
    text, expected, undefined, beyond = node
    if undefined:
        try:
            parse_expression(text, NAMESPACE)
        except ParseError:
            return
        raise AssertionError(f"{text!r} should be refused")
    assume(isinstance(expected, sympy.Expr))
    if beyond:
        try:
            parsed = parse_expression(text, NAMESPACE)
        except ParseError as error:
            assert "beyond double precision" in str(error)
            return
        assert parsed == expected
        return
    assert parse_expression(text, NAMESPACE) == expected


def test_a_constant_beyond_double_is_valid_text_the_parser_may_refuse():
    """Hypothesis found ``exp(((pi)**(2))**(3))``: e**(pi**6), about 10^417."""
    pi = ("pi", sympy.pi, False, False)
    squared = _node("(pi)**(2)", sympy.pi**2, pi)
    cubed = _node("((pi)**(2))**(3)", sympy.pi**6, squared)
    huge = _node("exp(((pi)**(2))**(3))", sympy.exp(sympy.pi**6), cubed)
    assert huge[2:] == (False, True) and cubed[2:] == (False, False)
    test_valid_expressions_parse_to_the_same_object.hypothesis.inner_test(huge)


def test_a_constant_without_an_enclosure_beyond_double_may_be_refused():
    """Hypothesis found ``exp(exp(pi**3))``, about 10^(1.3e13): its enclosure overflows
    mpmath's intervals (no bounds), and the parser refuses it from its exponent's bounds."""
    pi = ("pi", sympy.pi, False, False)
    cubed = _node("pi**3", sympy.pi**3, pi)
    inner = _node("exp(pi**3)", sympy.exp(sympy.pi**3), cubed)
    huge = _node("exp(exp(pi**3))", sympy.exp(sympy.exp(sympy.pi**3)), inner)
    assert huge[2:] == (False, True) and inner[2:] == (False, False)
    test_valid_expressions_parse_to_the_same_object.hypothesis.inner_test(huge)


def test_the_deadline_cannot_be_swallowed(monkeypatch):
    """A hang inside SymPy, under an ``except Exception`` that retries, still ends."""

    def stubborn(*args, **kwargs):
        while True:
            try:
                time.sleep(0.01)
            except Exception:  # what a careless parser might do
                continue

    monkeypatch.setattr(sympy, "Pow", stubborn)  # called under the builder's except Exception
    expected = r"still parsing after 0.2 s: 'x\*\*3'"  # swallowed, it would never end
    with pytest.raises(ParseDeadline, match=expected), hard_deadline(0.2, "x**3"):
        parse_expression("x**3", NAMESPACE)

"""Properties: any text gives an expression or a ParseError, quickly; valid text parses right."""

from __future__ import annotations

import time

import sympy
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from parsing_fixtures import NAMESPACE, S

from lagrangian.errors import ParseError
from lagrangian.parsing import parse_expression, referenced_names

SECONDS = 1.5
SETTINGS = settings(max_examples=250, deadline=None, suppress_health_check=[HealthCheck.too_slow])

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
    """``text`` gives an expression or a ParseError (nothing else), in time; names agree."""
    start = time.perf_counter()
    try:
        result = parse_expression(text, NAMESPACE)
    except ParseError:
        result = None
    assert time.perf_counter() - start < SECONDS
    if result is not None:
        assert isinstance(result, sympy.Expr)
        assert not result.has(sympy.zoo, sympy.nan, sympy.oo)
    try:
        found = referenced_names(text)
    except ParseError:
        assert result is None  # what has no syntax cannot be parsed either
        return
    if result is not None:
        assert found.symbols <= set(NAMESPACE.symbols) | set(NAMESPACE.functions)
        assert found.functions <= set(NAMESPACE.functions)


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


# -- valid expressions, built as text and as SymPy objects side by side ---------------------

x, y, theta = S["x"], S["y"], S["theta"]
NON_FINITE = (sympy.zoo, sympy.nan, sympy.oo, -sympy.oo)
LEAVES = st.sampled_from(
    [("x", x), ("y", y), ("theta", theta), ("pi", sympy.pi)]
    + [(str(n), sympy.Integer(n)) for n in range(6)]
    + [("0.25", sympy.Rational(1, 4)), ("1e-2", sympy.Rational(1, 100))]
).map(lambda leaf: (*leaf, False))
UNARY = {
    "sin": sympy.sin,
    "cos": sympy.cos,
    "exp": sympy.exp,
    "log": sympy.log,
    "sqrt": sympy.sqrt,
    "Abs": sympy.Abs,
}


def _node(text: str, value: sympy.Expr, *children) -> tuple[str, sympy.Expr, bool]:
    """(text, value, whether an infinite, undefined or complex value arose on the way)."""
    undefined = any(child[2] for child in children) or value.has(*NON_FINITE, sympy.I)
    return text, value, undefined


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
    text, expected, undefined = node
    if undefined:
        try:
            parse_expression(text, NAMESPACE)
        except ParseError:
            return
        raise AssertionError(f"{text!r} should be refused")
    assume(isinstance(expected, sympy.Expr))
    assert parse_expression(text, NAMESPACE) == expected

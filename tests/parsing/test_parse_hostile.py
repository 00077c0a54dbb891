"""Hostile input: refused (or parsed correctly), always quickly, never by evaluating Python."""

from __future__ import annotations

import pytest
import sympy
from parsing_fixtures import hard_deadline

from lagrangian.errors import ParseError
from lagrangian.parsing import ParseLimits, parse_expression

#: A hard stop for a hang, not a timing assertion (timings live in benchmarks/hostile.py):
#: every call finishes well within a second on a quiet machine.
HANG_SECONDS = 15

BIG = "9" * 100  # the longest literal allowed


def parsed(text: str, namespace, limits: ParseLimits | None = None):
    """The result or the ParseError; a hang fails at a hard deadline instead of stalling."""
    try:
        with hard_deadline(HANG_SECONDS, text):
            if limits is None:
                result = parse_expression(text, namespace)
            else:
                result = parse_expression(text, namespace, limits)
    except ParseError as error:
        result = error
    return result


REFUSED = {
    "import": "__import__('os').system('x')",
    "dunder attribute": "().__class__",
    "dunder name": "x.__class__",
    "lambda": "lambda: 0",
    "eval": 'eval("1")',
    "exec": "exec('import os')",
    "string": '"abc"',
    "attribute": "x.y",
    "index": "x[0]",
    "keyword call": "sin(x=1)",
    "semicolon": "x; import os",
    "backtick": "`x`",
    "tower of nines": "9**9**9**9",
    "tower of tens": "10**10**10",
    "power of a power": "(10**999)**999",
    "huge literal exponent": "1e999999",
    "long literal exponent": "1e" + "9" * 5000,
    "200 digits": "1" * 200,
    "deep parentheses": "(" * 10_000,
    "deep closed parentheses": "(" * 5_000 + "x" + ")" * 5_000,
    "many minus signs": "-" * 5_000 + "x",
    "power chain": "x" + "^x" * 5_000,
    "deep calls": "sin(" * 2_000 + "x" + ")" * 2_000,
    "deep braces": "{" * 5_000 + "x" + "}" * 5_000,
    "deep fractions": r"\frac{" * 1_000 + "1" + "}{2}" * 1_000,
    "too long": "x+" * 10_001 + "x",
    "big product": "*".join(["(9**999)"] * 100),
    "root of a long number": f"sqrt({BIG}*{BIG}*{BIG}+1)",
    "root through exp": f"exp(log({BIG}*{BIG}*{BIG}+1)/2)",
    "root through E": f"E**(log({BIG}*{BIG}*{BIG}+1)/3)",
    "root through trigonometry": f"cos(asin({BIG}/({BIG}+1)))",
    "merged symbolic exponents": "2**(x + 10**300)*2**(-x)",
    "merged scaled exponents": "2**(10**300*x)*2**(-10**300*x + 10**300)",
    "power of a symbolic power": "(2**(10**300*x))**(1/x)",
    "merged logs": "exp(10**300*x*log(2))*exp(-10**300*x*log(2) + 10**300*log(2))",
    "many roots": "+".join(f"sqrt({10**9 + i})" for i in range(1_100)),
    "many long roots": "+".join(f"sqrt({BIG}*{10**99 + i})" for i in range(95)),
    "merged roots": "*".join(f"sqrt({10**9 + i})" for i in range(1_000)),
    "harmonic denominators": "+".join(f"1/{10**15 + i}" for i in range(1_100)),
    "huge function argument": "cos("
    + "+".join(f"x**{i % 30}*y**{i // 30}" for i in range(1_500))
    + ")",
    "huge exponent": "x**(" + "+".join(f"x**{i % 30}*y**{i // 30}" for i in range(1_500)) + ")",
    "sympy failing inside": "atan(tan(7**300 + 2))",
    "root through atan2": "cos(atan2(7**300, 7**300 + 1))",
    "null byte": "x\x00",
    "format string": "{x!r:>{y}}",
    "latex input": r"\input{/etc/passwd}",
    "latex def": r"\def\x{\x}\x",
}

ACCEPTED = {
    "20k-character sum": "+".join(["x"] * 10_000),
    "20k-character product": "*".join(["x"] * 10_000),
    "20k-character quotient": "/".join(["x"] * 10_000),
    "long exact product": "*".join(["2"] * 9_000),
    "long exact quotient": "1/3*" * 4_000 + "1",
    "10**1000": "10**1000",
    "1e400": "1e400",
    "nested calls at the limit": "sin(" * 60 + "x" + ")" * 60,
    "nested roots": "sqrt(" * 60 + BIG + ")" * 60,
    "many decimals": "+".join(["0." + "1" * 99] * 150),
    "harmonic sum": "+".join(f"1/{i}" for i in range(1, 2_000)),
    "powers of products": "*".join(f"({p}*x)**1000" for p in (2, 3, 5, 7, 11)),
}


@pytest.mark.parametrize("text", REFUSED.values(), ids=REFUSED.keys())
def test_refused_quickly(ns, text):
    result = parsed(text, ns)
    assert isinstance(result, ParseError), result


@pytest.mark.parametrize("text", ACCEPTED.values(), ids=ACCEPTED.keys())
def test_accepted_quickly(ns, text):
    result = parsed(text, ns)
    assert isinstance(result, sympy.Expr), result


def test_accepted_results_are_right(ns, s):
    x = s["x"]
    assert parse_expression("+".join(["x"] * 10_000), ns) == 10_000 * x
    assert parse_expression("*".join(["x"] * 10_000), ns) == x**10_000
    assert parse_expression("*".join(["2"] * 9_000), ns) == sympy.Integer(2) ** 9_000
    assert parse_expression("10**1000", ns) == sympy.Integer(10) ** 1000


def test_nothing_is_evaluated(ns, monkeypatch):
    """Hostile text never reaches Python's evaluation, even when it fails to parse."""
    import builtins

    def forbidden(*args, **kwargs):
        raise AssertionError("evaluation attempted")

    monkeypatch.setattr(builtins, "eval", forbidden)
    monkeypatch.setattr(builtins, "exec", forbidden)
    monkeypatch.setattr(sympy, "sympify", forbidden)
    for text in list(REFUSED.values())[:12]:
        with pytest.raises(ParseError):
            parse_expression(text, ns)
    assert parse_expression("sin(x)**2 + 0.5", ns) == sympy.sin(ns.symbols["x"]) ** 2 + sympy.S.Half


def test_node_limit(ns):
    limits = ParseLimits(max_nodes=100)
    with pytest.raises(ParseError) as caught:
        parse_expression("+".join(["x"] * 60), ns, limits)
    assert caught.value.message == "expression too large (more than 100 tokens)"
    assert parse_expression("+".join(["x"] * 50), ns, limits) == 50 * ns.symbols["x"]


def test_smaller_limits(ns):
    limits = ParseLimits(
        max_length=50, max_depth=3, max_exponent=10, max_number_digits=5, max_result_digits=20
    )
    messages = {
        "x" * 51: "expression too long (51 characters, limit 50)",
        "((((x))))": "expression nested too deeply (limit 3)",
        "x**11": "exponent 11 too large (limit 10)",
        "123456": "number with 6 digits too long (limit 5)",
        "99999*99999*99999*99999*99999": "number too large (about 25 digits, limit 20)",
        "2**(1/11)": "exponent 1/11 has too large a denominator (limit 10)",
    }
    for text, message in messages.items():
        with pytest.raises(ParseError) as caught:
            parse_expression(text, ns, limits)
        assert caught.value.message == message
    assert parse_expression("(((x)))", ns, limits) == ns.symbols["x"]
    assert parse_expression("x**(1/11)", ns, limits) == ns.symbols["x"] ** sympy.Rational(1, 11)


@pytest.mark.parametrize(
    "fields",
    [
        {"max_length": 0},
        {"max_depth": -1},
        {"max_depth": 65},
        {"max_nodes": 1.5},
        {"max_exponent": True},
        {"max_number_digits": 5_000},
        {"max_result_digits": 10_000},
    ],
)
def test_invalid_limits(fields):
    with pytest.raises(ValueError):
        ParseLimits(**fields)


def test_deepest_nesting_leaves_room_on_the_stack(ns):
    """At the deepest nesting allowed, parsing works even from 400 frames down."""

    def nested(frames: int, text: str):
        if frames:
            return nested(frames - 1, text)
        return parse_expression(text, ns)

    texts = [
        "sin(" * 64 + "x" + ")" * 64,
        "V(" * 64 + "x" + ")" * 64,
        "atan2(x," * 64 + "x" + ")" * 64,
        "(" * 64 + "x" + ")" * 64,
        "-" * 64 + "x",
        "x" + "^x" * 64,
        "{" * 64 + "x" + "}" * 64,
        r"\sin" * 64 + " x",
        "-(" * 32 + "x" + ")" * 32,
    ]
    for text in texts:
        assert isinstance(nested(400, text), sympy.Expr)


def test_a_20k_term_sum_hits_the_node_limit_quickly(ns):
    text = "+".join(["x"] * 20_000)
    result = parsed(text, ns, ParseLimits(max_length=100_000))
    assert isinstance(result, ParseError)
    assert result.message == "expression too large (more than 20000 tokens)"


def test_default_limits():
    from lagrangian.parsing import DEFAULT_LIMITS

    expected = ParseLimits(
        max_length=20_000,
        max_depth=64,
        max_nodes=20_000,
        max_exponent=1_000,
        max_number_digits=100,
        max_result_digits=4_000,  # Python cannot print integers of more than 4,300 digits
    )
    assert expected == DEFAULT_LIMITS


def test_results_can_be_printed(ns):
    """The largest numbers allowed still print (Python refuses ints over 4,300 digits)."""
    for text in ("(9**999)**4", "1/(9**999)**4", "10**999*10**999*10**999*10**999", "2**(x+13000)"):
        try:
            result = parse_expression(text, ns)
        except ParseError:
            continue
        assert str(result)

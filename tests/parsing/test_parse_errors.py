"""Every error is a ParseError with a short message and the 0-based position."""

from __future__ import annotations

import pytest

from lagrangian.errors import LagrangianError, ParseError, UnknownNameError


@pytest.mark.parametrize(
    ("text", "message", "position"),
    [
        ("", "empty expression", 0),
        ("   ", "empty expression", 0),
        ("x[0]", "unexpected character '['", 1),
        ("x.y", "unexpected character '.'", 1),
        ("x = 1", "unexpected character '='", 2),
        ("x < 1", "unexpected character '<'", 2),
        ("x; y", "unexpected character ';'", 1),
        ("x @ y", "unexpected character '@'", 2),
        ("lambda: 0", "unexpected character ':'", 6),
        ('"abc"', "unexpected character '\"'", 0),
        ("'abc'", 'unexpected character "\'"', 0),
        ("x % 2", "unexpected character '%'", 2),
        ("x\x00", "unexpected character U+0000", 1),
        ("x}", "unexpected character '}'", 1),
        ("sin(x", "expected ')' to close '(' at position 4, found end of expression", 5),
        ("(x + (y)", "expected ')' to close '(' at position 1, found end of expression", 8),
        ("x +", "unexpected end of expression", 3),
        ("x * ", "unexpected end of expression", 4),
        ("*x", "unexpected '*'", 0),
        ("x + * y", "unexpected '*'", 4),
        ("()", "unexpected ')'", 1),
        ("x)", "unmatched ')'", 1),
        ("x, y", "unexpected ','", 1),
        ("f(x,)", "unexpected ')'", 4),
        ("2x", "implicit multiplication is not allowed: write '2*x'", 1),
        ("2 x", "implicit multiplication is not allowed: write '2*x'", 2),
        ("x y", "implicit multiplication is not allowed: write 'x*y'", 2),
        ("(x)(y)", "implicit multiplication is not allowed: write ')*('", 3),
        ("2(x)", "'2' is not a function: write '2*(...)' to multiply", 0),
        ("m(x)", "'m' is not a function", 0),
        ("foo(x)", "unknown function 'foo'", 0),
        ("pi(x)", "'pi' is not a function", 0),
        ("sin", "'sin' is a function: write sin(...)", 0),
        ("sin + 1", "'sin' is a function: write sin(...)", 0),
        ("sin(x, y)", "sin() takes 1 argument (2 given)", 0),
        ("sin()", "sin() takes 1 argument (0 given)", 0),
        ("atan2(x)", "atan2() takes 2 arguments (1 given)", 0),
        ("A(x, y)", "A() takes 3 arguments (2 given)", 0),
        ("1 + V(x, y)", "V() takes 1 argument (2 given)", 4),
        ("_x", "invalid name '_x': names may not start with '_'", 0),
        ("__import__", "invalid name '__import__': names may not start with '_'", 0),
        ("a__b", "invalid name 'a__b': names may not contain '__'", 0),
        ("1/0", "division by zero", 1),
        ("x/(x - x)", "division by zero", 1),
        ("0**-1", "division by zero", 1),
        ("0^(-1/2)", "division by zero", 1),
        ("log(0)", "log(0) is infinite or undefined", 0),
        ("tan(pi/2)", "tan(pi/2) is infinite or undefined", 0),
        ("atan2(0, 0)", "atan2(0, 0) is infinite or undefined", 0),
        ("x**5000", "exponent 5000 too large (limit 1000)", 1),
        ("x**-1001", "exponent -1001 too large (limit 1000)", 1),
        ("1" * 150, "number with 150 digits too long (limit 100)", 0),
        ("1e401", "exponent 401 too large (limit 400)", 0),
        ("2.5e-999", "exponent -999 too large (limit 400)", 0),
        ("9**9**9**9", "exponent 387420489 too large (limit 1000)", 4),
        ("10**10**10", "exponent 10000000000 too large (limit 1000)", 2),
        ("(10**999)**999", "number too large (about 998002 digits, limit 4000)", 9),
        ("θ\u0307\u0307\u0307", "too many dots over 'theta' (at most 2)", 0),
        ("x²²y", "implicit multiplication is not allowed: write '²²*y'", 3),
    ],
)
def test_messages_and_positions(parse_error, text, message, position):
    error = parse_error(text)
    assert error.message == message
    assert error.position == position
    assert error.text == text
    assert str(error) == f"{message} at position {position + 1}"


def test_unknown_name_is_an_unknown_name_error(ns):
    from lagrangian.parsing import parse_expression

    with pytest.raises(UnknownNameError) as caught:
        parse_expression("x + 2*zeta", ns)
    assert caught.value.name == "zeta"
    assert caught.value.position == 6
    assert str(caught.value) == "unknown symbol 'zeta' at position 7"


def test_too_long_has_no_position(parse_error):
    error = parse_error("x" * 25_000)
    assert error.message == "expression too long (25000 characters, limit 20000)"
    assert error.position is None


def test_too_deep(parse_error):
    error = parse_error("(" * 100 + "x" + ")" * 100)
    assert error.message == "expression nested too deeply (limit 64)"
    assert error.position == 64


def test_errors_are_lagrangian_errors(parse_error):
    assert isinstance(parse_error("x +"), LagrangianError)


def test_a_long_name_is_shortened_in_messages(parse_error):
    error = parse_error("_" + "a" * 500)
    assert len(error.message) < 120


def test_non_text_is_a_type_error(ns):
    from lagrangian.parsing import parse_expression

    with pytest.raises(TypeError):
        parse_expression(3, ns)  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        parse_expression("x", {"x": 1})  # type: ignore[arg-type]


def test_the_first_problem_is_reported(parse_error):
    # an unknown function is named before the unknown names in its arguments
    assert parse_error("foo(bar)").message == "unknown function 'foo'"
    # a lexical error anywhere wins over a syntax error before it
    assert parse_error("x + + [").message == "unexpected character '['"


def test_parse_error_is_not_swallowed_into_other_types(parse_error):
    assert type(parse_error("x +")) is ParseError

"""Plain text: what parses to what (compared with SymPy objects built here)."""

from __future__ import annotations

import pytest
import sympy
from parsing_fixtures import A, S, V

x, y, z, t, m, g, l, k = (S[name] for name in ["x", "y", "z", "t", "m", "g", "l", "k"])
theta, theta_dot = S["theta"], S["theta_dot"]


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("x", x),
        ("42", sympy.Integer(42)),
        ("x + y", x + y),
        ("x - y - z", x - y - z),
        ("x * y / z", x * y / z),
        ("x / y / z", x / (y * z)),
        ("x / y * z", x * z / y),
        ("x + y * z", x + y * z),
        ("(x + y) * z", (x + y) * z),
        ("x ** 2", x**2),
        ("x ^ 2", x**2),
        ("-x**2", -(x**2)),
        ("-x^2", -(x**2)),
        ("(-x)**2", x**2),
        ("2**-x", 2 ** (-x)),
        ("x**-2", x**-2),
        ("x^y^z", x ** (y**z)),
        ("x**y**z", x ** (y**z)),
        ("(x^y)^z", (x**y) ** z),
        ("--x", x),
        ("+x", x),
        ("-+-x", x),
        ("x - -y", x + y),
        ("2*x**2*y", 2 * x**2 * y),
        ("m*g*l*(1 - cos(theta))", m * g * l * (1 - sympy.cos(theta))),
        ("t", t),
        ("pi", sympy.pi),
        ("E", sympy.E),
        ("E**x", sympy.exp(x)),
        ("2*pi", 2 * sympy.pi),
    ],
)
def test_expressions(parse, text, expected):
    assert parse(text) == expected


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("0.5", sympy.Rational(1, 2)),
        (".5", sympy.Rational(1, 2)),
        ("0.1", sympy.Rational(1, 10)),
        ("2.", sympy.Integer(2)),
        ("1e-3", sympy.Rational(1, 1000)),
        ("2.5E+2", sympy.Integer(250)),
        ("2.5e2", sympy.Integer(250)),
        ("1E5", sympy.Integer(100000)),
        ("1.25e-1", sympy.Rational(1, 8)),
        ("007", sympy.Integer(7)),
        ("1e400", sympy.Integer(10) ** 400),
        ("9.81", sympy.Rational(981, 100)),
    ],
)
def test_numbers_are_exact(parse, text, expected):
    value = parse(text)
    assert value == expected
    assert isinstance(value, sympy.Rational)


def test_integers_are_integers(parse):
    assert isinstance(parse("12"), sympy.Integer)


def test_decimal_arithmetic_stays_exact(parse):
    assert parse("0.1 + 0.2") == sympy.Rational(3, 10)
    assert parse("x/2 + 0.5*x") == x


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("sin(x)", sympy.sin(x)),
        ("cos(x)", sympy.cos(x)),
        ("tan(x)", sympy.tan(x)),
        ("cot(x)", sympy.cot(x)),
        ("sec(x)", sympy.sec(x)),
        ("csc(x)", sympy.csc(x)),
        ("asin(x)", sympy.asin(x)),
        ("acos(x)", sympy.acos(x)),
        ("atan(x)", sympy.atan(x)),
        ("atan2(y, x)", sympy.atan2(y, x)),
        ("sinh(x)", sympy.sinh(x)),
        ("cosh(x)", sympy.cosh(x)),
        ("tanh(x)", sympy.tanh(x)),
        ("exp(x)", sympy.exp(x)),
        ("log(x)", sympy.log(x)),
        ("sqrt(x)", sympy.sqrt(x)),
        ("Abs(x)", sympy.Abs(x)),
        ("sign(x)", sympy.sign(x)),
        ("sin(x)**2 + cos(x)**2", sympy.sin(x) ** 2 + sympy.cos(x) ** 2),
        ("sin(pi/6)", sympy.Rational(1, 2)),
        ("sqrt(8)", 2 * sympy.sqrt(2)),
        ("exp(log(x))", x),
        ("sin(cos(x + y))", sympy.sin(sympy.cos(x + y))),
    ],
)
def test_builtin_functions(parse, text, expected):
    assert parse(text) == expected


def test_builtin_tables_are_exactly_the_documented_ones():
    from lagrangian.parsing import BUILTIN_CONSTANTS, BUILTIN_FUNCTIONS

    assert set(BUILTIN_FUNCTIONS) == set(
        [
            "sin",
            "cos",
            "tan",
            "cot",
            "sec",
            "csc",
            "asin",
            "acos",
            "atan",
            "atan2",
            "sinh",
            "cosh",
            "tanh",
            "exp",
            "log",
            "sqrt",
            "Abs",
            "sign",
        ]
    )
    assert {name: arity for name, (_, arity) in BUILTIN_FUNCTIONS.items() if arity != 1} == {
        "atan2": 2
    }
    assert dict(BUILTIN_CONSTANTS) == {"pi": sympy.pi, "E": sympy.E}


def test_declared_function_bare_means_its_declared_arguments(parse):
    assert parse("A") == A(x, y, z)
    assert parse("V") == V(x)
    assert parse("2*A + 1") == 2 * A(x, y, z) + 1


def test_declared_function_called_with_any_expressions(parse):
    assert parse("A(x, y - z, t)") == A(x, y - z, t)
    assert parse("V(sin(x)**2)") == V(sympy.sin(x) ** 2)
    assert parse("A(V(y), 0.5, A)") == A(V(y), sympy.Rational(1, 2), A(x, y, z))


def test_whitespace_is_free(parse):
    assert parse(" \t x\n+\r\ny ") == x + y
    assert parse("sin (x)") == sympy.sin(x)


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("θ", S["theta"]),
        ("\u03b8\u0307", S["theta_dot"]),  # θ with a combining dot above
        ("\u03b8\u0308", S["theta_ddot"]),  # θ with a combining diaeresis
        ("\u1e8b", S["x_dot"]),  # precomposed x with dot above
        ("\u1e8d", S["x_ddot"]),  # precomposed x with diaeresis
        ("x\u0307", S["x_dot"]),
        ("θ₁", S["theta1"]),
        ("\u03b8\u0307\u2081", S["theta1_dot"]),
        ("x²", x**2),
        ("\u03b8\u0307\u00b2", theta_dot**2),
        ("x³ + x²", x**3 + x**2),
        ("x⁻¹", 1 / x),
        ("2·x", 2 * x),
        ("2⋅x", 2 * x),
        ("2×x", 2 * x),
        ("x − y", x - y),
        ("x ÷ y", x / y),
        ("ω*μ*λ*φ", S["omega"] * S["mu"] * S["lambda"] * S["phi"]),
        ("Θ", S["Theta"]),
        ("π", sympy.pi),
        ("m·g·l·(1 − cos(θ))", m * g * l * (1 - sympy.cos(theta))),
    ],
)
def test_unicode(parse, text, expected):
    assert parse(text) == expected


def test_names_with_digits_and_underscores(parse):
    assert parse("theta1_dot") == S["theta1_dot"]
    assert parse("l_ab") == S["l_ab"]
    assert parse("m1*m2") == S["m1"] * S["m2"]


def test_symbols_come_from_the_namespace_not_by_name(parse):
    # the namespace decides the object (here: real symbols), never Symbol(text)
    assert parse("x").is_real is True
    assert parse("x") is S["x"]


def test_result_is_an_expression(parse):
    for text in ("1", "x", "A", "sin(x)", "pi"):
        assert isinstance(parse(text), sympy.Expr)

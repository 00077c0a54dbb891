r"""LaTeX input: textbook forms map to the same objects as plain text."""

from __future__ import annotations

import pytest
import sympy
from parsing_fixtures import A, S, V

x, y, z, m, g, l, k = (S[name] for name in ["x", "y", "z", "m", "g", "l", "k"])
theta, phi, theta_dot = S["theta"], S["phi"], S["theta_dot"]


def test_pendulum_lagrangian_matches_plain_text(parse):
    latex = r"\frac{1}{2} m l^{2} \dot{\theta}^{2} + m g l \cos\theta"
    plain = "m*l**2*theta_dot**2/2 + m*g*l*cos(theta)"
    assert parse(latex) == parse(plain)


@pytest.mark.parametrize(
    ("latex", "plain"),
    [
        (r"\frac{1}{2} k x^2", "k*x**2/2"),
        (
            r"\frac{m}{2}\left(\dot{x}^2 + l^2\dot\theta^2\right)",
            "m/2*(x_dot**2 + l**2*theta_dot**2)",
        ),
        (r"\frac{1}{2} m_1 l_1^2 \dot{\theta}_1^2", "m1*l1**2*theta1_dot**2/2"),
        (r"m_{1} m_{2}", "m1*m2"),
        (r"-m g l \cos{\theta}", "-m*g*l*cos(theta)"),
        (r"\cos(\theta_1 - \theta_2)", "cos(theta1 - theta2)"),
        (r"x \cdot y \times z", "x*y*z"),
        (r"x \div y", "x/y"),
        (r"2x\,", "2*x"),
        (r"2 x y \pi", "2*x*y*pi"),
        (r"x^{2}", "x**2"),
        (r"x^{y+1}", "x**(y+1)"),
        (r"x^-1", "1/x"),
        (r"x^{-1}", "1/x"),
        (r"x**2 + \pi", "x**2 + pi"),
        (r"[x + y]^{2}", "(x + y)**2"),
        # a name before a group multiplies it: the exponent is the group's, not the product's
        (r"\frac{1}{2} k (x - l)^2", "k*(x - l)**2/2"),
        (r"k \left(x - l\right)^{2}", "k*(x - l)**2"),
        (r"\left[ x + y \right] z", "(x + y)*z"),
        (r"{x + y} z", "(x + y)*z"),
        (r"m(x + y)\,", "m*(x + y)"),
        (r"\pi(x + y)", "pi*(x + y)"),
        (r"\frac{1}{x}", "1/x"),
        (r"\frac{x+y}{\sqrt{x}}", "(x+y)/sqrt(x)"),
        (r"\dfrac{x}{y} + \tfrac{1}{3}", "x/y + 1/3"),
        (r"\frac x y", "x/y"),
        (r"\frac\theta2", "theta/2"),
        (r"x \, y \; z \! \quad k \qquad m \: g \ l", "x*y*z*k*m*g*l"),
        (r"\displaystyle \frac{1}{2}", "1/2"),
        (r"0.5\,x", "x/2"),
    ],
)
def test_latex_equals_plain(parse, latex, plain):
    assert parse(latex) == parse(plain)


@pytest.mark.parametrize(
    ("latex", "expected"),
    [
        (r"\sin\theta", sympy.sin(theta)),
        (r"\sin{\theta}", sympy.sin(theta)),
        (r"\sin(\theta)", sympy.sin(theta)),
        (r"\sin \theta", sympy.sin(theta)),
        (r"\sin x", sympy.sin(x)),
        (r"\sin^2\theta", sympy.sin(theta) ** 2),
        (r"\sin^{2}(\theta)", sympy.sin(theta) ** 2),
        (r"\sin^2(x + y)", sympy.sin(x + y) ** 2),
        (r"\sin\theta^2", sympy.sin(theta**2)),
        (r"\sin\theta\cos\phi", sympy.sin(theta) * sympy.cos(phi)),
        (r"\cos\theta \dot\theta", sympy.cos(theta) * theta_dot),
        (r"\sin -x", sympy.sin(-x)),
        (r"\sin\left(x\right)", sympy.sin(x)),
        (r"\tan x + \cot x", sympy.tan(x) + sympy.cot(x)),
        (r"\sec x \csc x", sympy.sec(x) * sympy.csc(x)),
        (r"\arcsin x + \arccos x + \arctan x", sympy.asin(x) + sympy.acos(x) + sympy.atan(x)),
        (r"\sinh x + \cosh x + \tanh x", sympy.sinh(x) + sympy.cosh(x) + sympy.tanh(x)),
        (r"\exp(x)", sympy.exp(x)),
        (r"\exp{-x}", sympy.exp(-x)),
        (r"\ln x", sympy.log(x)),
        (r"\log(x)", sympy.log(x)),
        (r"\sqrt{x}", sympy.sqrt(x)),
        (r"\sqrt x", sympy.sqrt(x)),
        (r"\sqrt{x^2 + y^2}", sympy.sqrt(x**2 + y**2)),
        (r"\sqrt[3]{x}", x ** sympy.Rational(1, 3)),
        (r"\sqrt[y]{x}", x ** (1 / y)),
        (r"\sqrt{8}", 2 * sympy.sqrt(2)),
        (r"\pi", sympy.pi),
        (r"sin(x)", sympy.sin(x)),  # plain calls work inside LaTeX too
        (r"atan2(y, x) + \sin x", sympy.atan2(y, x) + sympy.sin(x)),
    ],
)
def test_functions(parse, latex, expected):
    assert parse(latex) == expected


@pytest.mark.parametrize(
    ("latex", "name"),
    [
        (r"\theta", "theta"),
        (r"\phi", "phi"),
        (r"\omega", "omega"),
        (r"\mu", "mu"),
        (r"\lambda", "lambda"),
        (r"\varphi", "varphi"),
        (r"\Theta", "Theta"),
        (r"\dot{\theta}", "theta_dot"),
        (r"\dot\theta", "theta_dot"),
        (r"\dot \theta", "theta_dot"),
        (r"\dot{x}", "x_dot"),
        (r"\dot x", "x_dot"),
        (r"\ddot{x}", "x_ddot"),
        (r"\ddot{\theta}", "theta_ddot"),
        (r"\dot{\phi}", "phi_dot"),
        (r"\theta_1", "theta1"),
        (r"\theta_{1}", "theta1"),
        (r"\theta_{ 1 }", "theta1"),
        (r"m_{1}", "m1"),
        (r"{m_1}", "m1"),
        (r"l_{ab}", "l_ab"),
        (r"x_dot", "x_dot"),
        (r"theta_dot", "theta_dot"),
        (r"\dot{\theta}_1", "theta1_dot"),
        (r"\dot{\theta_1}", "theta1_dot"),
        (r"\dot{\theta}_{1}", "theta1_dot"),
        (r"\left(\dot{\theta}_1\right)", "theta1_dot"),
        (r"\dot{\theta_{2}}", "theta2_dot"),
        ("{θ}", "theta"),
        (r"\dot{θ}", "theta_dot"),
    ],
)
def test_names(parse, latex, name):
    assert parse(latex) == S[name]


def test_declared_functions(parse):
    assert parse(r"\frac{1}{2} A") == A(x, y, z) / 2
    assert parse(r"V(\theta)") == V(theta)
    assert parse(r"A(x, y, \dot{x})") == A(x, y, S["x_dot"])


def test_a_letter_run_is_one_name(ns):
    from lagrangian.errors import UnknownNameError
    from lagrangian.parsing import parse_expression

    with pytest.raises(UnknownNameError) as caught:
        parse_expression(r"\frac{1}{2} ml^2", ns)
    assert caught.value.name == "ml"
    assert parse_expression(r"\frac{1}{2} m l^2", ns) == m * l**2 / 2


@pytest.mark.parametrize(
    ("latex", "message", "position"),
    [
        (r"\input{x}", "unknown LaTeX command '\\input'", 0),
        (r"\def\x{1}", "unknown LaTeX command '\\def'", 0),
        (r"x + \foo", "unknown LaTeX command '\\foo'", 4),
        (r"x + \\", "unknown LaTeX command '\\\\'", 4),
        ("x + \\", "expected a command after '\\'", 4),
        (r"\frac{1}{2", "expected '}' to close '{' at position 9, found end of expression", 10),
        (r"\frac{1}", "unexpected end of expression", 8),
        (r"\frac12", "ambiguous argument '12' of '\\frac': use braces, as in \\frac{1}{2}", 5),
        (r"\sin 2x", "ambiguous argument of '\\sin': use parentheses, as in \\sin(2 x)", 5),
        (
            r"\sin^{-1} x",
            "'\\sin^{-1}' is ambiguous: write the inverse function or (\\sin x)^{-1}",
            4,
        ),
        (r"{x 2}", "write '\\cdot' before the number '2', or put the number first", 3),
        (r"x^2^{3}", "double superscript: use braces, as in x^{a^b}", 3),
        (r"\left( x \right]", "expected ')' to close '\\left(' at position 1, found '\\right]'", 9),
        (r"\left\{ x \right\}", "expected one of ( ) [ ] after '\\left'", 5),
        (r"\dot{\sin}", "cannot put '\\dot' over '\\sin'", 5),
        (r"\dot{x y}", "expected '}' to close '\\dot{'", 7),
        (r"\dot 2", "expected a name after '\\dot'", 5),
        (r"x_{}", "empty subscript", 1),
        (r"\pi x_", "expected a subscript after '_'", 5),
        (r"x_{1", "expected '}' to close the subscript", 4),
        (r"x_{+}", "unexpected '+' in a subscript", 3),
        (r"\pi(x + y)_1", "unexpected character '_'", 10),
        (r"{x", "expected '}' to close '{' at position 1, found end of expression", 2),
        (r"\pi x}", "unmatched '}'", 5),
        (r"\frac{1}{0}", "division by zero", 8),
        (r"\_x", "unknown LaTeX command '\\_'", 0),
        (r"\dot{\dot{x}}", "cannot put '\\dot' over '\\dot'", 5),
        ("\\sin \\theta $", "unexpected character '$'", 12),
    ],
)
def test_errors(parse_error, latex, message, position):
    error = parse_error(latex)
    assert error.message == message
    assert error.position == position


def test_braces_alone_switch_to_latex(parse):
    assert parse("2{x}") == 2 * x  # juxtaposition is LaTeX's


def test_sqrt_index_zero_is_division_by_zero(parse_error):
    assert parse_error(r"\sqrt[0]{x}").message == "division by zero"


def test_latex_is_recognised_by_a_backslash_or_a_brace(parse_error):
    from lagrangian.parsing.latex import looks_like_latex

    assert looks_like_latex(r"\theta")
    assert looks_like_latex("x^{2}")
    assert not looks_like_latex("x^2 + 2*y")
    # without either, juxtaposition is plain text's error
    assert parse_error("2 x").message.startswith("implicit multiplication is not allowed")


def test_unicode_inside_latex(parse):
    assert parse(r"\frac{1}{2} m \dot{θ}²") == parse("m*theta_dot**2/2")
    assert parse(r"θ_1 \cdot x") == parse("theta1*x")

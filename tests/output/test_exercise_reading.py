r"""The exercise page's reader (page_assets/tokens.js and exerciseParse in expressions.js)
against the project's parser (lagrangian.parsing) in Chromium: each text, LaTeX, Unicode or
plain, has the same value at a point, and each text the parser refuses is refused in its
words at the same position. The scripts run in a blank page, as the exercise page runs them.
"""

from __future__ import annotations

import math
import random
from importlib import resources

import pytest
import sympy

from lagrangian.errors import ParseError
from lagrangian.parsing import Namespace, parse_expression

pytestmark = pytest.mark.slow

NAMES = [
    "x", "y", "z", "m", "g", "l", "k", "a", "theta", "phi", "omega", "mu", "lambda", "varphi",
    "Theta", "theta_dot", "theta_ddot", "x_dot", "x_ddot", "theta1", "theta2", "theta1_dot",
    "theta2_dot", "theta2_ddot", "m1", "m2", "l1", "l_ab", "r", "r_dot",
]  # fmt: skip

#: Texts read alike, many of them tests/parsing's (LaTeX, then Unicode and plain text).
SAME = [
    r"\frac{1}{2} m l^{2} \dot{\theta}^{2} + m g l \cos\theta",
    r"\frac{m}{2}\left(\dot{x}^2 + l^2\dot\theta^2\right)",
    r"\frac{1}{2} m_1 l_1^2 \dot{\theta}_1^2 + m_{1} m_{2}",
    r"-m g l \cos{\theta} + \cos(\theta_1 - \theta_2)",
    r"x \cdot y \times z - x \div y + 2x\, + 2 x y \pi",
    r"x^{y+1} + x^-1 + x^{-1} + x**2 + [x + y]^{2}",
    r"\frac{1}{2} k (x - l)^2",  # commit c226dad: k*(x - l)^2, not (k*(x - l))^2
    r"k \left(x - l\right)^{2} + \left[ x + y \right] z + {x + y} z",
    r"m(x + y)\, + \pi(x + y) + k(x - a)^3 + m (x)",
    r"\frac{x+y}{\sqrt{x}} + \dfrac{x}{y} + \tfrac{1}{3} + \frac x y + \frac\theta2",
    r"x \, y \; z \! \quad k \qquad m \: g \ l + \displaystyle \frac{1}{2} + 0.5\,x",
    r"\sin\theta + \sin{\theta} + \sin(\theta) + \sin \theta + \sin x",
    r"\sin^2\theta + \sin^{2}(\theta) + \sin^2(x + y) + \sin\theta^2",
    r"\sin\theta\cos\phi + \cos\theta \dot\theta + \sin -x + \sin\left(x\right)",
    r"\tan x + \cot x + \sec x \csc x + \arcsin x + \arccos x + \arctan x",
    r"\sinh x + \cosh x + \tanh x + \exp(x) + \exp{-x} + \ln x + \log(x)",
    r"\sqrt{x} + \sqrt x + \sqrt{x^2 + y^2} + \sqrt[3]{x} + \sqrt[y]{x} + \sqrt{8}",
    r"sin(x) + atan2(y, x) + \sin x + \pi + E",
    r"\theta \phi \omega \mu \lambda \varphi \Theta + \ell",
    r"\dot{x} + \dot x + \ddot{x} + \ddot{\theta} + \dot \theta",
    r"\theta_1 + \theta_{1} + \theta_{ 1 } + {m_1} + l_{ab} + x_dot + theta_dot",
    r"\dot{\theta}_1 + \dot{\theta_1} + \dot{\theta}_{1} + \left(\dot{\theta}_1\right)",
    r"\dot{\theta_{2}} + {θ} + \dot{θ} + \ddot\theta_2",
    "2{x}",
    "θ̇ + ẍ + θ₁ + ϑ + µ + ω·θ + m₁·m₂ + θ̇₁ + θ̈₂",
    "x² + x⁻¹ + 2·x × y − x ÷ y + x⋅y + (x + y)²",
    "m*l**2*theta_dot**2/2 + m*g*l*cos(theta) - 2^-x + x^y^z + -x^2",
    "1.5e-3*x + .5*y + 2.*z + 3E2",
]

#: Texts the parser refuses (every name known, so that the first problem is the same one).
REFUSED = [
    r"\input{x}", r"x + \foo", r"x + \\", "x + \\", r"\frac{1}{2", r"\frac{1}", r"\frac12",
    r"\sin 2x", r"\sin^{-1} x", r"\sin^-1 x", r"{x 2}", r"x^2^{3}", r"\left( x \right]",
    r"\left\{ x \right\}", r"\dot{\sin}", r"\dot{x y}", r"\dot 2", r"x_{}", r"\pi x_",
    r"x_{1", r"x_{+}", r"\pi(x + y)_1", r"{x", r"\pi x}", r"\_x", r"\dot{\dot{x}}",
    "\\sin \\theta $", "\\x\u0001", r"\frac{1}{2} x \sqrt 12", r"\sin(x, y)", r"x(y, z)",
    r"\sqrt[3 x", "x y", "2(x)", "x(y)", "sin x", "foo(x)", "x__y", "_x", "θ̈̇", "x⃛",
    "x + ", "", "(x))", "x ** * y", "x⁻", "sin(x, y)", "x\u2028y", "x = y",
]  # fmt: skip


#: The page's scripts that read an answer, in the page's order (output/page.py).
SCRIPTS = ("tokens.js", "expressions.js")


#: Unknown names, with the parser's guess of the one meant (parsing/suggest.py) or none.
MISSPELT = [
    "xdot", "thetadot", "dx", "d_x", "x_dd", "ddtheta", "THETAdot", "theta_dott", "thetta",
    "thtea", "omegaa", "omga", "lamda", r"\dot{y}", "theta3", "Omega", "q", "sinn(x)",
    "cso(x)", "foo(x)", "m(x, y)", "atan3(x, y)", "theta1_dddot",
]  # fmt: skip


@pytest.fixture(scope="module")
def reader(browser):
    page = browser.new_page()
    page.set_content("<html><body></body></html>")
    assets = resources.files("lagrangian.output").joinpath("page_assets")
    scripts = [assets.joinpath(name).read_text("utf-8") for name in SCRIPTS]
    page.add_script_tag(content="\n".join(scripts))
    yield page
    page.close()


def python_value(text: str, point: dict[str, float]) -> float:
    symbols = {name: sympy.Symbol(name, positive=True) for name in NAMES}
    expression = parse_expression(text, Namespace(symbols))
    return float(expression.subs({symbols[n]: v for n, v in point.items()}).evalf(30))


@pytest.mark.parametrize("text", SAME)
def test_the_page_reads_a_text_as_the_parser_does(reader, text):
    point = {name: random.Random(f"{name}").uniform(0.3, 0.9) for name in NAMES}
    found = reader.evaluate(
        "([t, names, env]) => exerciseValue(exerciseParse(t, new Set(names)), env)",
        [text, NAMES, point],
    )
    expected = python_value(text, point)
    assert math.isclose(found, expected, rel_tol=1e-12), (found, expected)


@pytest.mark.parametrize("text", REFUSED + MISSPELT)
def test_the_page_refuses_a_text_in_the_parsers_words(reader, text):
    found = reader.evaluate(
        """([t, names]) => {
          try { exerciseParse(t, new Set(names)); return null; } catch (e) { return e.message; }
        }""",
        [text, NAMES],
    )
    with pytest.raises(ParseError) as refused:
        python_value(text, {})
    assert found == str(refused.value)

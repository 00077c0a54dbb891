r"""The exercise page reads LaTeX and Unicode as ``lagrangian check`` does (page_assets/
tokens.js and the grammar of expressions.js, after lagrangian/parsing): on held-out answers
to systems that are not examples, the page's verdict and terms at fault are check's, and a
text the parser refuses is refused by the page in the parser's words.
"""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from analysis.test_check import MODELS
from lagrangian.errors import ParseError
from lagrangian.output.exercise import STEPS
from lagrangian.output.page import page_html
from lagrangian.parsing import Namespace, parse_expression
from output.browser import open_page

pytestmark = pytest.mark.slow

#: Two carts joined by springs, x1 and x2: subscripts (x₁, \dot{x}_1) on a system that is
#: neither an example nor a model of test_check.
TWO_CARTS = """
name = "Two carts on springs"
description = "Carts m1, m2 on a track: a spring k1 from the wall to the first, k2 between them."
coordinates = ["x1", "x2"]
kinetic = "m1*x1_dot^2/2 + m2*x2_dot^2/2"
potential = "k1*x1^2/2 + k2*(x2 - x1 - a)^2/2"

[parameters]
m1 = 1.0
m2 = 2.0
k1 = 3.0
k2 = 5.0
a = 0.5

[initial]
x1 = 0.1
x2 = 0.7
"""

#: (model, step, answer, verdict): the answer written in LaTeX or with Unicode names.
CASES = [
    # k (r - l_0)^2 is k*(r - l0)^2 (commit c226dad), \left( \right), \cos\theta, \dot{r}
    ("spring_pendulum", "lagrangian",
     r"\frac{1}{2} m \left(\dot{r}^2 + r^2 \dot{\theta}^2\right) + m g r \cos\theta"
     r" - \frac{1}{2} k (r - l_0)^2", "right"),
    ("spring_pendulum", "potential", r"\tfrac{1}{2} k (r - l_0)^2 - m g r \cos\theta", "right"),
    ("spring_pendulum", "potential", r"\frac{1}{2} k (r - l_0)^2 + m g r \cos\theta", "wrong"),
    ("spring_pendulum", "kinetic", "m*(ṙ² + r²*θ̇²)/2", "right"),
    ("spring_pendulum", "kinetic", "m*(ṙ² + r²θ̇²)/2", "error"),  # plain text: no implicit product
    ("spring_pendulum", "kinetic", "m·ṙ²/2 + m·r·θ̇²/2", "wrong"),
    ("spring_pendulum", "equations",
     r"m \ddot{r} = m r \dot\theta^2 + m g \cos\theta - k (r - l_0)", "right"),
    ("spring_pendulum", "equations", "r·θ̈ + 2·ṙ·θ̇ + g·sin(θ) = 0", "equivalent"),
    # \sin^2\theta is sin(theta)^2, \omega and ω
    ("rotating_hoop", "kinetic",
     r"\frac{1}{2} m R^2 \left( \dot{\theta}^2 + \omega^2 \sin^2\theta \right)", "right"),
    ("rotating_hoop", "kinetic", r"\frac{m R^2}{2} \dot\theta^2", "wrong"),
    ("rotating_hoop", "lagrangian",
     "m·R²·(θ̇² + ω²·sin(θ)²)/2 + m·g·R·cos(θ) + 7", "equivalent"),
    ("rotating_hoop", "equations",
     r"R \ddot\theta = R \omega^2 \sin\theta \cos\theta - g \sin(\theta)", "right"),
    ("rotating_hoop", "equations",
     r"R \ddot\theta = R \omega^2 \sin\theta - g \sin\theta", "wrong"),
    ("atwood", "lagrangian", r"\frac{(m_1 + m_2) \dot{x}^2}{2} + (m_1 - m_2) g x", "right"),
    ("atwood", "potential", r"(m_2 - m_1) g x \cdot 3", "wrong"),
    ("two_carts", "kinetic", "m₁·ẋ₁²/2 + m₂·ẋ₂²/2", "right"),
    ("two_carts", "kinetic", "m₁ẋ₁²/2 + m₂ẋ₂²/2", "error"),  # one name, m1x1_dot
    ("two_carts", "kinetic", "m₁·ẋ₁²/2 + m₂·ẋ₂²", "wrong"),
    ("two_carts", "potential",
     r"\frac{1}{2} k_1 x_1^2 + \frac{1}{2} k_2 (x_2 - x_1 - a)^2", "right"),
    ("two_carts", "potential", r"\frac{1}{2} k_1 x_1^2 + \frac{1}{2} k_2 (x_2 - x_1)^2", "wrong"),
    ("two_carts", "lagrangian",
     r"\frac{1}{2} m_{1} \dot{x}_1^2 + \frac{1}{2} m_2 \dot{x_2}^2 - \frac{1}{2} k_1 x_1^2"
     r" - \frac{1}{2} k_2 \left[x_2 - x_1 - a\right]^2", "right"),
    ("two_carts", "equations",
     r"m_1 \ddot{x}_1 = -k_1 x_1 + k_2 \left(x_2 - x_1 - a\right)", "right"),
    # each side is read alone: one with no backslash or brace is plain text, as in check
    ("two_carts", "equations", r"m_1 \ddot{x}_1 = -k_1 x_1 + k_2 (x_2 - x_1 - a)", "error"),
    ("two_carts", "equations", "m₂ẍ₂ + k₂(x₂ − x₁ − a) = 0", "error"),  # implicit in plain text
    ("two_carts", "equations", "m₂·ẍ₂ + k₂·(x₂ − x₁ − a) = 0", "right"),
    ("two_carts", "equations", r"m_2 \ddot{x}_2 + k_2 (x_2 - x_1) = 0", "wrong"),
]  # fmt: skip

#: Texts the parser refuses, each a different rule of the LaTeX and Unicode readers (every
#: name known: the page resolves names as it reads, the parser after a whole text is read,
#: so a text with two problems may be refused for another one first).
REFUSED = [
    r"\frac{1}{2} m1 \foo",
    r"\sin 2\theta",
    r"\frac{1}{2} m1 x_dot^2 3",
    r"\frac12 m1 \dot{x}^2^2",
    r"\sin^{-1} x",
    r"\sqrt 12 x",
    r"\left\{ x \right\}",
    r"m1 x_{} ",
    "m1·x⃛",
    "m1*x__dot",
    "_x*m1",
    "m1*(x",
    r"\frac{1}{2} m1 (x",
    "m1·ẍ̇̇",
]


def system_of(name: str, folder) -> lg.System:
    if name == "two_carts":
        path = folder / "two_carts.toml"
        path.write_text(TWO_CARTS, "utf-8")
        return lg.load(path)
    return lg.load(MODELS / f"{name}.toml")


@pytest.fixture(scope="module")
def pages(tmp_path_factory, browser):
    """model name -> (its system, its exercise page opened once)."""
    folder = tmp_path_factory.mktemp("exercise-latex")
    opened = {}

    def page_of(name: str):
        if name not in opened:
            system = system_of(name, folder)
            path = folder / f"{name}.html"
            path.write_text(page_html(system, exercise=STEPS), "utf-8")
            page = open_page(browser, path)
            page.page.wait_for_function("() => window.lagrangianCheck !== undefined")
            opened[name] = (system, page)
        return opened[name]

    yield page_of
    for _, page in opened.values():
        page.page.close()


def test_the_cases_cover_every_step_and_verdict():
    assert {step for _, step, _, _ in CASES} == set(STEPS)
    assert {verdict for *_, verdict in CASES} == {"right", "equivalent", "wrong", "error"}


@pytest.mark.parametrize(("name", "step", "answer", "verdict"), CASES)
def test_the_page_reads_latex_and_unicode_as_check_does(pages, name, step, answer, verdict):
    system, opened = pages(name)
    found = opened.page.evaluate("([s, t]) => window.lagrangianCheck(s, t)", [step, answer])
    if verdict == "error":  # check refuses it too, in the same words
        with pytest.raises(lg.errors.ModelError) as refused:
            system.check(**{step: [answer] if step == "equations" else answer})
        assert found["verdict"] == "error"
        assert found["reason"] in str(refused.value)
        return
    expected = system.check(**{step: [answer] if step == "equations" else answer})
    assert (found["verdict"], expected.verdict) == (verdict, verdict), found["reason"]
    if verdict == "right":
        assert found["reason"] == expected.reason
    names = dict(system.symbols)

    def read(text):  # each term's expression, to compare whatever its printing
        return None if text is None else sympy.parse_expr(text.replace("^", "**"), names)

    mine = [(t["problem"], read(t["term"]), read(t["expected"])) for t in found["terms"]]
    theirs = [(t.problem, read(t.term), read(t.expected)) for t in expected.terms]
    assert len(mine) == len(theirs) and (verdict != "wrong" or theirs)
    for problem, term, right in theirs:
        assert any(
            problem == p
            and sympy.simplify(term - t) == 0
            and (right is None if r is None else sympy.simplify(right - r) == 0)
            for p, t, r in mine
        ), (problem, term, right, mine)
    assert opened.errors == []


@pytest.mark.parametrize("text", REFUSED)
def test_a_text_the_parser_refuses_is_refused_in_its_words(pages, text):
    system, opened = pages("atwood")
    found = opened.page.evaluate("(t) => window.lagrangianCheck('kinetic', t)", text)
    namespace = Namespace({name: s for name, s in system.symbols.items()})
    with pytest.raises(ParseError) as refused:
        parse_expression(text, namespace)
    assert found == {"verdict": "error", "reason": str(refused.value), "terms": []}

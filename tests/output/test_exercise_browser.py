"""The exercise page in Chromium: its checker agrees with ``lagrangian check`` on every
held-out answer of tests/analysis/test_check.py that a page asks (T, V, L, equations, as
plain text), and a student's typing, checking and revealing works with no console error.
"""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from analysis.test_check import CASES, MODELS
from lagrangian.errors import ModelError
from lagrangian.output.exercise import NO_CONSTRAINTS, NO_FUNCTIONS, STEPS
from lagrangian.output.page import page_html
from output.browser import open_page

pytestmark = pytest.mark.slow

#: The cases a page asks: one answer of a page's step, written as plain text.
PAGE_CASES = [
    (name, step, answer[0] if step == "equations" else answer, verdict)
    for name, answers, verdict, _, _ in CASES
    for step, answer in answers.items()
    if step in STEPS and "\\" not in str(answer)
]


@pytest.fixture(scope="module")
def pages(browser, tmp_path_factory):
    """model name -> its exercise page, opened once."""
    folder = tmp_path_factory.mktemp("exercise")
    opened = {}

    def page_of(name: str):
        if name not in opened:
            path = folder / f"{name}.html"
            path.write_text(page_html(lg.load(MODELS / f"{name}.toml"), exercise=STEPS), "utf-8")
            opened[name] = open_page(browser, path)
            opened[name].page.wait_for_function("() => window.lagrangianCheck !== undefined")
        return opened[name]

    yield page_of
    for page in opened.values():
        page.page.close()


#: 2,688 terms once multiplied out (SymPy's count; the page stops past 500 too)
TOO_LARGE = "(x_dot + g)^3*(m1 + m2)^3*(x + 1)^3*(x + m1 + g + x_dot)^6"


def test_an_answer_too_large_to_compare_is_refused_in_the_same_words(pages):
    found = pages("atwood").page.evaluate(f"() => window.lagrangianCheck('kinetic', '{TOO_LARGE}')")
    assert found == {
        "verdict": "error",
        "reason": "too many terms to compare one by one (more than 500 once multiplied out)",
        "terms": [],
    }
    with pytest.raises(ModelError, match="too many terms to compare one by one"):
        lg.load(MODELS / "atwood.toml").check(kinetic=TOO_LARGE)


def test_the_cases_cover_every_step_and_verdict():
    assert {step for _, step, _, _ in PAGE_CASES} == set(STEPS)
    assert {verdict for *_, verdict in PAGE_CASES} == {"right", "equivalent", "wrong"}


@pytest.mark.parametrize(("name", "step", "answer", "verdict"), PAGE_CASES)
def test_the_page_agrees_with_check(pages, name, step, answer, verdict):
    opened = pages(name)
    found = opened.page.evaluate("([s, t]) => window.lagrangianCheck(s, t)", [step, answer])
    keyword = {"equations": "equations"}.get(step, step)
    expected = lg.load(MODELS / f"{name}.toml").check(
        **{keyword: [answer] if step == "equations" else answer}
    )
    assert found["verdict"] == expected.verdict == verdict
    if verdict == "right" or "combination" in expected.reason:
        assert found["reason"] == expected.reason
    names = dict(lg.load(MODELS / f"{name}.toml").symbols)
    if " times " in expected.reason:  # an equation times a factor: the same factor
        head, factor = expected.reason.split(" times ")
        assert found["reason"].startswith(head + " times ")
        printed = found["reason"].split(" times ")[1]
        difference = sympy.parse_expr(factor.replace("^", "**"), local_dict=names) - (
            sympy.parse_expr(printed.replace("^", "**"), local_dict=names)
        )
        assert sympy.simplify(difference) == 0

    def read(text):  # each term's expression, to compare whatever its printing
        if text is None:
            return None
        return sympy.parse_expr(text.replace("^", "**"), local_dict=names)

    mine = [(t["problem"], read(t["term"]), read(t["expected"])) for t in found["terms"]]
    theirs = [(t.problem, read(t.term), read(t.expected)) for t in expected.terms]
    assert len(mine) == len(theirs)
    for problem, term, right in theirs:  # the same terms at fault and the same right terms
        assert any(
            problem == p
            and sympy.simplify(term - t) == 0
            and (right is None if r is None else sympy.simplify(right - r) == 0)
            for p, t, r in mine
        ), (problem, term, right, mine)
    assert opened.errors == []


def test_a_student_types_checks_and_sees_the_solution(pages):
    opened = pages("atwood")
    page = opened.page
    solution = page.locator("#solution > :not(#exercise)")
    assert solution.count() > 0
    assert all(not solution.nth(k).is_visible() for k in range(solution.count()))

    def answer(field: str, text: str) -> str:
        page.fill(f"#exercise-{field}", text)
        page.locator(f"#exercise-{field}").press("Enter")
        verdict = page.locator(f"#exercise-{field} ~ .exercise-verdict")
        return verdict.get_attribute("data-verdict") + ": " + verdict.inner_text()

    assert answer("kinetic", "m1*x_dot^2/2") == (
        "wrong: Wrong: the term m1*x_dot^2/2 should be x_dot^2*(m1 + m2)/2"
    )
    assert answer("kinetic", "(m1 + m2)*x_dot^2/2") == "right: Right: right"
    assert answer("potential", "m1*g*(x") == (
        "error: Cannot read this: expected ')' to close '(' at position 6, found end of expression "
        "at position 8"  # the parser's words (lagrangian.parsing)
    )
    assert answer("potential", "(m2 - m1)*g*x + 4") == (
        "equivalent: Right, equivalently: right up to a constant, which changes no motion"
    )
    assert answer("lagrangian", "(m1 + m2)*x_dot^2/2 + (m1 - m2)*g*x") == "right: Right: right"
    assert not solution.first.is_visible()  # one step is left
    assert answer("equations-0", "x_ddot = (m1 - m2)*g/(m1 + m2)").startswith("equivalent: ")
    assert all(solution.nth(k).is_visible() for k in range(solution.count()))
    page.locator("#exercise-equations-0 ~ .exercise-show").click()
    assert page.locator("#exercise-equations-0 ~ .exercise-answer .katex").count() == 1
    assert opened.errors == []


@pytest.mark.parametrize("name", ["cartesian_pendulum", "velocity_dependent_potential"])
def test_what_a_page_cannot_ask_is_said_in_it(browser, tmp_path, name):
    path = tmp_path / f"{name}.html"
    path.write_text(page_html(lg.load(name), exercise=STEPS), "utf-8")
    opened = open_page(browser, path)
    notes = opened.page.locator(".exercise-note").all_inner_texts()
    fields = opened.page.locator("#exercise input").count()
    if name == "cartesian_pendulum":  # constrained: T, V and L asked, not the equations
        assert notes == [NO_CONSTRAINTS]
        assert fields == 3
        assert (
            opened.page.evaluate(
                "window.lagrangianCheck('kinetic', 'm*(x_dot^2 + y_dot^2)/2').verdict"
            )
            == "right"
        )
    else:  # unspecified functions: nothing asked, the solution in view
        assert notes == [NO_FUNCTIONS]
        assert fields == 0
        assert opened.page.locator("#solution > :not(#exercise)").first.is_visible()
    assert opened.errors == []
    opened.page.close()


def mutations(system: lg.System) -> list[tuple[str, str]]:
    """(step, answer) for the right T, V, L and equations of ``system`` and, of each, the
    usual slips: a factor 2 on all, a constant or a total derivative added, each term
    left out, doubled or added twice, a term that does not belong."""
    from lagrangian.analysis.check import raw_equations, right_kinetic, right_potential

    eom = system.equations_of_motion()
    q = system.coordinates[0]
    rights = [("kinetic", right_kinetic(eom)), ("potential", right_potential(eom))]
    rights += [("lagrangian", system.lagrangian)]
    rights += [("equations", sympy.expand(e)) for e in raw_equations(eom)]
    found = []
    for step, right in rights:
        terms = sympy.Add.make_args(sympy.expand(right))
        slips = [right, 2 * right, right + 5, right + sympy.cos(q.q) * q.q_dot]
        slips += [right - t for t in terms] + [right - 2 * t for t in terms]
        slips += [right + t for t in terms] + [right + q.q * q.q_dot**2]
        found += [(step, str(slip).replace("**", "^")) for slip in slips]
    return found


@pytest.mark.parametrize("name", ["cart_pole"])  # 79 answers, half a minute
def test_the_page_agrees_with_check_on_the_usual_slips(browser, tmp_path, name):
    system = lg.load(name)
    path = tmp_path / f"{name}.html"
    path.write_text(page_html(system, exercise=STEPS), "utf-8")
    opened = open_page(browser, path)
    opened.page.wait_for_function("() => window.lagrangianCheck !== undefined")
    disagreements = []
    for step, answer in mutations(system):
        found = opened.page.evaluate("([s, t]) => window.lagrangianCheck(s, t)", [step, answer])
        expected = system.check(**({step: [answer]} if step == "equations" else {step: answer}))
        if (found["verdict"], sorted(t["problem"] for t in found["terms"])) != (
            expected.verdict,
            sorted(t.problem for t in expected.terms),
        ):
            disagreements.append((step, answer, found["reason"], expected.reason))
    assert disagreements == []
    assert opened.errors == []
    opened.page.close()

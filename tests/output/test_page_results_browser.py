"""The equilibria of the page in a real browser (headless Chromium): every verdict and
ω², ω and period as numbers in view at 1400 px and at a phone's 412 px, the numbers
following the sliders (checked against ``analyze --set ... --json``), sliders that land
on the model's own values, and the plots' axes named as the model's symbols are typeset.
"""

from __future__ import annotations

import json

import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.examples import example_names
from lagrangian.output.page import page_html
from output.browser import open_page

pytestmark = pytest.mark.slow

#: Every example with two or more coordinates (the double pendulum's, the heavy top's and
#: the cart-pole's symbolic forms are the longest).
MULTI_COORDINATE = tuple(n for n in example_names() if len(lg.load(n).coordinates) >= 2)

#: Every element of the section "Equilibria and small oscillations" wider than its box
#: (scrollWidth > clientWidth, KaTeX's own inner boxes aside), and every piece of typeset
#: math or table cell that reaches past the column's right edge.
OVERFLOWING = """() => {
  const heading = [...document.querySelectorAll("#solution h2")]
    .find((h) => h.textContent.startsWith("Equilibria"));
  const section = heading.parentElement;
  const right = section.getBoundingClientRect().right;
  const wide = [];
  for (const node of section.querySelectorAll("*")) {
    if (node.closest(".katex")) continue;
    if (node.clientWidth > 0 && node.scrollWidth > node.clientWidth + 1)
      wide.push(`${node.tagName}.${node.className}: ${node.scrollWidth} > ${node.clientWidth}`);
  }
  for (const node of section.querySelectorAll(".katex-html, td, th")) {
    const box = node.getBoundingClientRect();
    if (box.right > right + 1) wide.push(`${node.tagName}.${node.className} ends at ${box.right}`);
  }
  return wide;
}"""


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("pages")
    pages: dict = {}

    def page_of(name: str):
        if name not in pages:
            pages[name] = folder / f"{name}.html"
            pages[name].write_text(page_html(lg.load(name)), encoding="utf-8")
        return pages[name]

    return page_of


@pytest.mark.parametrize("width", [1400, 412])
@pytest.mark.parametrize("name", MULTI_COORDINATE)
def test_no_element_of_the_analysis_overflows_its_column(browser, written, name, width):
    opened = open_page(browser, written(name), width=width)
    page = opened.page
    assert page.evaluate(OVERFLOWING) == []
    # every equilibrium's verdict is said in words, in view
    verdicts = page.locator(".equilibrium .verdict").all_inner_texts()
    assert all(v.split()[0] in ("stable", "unstable", "marginal") for v in verdicts)
    if name in ("double_pendulum", "heavy_top", "cart_pole"):
        assert verdicts  # (central forces, rolling: no isolated equilibrium to judge)
    assert opened.errors == []
    page.close()


def _analyzed(name: str, values: dict, capsys) -> list[dict]:
    argv = ["analyze", name, "--json"]
    for key, value in values.items():
        argv += ["--set", f"{key}={value}"]
    assert main(argv) == ExitStatus.SUCCESS
    return json.loads(capsys.readouterr().out)["equilibria"]


def test_the_numbers_follow_the_sliders_as_analyze_computes_them(browser, written, capsys):
    opened = open_page(browser, written("double_pendulum"))
    page = opened.page
    page.evaluate("() => lagrangian.pause()")
    for values in ({}, {"m2": 2, "l1": 0.5}):
        for key, value in values.items():
            page.evaluate(f"() => lagrangian.set('{key}', {value})")
        shown = page.evaluate("() => lagrangian.results()")
        expected = _analyzed("double_pendulum", values, capsys)
        assert len(shown) == len(expected) == 4
        for mine, theirs in zip(shown, expected, strict=True):
            numbers = theirs["at_parameter_values"]["omega_squared"]
            assert mine["omega_squared"] == pytest.approx(numbers, rel=1e-12)
            assert mine["verdict"] == theirs["stability"]
    # the table shows them: ω² of the lower equilibrium, its ω and period, 6 digits
    row = page.locator(".equilibrium").first.locator("tbody tr").first.locator("td")
    omega2 = expected[0]["at_parameter_values"]["omega_squared"][0]
    assert row.all_inner_texts()[1:4] == [
        f"{omega2:.6g}",
        f"{omega2**0.5:.6g}",
        f"{2 * 3.141592653589793 / omega2**0.5:.6g}",
    ]
    assert opened.errors == []
    page.close()


def test_a_verdict_that_depends_on_the_values_changes_with_them(browser, tmp_path):
    # the pendulum on a spinning hoop: the bottom is stable iff g > R ω²
    model = tmp_path / "hoop.toml"
    model.write_text(
        'name = "hoop"\ncoordinates = ["theta"]\n'
        'kinetic = "m*R^2*(theta_dot^2 + w^2*sin(theta)^2)/2"\n'
        'potential = "-m*g*R*cos(theta)"\n'
        "[parameters]\nm = 1\nR = 1\ng = 9.81\nw = 2\n[initial]\ntheta = 0.3\n",
        encoding="utf-8",
    )
    path = tmp_path / "hoop.html"
    path.write_text(page_html(lg.load(model)), encoding="utf-8")
    opened = open_page(browser, path)
    page = opened.page
    page.evaluate("() => lagrangian.pause()")
    bottom = page.locator(".equilibrium").first.locator(".verdict")
    assert bottom.inner_text() == "stable at these values"
    page.evaluate("() => lagrangian.set('w', 4)")  # R w^2 = 16 > g
    assert bottom.inner_text() == "unstable at these values"
    assert opened.errors == []
    page.close()


def test_sliders_land_on_the_models_own_values(browser, written):
    opened = open_page(browser, written("double_pendulum"))
    page = opened.page
    page.evaluate("() => lagrangian.pause()")
    for name, value in (("g", "9.81"), ("m1", "1"), ("theta2", "0.5")):
        slider = page.get_by_role("slider", name=name, exact=True)
        assert slider.evaluate("(node) => node.value") == value
        # a step up and back down lands on the value again, not beside it
        moved = slider.evaluate(
            "(node) => { node.stepUp(); node.stepDown();"
            " node.dispatchEvent(new Event('input')); return node.value; }"
        )
        assert moved == value
    assert page.evaluate("() => lagrangian.parameters.g") == 9.81
    page.close()


def test_the_phase_portrait_names_coordinates_as_typeset(browser, written):
    opened = open_page(browser, written("double_pendulum"))
    choice = opened.page.get_by_label("coordinate of the phase portrait")
    assert choice.locator("option").all_inner_texts() == ["θ₁", "θ₂"]
    opened.page.close()

"""The page of a dimensioned model says its units (issue 31): each control's label and
the readouts (t, the energy, the conserved quantities), in a real browser."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.output.page import page_html
from lagrangian.output.page_content import page_content
from output.browser import chromium, open_page

pytestmark = pytest.mark.slow

CART = """
name = "cart"
coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "k*x^2/2"
[parameters]
m = "500 g"
k = "2 N/cm"
[initial]
x = 0.1
"""


@pytest.fixture(scope="module")
def browser():
    with chromium() as browser:
        yield browser


def test_the_controls_and_readouts_carry_units(browser, tmp_path):
    path = tmp_path / "cart.toml"
    path.write_text(CART)
    system = lg.load(path)
    document = page_content(system).document
    assert document["units"] == {"t": "s", "energy": "J"}
    assert document["labels"]["k"] == r"k\ [\mathrm{N/m}]"
    assert document["labels"]["x_dot"] == r"\dot{x}\ [\mathrm{m/s}]"
    page_path = tmp_path / "cart.html"
    page_path.write_text(page_html(system), encoding="utf-8")
    opened = open_page(browser, page_path)
    page = opened.page
    page.evaluate("() => { lagrangian.pause(); lagrangian.run(1); }")
    page.wait_for_timeout(400)  # the readouts are redrawn a few times a second
    lines = page.locator(".readouts div").all_inner_texts()
    assert lines[0].startswith("t = ") and lines[0].endswith(" s")
    energy = float(lines[1].removeprefix("energy h = ").removesuffix(" J"))
    assert energy == pytest.approx(200 * 0.1**2 / 2, rel=1e-6)  # k x0^2/2, k = 200 N/m
    assert opened.errors == []
    page.close()


def test_a_model_without_units_has_no_units_on_its_page():
    document = page_content(lg.load("harmonic_oscillator")).document
    assert "units" not in document
    assert "mathrm" not in "".join(document["labels"].values())

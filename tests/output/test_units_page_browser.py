"""The page of a dimensioned model says its units (issue 31): each control's label, the
readouts (t, the energy, the conserved quantities) and the plots' axes, in a real browser."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.output.page import page_html
from lagrangian.output.page_content import page_content
from output.browser import open_page

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


def test_the_controls_and_readouts_carry_units(browser, tmp_path):
    path = tmp_path / "cart.toml"
    path.write_text(CART)
    system = lg.load(path)
    document = page_content(system).document
    assert document["units"] == {"t": "s", "energy": "J", "x": "m", "x_dot": "m/s"}
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


#: Records every text drawn on a canvas (the plots' axis labels are drawn, not in the DOM).
RECORD_CANVAS_TEXT = """() => {
  window.drawnTexts = [];
  const fillText = CanvasRenderingContext2D.prototype.fillText;
  CanvasRenderingContext2D.prototype.fillText = function (text, ...rest) {
    window.drawnTexts.push(String(text));
    return fillText.call(this, text, ...rest);
  };
}"""


def _axis_labels(browser, system, path) -> set[str]:
    path.write_text(page_html(system), encoding="utf-8")
    opened = open_page(browser, path)
    page = opened.page
    page.evaluate(RECORD_CANVAS_TEXT)
    page.evaluate("() => { lagrangian.pause(); lagrangian.run(1); }")
    page.wait_for_timeout(400)  # the plots are redrawn a few times a second
    drawn = set(page.evaluate("() => window.drawnTexts"))
    assert opened.errors == []
    page.close()
    return drawn


def test_the_plots_axes_carry_units(browser, tmp_path):
    path = tmp_path / "cart.toml"
    path.write_text(CART)
    drawn = _axis_labels(browser, lg.load(path), tmp_path / "cart.html")
    assert {"t [s]", "x [m]", "ẋ [m/s]"} <= drawn  # time series: t, x; phase: x, ẋ
    assert not {"t", "x", "ẋ"} & drawn


def test_several_coordinates_share_an_axis_unit_only_when_alike(browser, tmp_path):
    path = tmp_path / "double.toml"
    path.write_text(DOUBLE)
    drawn = _axis_labels(browser, lg.load(path), tmp_path / "double.html")
    assert {"t [s]", "θ₁ [rad]", "θ̇₁ [rad/s]", "q [rad]"} <= drawn
    path.write_text(CART_AND_PENDULUM)
    drawn = _axis_labels(browser, lg.load(path), tmp_path / "mixed.html")
    assert {"t [s]", "x [m]", "ẋ [m/s]", "q"} <= drawn and "q [m]" not in drawn


def test_a_unitless_models_plots_say_no_units(browser, tmp_path):
    drawn = _axis_labels(browser, lg.load("harmonic_oscillator"), tmp_path / "plain.html")
    assert {"t", "x", "ẋ"} <= drawn
    assert not any("[" in text for text in drawn)


DOUBLE = """
name = "double"
coordinates = ["theta1", "theta2"]
[parameters]
m = "1 kg"
l = "1 m"
g = "9.81 m/s^2"
[[particles]]
name = "a"
mass = "m"
position = ["l*sin(theta1)", "-l*cos(theta1)"]
[[particles]]
name = "b"
mass = "m"
position = ["l*sin(theta1) + l*sin(theta2)", "-l*cos(theta1) - l*cos(theta2)"]
[gravity]
g = "g"
[initial]
theta1 = 0.5
"""

CART_AND_PENDULUM = """
name = "cart and pendulum"
coordinates = ["x", "theta"]
[parameters]
m = "1 kg"
l = "1 m"
g = "9.81 m/s^2"
[[particles]]
name = "cart"
mass = "m"
position = ["x", "0"]
[[particles]]
name = "bob"
mass = "m"
position = ["x + l*sin(theta)", "-l*cos(theta)"]
[gravity]
g = "g"
[initial]
theta = 0.5
"""

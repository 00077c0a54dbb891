"""Rough edges of the page met by a new user (issue 32, item 6), each in a real browser
(headless Chromium): a conserved momentum that starts at 0 drifts in absolute terms, the
page refuses what the command line refuses with the same words, and a model typed with
no initial state says how to start it moving."""

from __future__ import annotations

import re
import subprocess
import sys

import pytest

import lagrangian as lg
from lagrangian.output.page import page_html
from output.browser import chromium, open_page

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def browser():
    with chromium() as browser:
        yield browser


def _written(tmp_path, model) -> object:
    path = tmp_path / "page.html"
    path.write_text(page_html(lg.load(model)), encoding="utf-8")
    return path


def test_a_momentum_that_starts_at_zero_shows_an_absolute_drift(browser, tmp_path):
    # the cart-pole from rest: p_x = (M + m) x' + m l cos(theta) theta' = 0 at the start
    opened = open_page(browser, _written(tmp_path, "cart_pole"))
    page = opened.page
    page.evaluate("() => { lagrangian.pause(); lagrangian.run(3); }")
    assert page.evaluate("() => lagrangian.conserved().p_x") == pytest.approx(0, abs=1e-9)
    page.wait_for_timeout(400)  # the readouts are redrawn a few times a second
    line = next(t for t in page.locator(".readouts div").all_inner_texts() if t.startswith("p_x"))
    drift = re.fullmatch(r"p_x = \S+ \(absolute drift (\S+)\)", line)
    assert drift, line
    assert abs(float(drift.group(1))) < 1e-9  # was -4.72e+284: a change divided by 1e-300
    page.close()


def test_the_page_refuses_a_negative_mass_as_the_command_line_does(browser, tmp_path):
    cli = subprocess.run(
        [sys.executable, "-m", "lagrangian", "simulate", "double_pendulum", "--set", "m1=-1"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert cli.returncode == 2
    expected = cli.stderr.strip().removeprefix("lagrangian: error: ")
    opened = open_page(browser, _written(tmp_path, "double_pendulum"))
    page = opened.page
    page.evaluate("() => lagrangian.pause()")
    thrown = page.evaluate(
        "() => { try { lagrangian.set('m1', -1); } catch (e) { return e.message; } }"
    )
    assert thrown == expected
    assert page.evaluate("() => lagrangian.parameters.m1") == 1  # kept
    field = page.get_by_label("m1 value", exact=True)
    field.fill("-1")
    field.dispatch_event("change")
    assert page.get_by_role("status").inner_text() == expected
    assert page.evaluate("() => lagrangian.parameters.m1") == 1
    assert opened.errors == []
    page.close()


def test_a_model_with_no_initial_state_says_how_to_start_it(browser, tmp_path):
    # the README's model as a new user types it: no [initial], so x = x' = 0, at rest
    model = tmp_path / "spring.toml"
    model.write_text(
        'coordinates = ["x"]\nkinetic = "m*x_dot^2/2"\npotential = "k*x^2/2"\n'
        "[parameters]\nm = 1\nk = 1\n",
        encoding="utf-8",
    )
    opened = open_page(browser, _written(tmp_path, model))
    page = opened.page
    hint = page.get_by_role("note")
    assert hint.is_visible()
    assert hint.inner_text() == (
        "At rest in an equilibrium, so nothing moves: drag a mass, or give an initial"
        " value (x or x_dot below), to start the motion."
    )
    page.evaluate("() => lagrangian.set('x', 0.5)")
    assert hint.is_hidden()
    assert page.evaluate("() => lagrangian.run(1).q.x") != 0.5  # it moves
    page.close()

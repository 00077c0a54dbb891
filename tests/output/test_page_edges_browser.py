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
from output.browser import open_page

pytestmark = pytest.mark.slow


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


#: A bead on a hoop of radius R turning at omega about the vertical (its distance from the
#: centre is constant: drawn before as a pendulum's rod from the origin).
TURNING_HOOP = """
name = "bead on a turning hoop"
coordinates = ["theta"]
[parameters]
m = 1
R = 1.5
g = 9.81
omega = 5
[[particles]]
name = "bead"
mass = "m"
position = ["R*sin(theta)*cos(omega*t)", "R*sin(theta)*sin(omega*t)", "-R*cos(theta)"]
[gravity]
g = "g"
direction = [0, 0, -1]
[initial]
theta = 0.5
"""


def test_a_bead_is_drawn_on_its_hoop_or_wire_and_a_pendulum_on_its_rod(browser, tmp_path):
    model = tmp_path / "hoop.toml"
    model.write_text(TURNING_HOOP, encoding="utf-8")
    hoop = open_page(browser, _written(tmp_path, model)).page
    hoop.evaluate("() => { lagrangian.pause(); lagrangian.run(0.7); }")
    (track,) = hoop.evaluate("() => lagrangian.tracks()")
    assert track["particle"] == "bead" and len(track["points"]) > 50
    assert [sum(x * x for x in p) ** 0.5 for p in track["points"]] == pytest.approx(
        [1.5] * len(track["points"]), abs=1e-12
    )  # the whole hoop, of radius R
    assert hoop.evaluate("() => lagrangian.rods()") == []  # not a pendulum's rod
    hoop.close()
    wire = open_page(browser, _written(tmp_path, "rotating_wire_bead")).page
    wire.evaluate("() => { lagrangian.pause(); lagrangian.run(1.3); }")
    (track,) = wire.evaluate("() => lagrangian.tracks()")
    bead = wire.evaluate("() => lagrangian.state().q.r")
    # the wire through the origin at the angle omega t = 1.3, the bead on it
    for x, y in track["points"]:
        assert x * 0.963558185417193 - y * 0.26749882862458735 == pytest.approx(0, abs=1e-9)
    middle = track["points"][len(track["points"]) // 2]
    assert middle == pytest.approx([bead * 0.26749882862458735, bead * 0.963558185417193])
    assert max(abs(x) for x, _ in track["points"]) > 2 * abs(middle[0])  # a rail, not a dot
    wire.close()
    cart = open_page(browser, _written(tmp_path, "cart_pole")).page
    (rail,) = cart.evaluate("() => lagrangian.tracks()")  # the cart's, along y = 0
    assert rail["particle"] == "cart" and {y for _, y in rail["points"]} == {0}
    assert cart.evaluate("() => lagrangian.rods()") == [["cart", "bob"]]  # the pole
    cart.close()
    pendulum = open_page(browser, _written(tmp_path, "simple_pendulum")).page
    assert pendulum.evaluate("() => lagrangian.tracks()") == []
    assert pendulum.evaluate("() => lagrangian.rods()") == [["origin", "bob"]]
    pendulum.close()


def test_the_page_refuses_a_mass_made_negative_as_the_command_line_does(browser, tmp_path):
    model = tmp_path / "block.toml"
    model.write_text(
        'name = "block"\ncoordinates = ["x"]\npotential = "k*x^2/2"\n'
        "[parameters]\nm = 2\nd = 1\nk = 1\n"
        '[[particles]]\nname = "block"\nmass = "m - d"\nposition = ["x", "0"]\n'
        "[initial]\nx = 1\n",
        encoding="utf-8",
    )
    cli = subprocess.run(
        [sys.executable, "-m", "lagrangian", "simulate", str(model), "--set", "d=3"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert cli.returncode == 2
    expected = cli.stderr.strip().removeprefix("lagrangian: error: ")
    assert expected.startswith("the mass of 'block' (particles[0].mass = -d + m) is -1")
    opened = open_page(browser, _written(tmp_path, model))
    page = opened.page
    page.evaluate("() => lagrangian.pause()")
    thrown = page.evaluate(
        "() => { try { lagrangian.set('d', 3); } catch (e) { return e.message; } }"
    )
    assert thrown == expected
    assert page.evaluate("() => lagrangian.parameters.d") == 1  # kept
    page.evaluate("() => lagrangian.set('d', 1.5)")  # a mass of 0.5 is a mass
    assert page.evaluate("() => lagrangian.parameters.d") == 1.5
    assert opened.errors == []
    page.close()

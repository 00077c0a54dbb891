"""The page's Poincaré section panel in a real browser (headless Chromium): a click in
the plane starts an orbit on the energy shell, and its crossings are the points of
``lagrangian poincare`` from the same start.

Checked independently: the start's energy from the model's formula in numpy, the
crossings from the CLI's DOP853 through SciPy (or its compiled loop), the velocity of a
held-out model with a magnetic term and coupled velocities from the quadratic solved by
numpy.roots.
"""

from __future__ import annotations

import csv
import re

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.output.page import page_html
from output.browser import open_page

pytestmark = pytest.mark.slow

E = 0.125
#: Not an example of the project: a unit charge in a quartic well with a magnetic field B
#: (A = (0, B x)) and velocities coupled by k, so h = (x'^2 + y'^2)/2 + k x' y' + V: the
#: field leaves h alone but moves p_y = y' + k x' + B x.
CHARGE = """
name = "charge in a quartic well"
coordinates = ["x", "y"]
lagrangian = "(x_dot^2 + y_dot^2)/2 + k*x_dot*y_dot + B*x*y_dot - (x^2 + y^2)/2 - a*(x^4 + y^4)"

[parameters]
k = 0.3
B = 0.7
a = 0.5

[initial]
x = 0.3
y = 0.1
x_dot = 0.2
y_dot = -0.1

[simulate]
t_end = 40.0
"""
K, B, A = 0.3, 0.7, 0.5


@pytest.fixture(scope="module")
def henon_heiles(browser, tmp_path_factory):
    path = tmp_path_factory.mktemp("pages") / "henon_heiles.html"
    path.write_text(page_html(lg.load("henon_heiles")), encoding="utf-8")
    opened = open_page(browser, path)
    opened.page.evaluate("() => lagrangian.pause()")
    return opened


@pytest.fixture(scope="module")
def charge(browser, tmp_path_factory):
    folder = tmp_path_factory.mktemp("charge")
    model = folder / "charge.toml"
    model.write_text(CHARGE, encoding="utf-8")
    path = folder / "charge.html"
    path.write_text(page_html(lg.load(str(model))), encoding="utf-8")
    opened = open_page(browser, path)
    opened.page.evaluate("() => lagrangian.pause()")
    return opened, model


def henon_heiles_energy(x, y, x_dot, y_dot):
    return (x_dot**2 + y_dot**2) / 2 + (x**2 + y**2) / 2 + x**2 * y - y**3 / 3


def python_points(capsys, tmp_path, model, start, section, t_end):
    """The crossings of ``lagrangian poincare`` from ``start`` (x, y, x_dot, y_dot): t and
    the state at each, from its CSV."""
    names = ("x", "y", "x_dot", "y_dot")
    out = tmp_path / "points.csv"
    settings = [f"--set={name}={value!r}" for name, value in zip(names, start, strict=True)]
    status = main(
        ["poincare", model, "--section", section, "--axes", "y,p_y", "--t-end", str(t_end),
         *settings, "--out", str(out), "--json"]
    )  # fmt: skip
    capsys.readouterr()
    assert status == ExitStatus.SUCCESS
    with open(out, newline="") as file:
        rows = list(csv.DictReader(file))
    times = np.array([float(row["t"]) for row in rows])
    states = np.array([[float(row[name]) for name in names] for row in rows])
    return times, states


def test_a_click_starts_an_orbit_on_the_shell_with_the_crossings_of_lagrangian_poincare(
    henon_heiles, capsys, tmp_path
):
    page = henon_heiles.page
    page.evaluate(
        "() => lagrangian.section.configure({coordinate: 'x', value: 0, direction: '+',"
        " axis: 'y', kind: 'momentum', energy: 0.125, t_end: 100})"
    )
    x, y = page.evaluate("() => lagrangian.section.screen(0.1, 0.05)")
    page.get_by_label("Poincaré section", exact=True).click(position={"x": x, "y": y})
    page.evaluate("() => lagrangian.section.settled()")  # integrated in slices
    (orbit,) = page.evaluate("() => lagrangian.section.orbits()")
    assert orbit["done"]
    start = orbit["start"]
    assert start[0] == 0.0 and start[2] > 0  # on the section x = 0, crossing upwards
    assert start[1] == pytest.approx(0.1, abs=0.01) and start[3] == pytest.approx(0.05, abs=0.01)
    assert henon_heiles_energy(*start) == pytest.approx(E, abs=1e-9)
    status = page.evaluate("() => lagrangian.section.status()")
    assert status.startswith("Orbit 1 from y = ") and status.endswith(" crossings.")

    times, states = python_points(capsys, tmp_path, "henon_heiles", start, "x = 0", 100)
    assert len(times) == len(orbit["times"]) >= 10
    assert np.allclose(orbit["times"], times, rtol=0, atol=1e-6)
    assert np.allclose(orbit["states"], states, rtol=0, atol=1e-6)
    # the plane's points: (y, p_y = y_dot) at the crossings; every one on the shell
    assert np.allclose(orbit["points"], states[:, [1, 3]], rtol=0, atol=1e-6)
    assert np.abs(henon_heiles_energy(*states.T) - E).max() < 1e-8
    assert np.abs(states[:, 0]).max() < 1e-12


def test_a_long_orbit_shows_its_first_points_while_the_page_keeps_running(henon_heiles):
    # t_end = 2000: about 20,000 DOP853 steps, far more than one slice of integration; the
    # page draws frames between the slices, and the points drawn at the first frame that
    # shows one are the first crossings of the finished orbit
    page = henon_heiles.page
    page.evaluate(
        "() => lagrangian.section.configure({coordinate: 'x', value: 0, direction: '+',"
        " axis: 'y', kind: 'momentum', energy: 0.125, t_end: 2000})"
    )
    seen = page.evaluate(
        """async () => {
            const section = lagrangian.section;
            const orbit = section.launch(0.1, 0.05);
            let drawn = section.orbits()[0];
            while (drawn.points.length === 0) {
                await new Promise((resolve) => requestAnimationFrame(resolve));
                drawn = section.orbits()[0];
            }
            return { first: drawn, status: section.status(), last: await orbit };
        }"""
    )
    first, last = seen["first"], seen["last"]
    assert not first["done"] and last["done"]
    assert 1 <= len(first["points"]) < len(last["points"])
    assert first["points"] == last["points"][: len(first["points"])]
    assert first["times"] == last["times"][: len(first["times"])]
    assert re.fullmatch(r"Orbit 1 from y = .*: \d+ crossings so far \(t = \S+\)…", seen["status"])
    assert page.evaluate("() => lagrangian.section.status()").endswith(" crossings.")
    assert henon_heiles.errors == []


def test_a_click_outside_the_energy_allowed_region_starts_nothing(henon_heiles):
    page = henon_heiles.page
    page.evaluate(
        "() => lagrangian.section.configure({coordinate: 'x', value: 0, direction: '+',"
        " axis: 'y', kind: 'momentum', energy: 0.125, t_end: 100})"
    )
    # p_y = 0.6: the kinetic energy p_y^2 / 2 = 0.18 alone is above E = 1/8
    x, y = page.evaluate("() => lagrangian.section.screen(0.0, 0.6)")
    page.get_by_label("Poincaré section", exact=True).click(position={"x": x, "y": y})
    status = page.evaluate("() => lagrangian.section.status()")
    found = re.fullmatch(
        r"outside the energy-allowed region: no real ẋ gives E = 0\.125000 at "
        r"y = (\S+), p_y = (\S+); nothing started",
        status,
    )
    assert found, status
    clicked_y, clicked_p = (float(v) for v in found.groups())
    assert henon_heiles_energy(0.0, clicked_y, 0.0, clicked_p) > E  # at rest across: above E
    assert page.evaluate("() => lagrangian.section.orbits()") == []
    assert henon_heiles.errors == []


def numpy_velocity(x, y, y_dot, E, sign):
    """x_dot of the charge on h = E, given y_dot, the root of the sign (numpy.roots)."""
    potential = (x**2 + y**2) / 2 + A * (x**4 + y**4)
    roots = np.roots([0.5, K * y_dot, y_dot**2 / 2 + potential - E])
    return max(roots) if sign > 0 else min(roots)


@pytest.mark.parametrize("direction", ["+", "-"])
def test_the_velocity_of_a_held_out_model_is_the_root_of_its_quadratic(charge, direction):
    opened, _ = charge
    page = opened.page
    page.evaluate(
        "(d) => lagrangian.section.configure({coordinate: 'x', value: 0.3, direction: d,"
        " axis: 'y', kind: 'velocity', energy: 0.4, t_end: 5})",
        direction,
    )
    orbit = page.evaluate("() => lagrangian.section.launch(0.2, 0.5)")
    x_dot = numpy_velocity(0.3, 0.2, 0.5, 0.4, 1 if direction == "+" else -1)
    assert orbit["start"][:2] == [0.3, 0.2] and orbit["start"][3] == 0.5
    assert orbit["start"][2] == pytest.approx(x_dot, rel=1e-12)
    # the coupling k x' y' makes the roots unequal: the direction's root, not -root
    assert abs(x_dot + numpy_velocity(0.3, 0.2, 0.5, 0.4, -1 if direction == "+" else 1)) > 0.1


def test_the_momentum_of_a_held_out_model_moves_the_start_by_its_magnetic_term(
    charge, capsys, tmp_path
):
    opened, model = charge
    page = opened.page
    page.evaluate(
        "() => lagrangian.section.configure({coordinate: 'x', value: 0.3, direction: '+',"
        " axis: 'y', kind: 'momentum', energy: 0.4, t_end: 40})"
    )
    orbit = page.evaluate("() => lagrangian.section.launch(0.2, 0.5)")
    # p_y = y_dot + k x_dot + B x = 0.5: y_dot = c - k x_dot, c = 0.5 - B x; then
    # h = (1 - k^2) x_dot^2 / 2 + c^2 / 2 + V = E (the linear terms cancel)
    c = 0.5 - B * 0.3
    potential = (0.3**2 + 0.2**2) / 2 + A * (0.3**4 + 0.2**4)
    x_dot = max(np.roots([(1 - K**2) / 2, 0.0, c**2 / 2 + potential - 0.4]))
    expected = [0.3, 0.2, x_dot, c - K * x_dot]
    assert orbit["start"] == pytest.approx(expected, rel=1e-12)
    times, states = python_points(capsys, tmp_path, str(model), orbit["start"], "x = 0.3", 40)
    assert len(times) == len(orbit["times"]) >= 3
    assert np.allclose(orbit["times"], times, rtol=0, atol=1e-6)
    assert np.allclose(orbit["states"], states, rtol=0, atol=1e-6)
    momenta = states[:, 3] + K * states[:, 2] + B * states[:, 0]
    assert np.allclose(np.array(orbit["points"])[:, 1], momenta, rtol=0, atol=1e-6)
    assert opened.errors == []


def test_a_model_without_an_energy_shell_says_why(browser, tmp_path):
    path = tmp_path / "driven.html"
    path.write_text(page_html(lg.load("driven_damped_pendulum")), encoding="utf-8")
    opened = open_page(browser, path)
    panel = opened.page.locator("fieldset.poincare")
    assert "A Poincaré section needs two coordinates or more" in panel.inner_text()
    assert opened.page.evaluate("() => lagrangian.section") is None
    assert opened.errors == []


def test_the_section_of_the_run_is_that_of_lagrangian_poincare_from_the_models_start(
    henon_heiles, capsys, tmp_path
):
    page = henon_heiles.page
    page.evaluate(
        "() => lagrangian.section.configure({coordinate: 'x', value: 0, direction: '+',"
        " axis: 'y', kind: 'velocity', energy: null, t_end: 100})"
    )
    page.get_by_role("button", name="Section of this run").click()
    page.evaluate("() => lagrangian.section.settled()")
    (orbit,) = page.evaluate("() => lagrangian.section.orbits()")
    start = [0.0, -0.25, 0.42081, 0.0]  # henon_heiles.toml's [initial]
    assert orbit["start"] == start
    times, states = python_points(capsys, tmp_path, "henon_heiles", start, "x = 0", 100)
    assert len(times) == len(orbit["times"]) >= 10
    assert np.allclose(orbit["times"], times, rtol=0, atol=1e-6)
    assert np.allclose(orbit["points"], states[:, [1, 3]], rtol=0, atol=1e-6)


def test_an_energy_not_quadratic_in_the_velocity_is_refused(browser, tmp_path):
    # h = x_dot^4 / 4 + y_dot^2 / 2 + V: a quadratic through h at x_dot = -1, 0, 1 misses
    # h at x_dot = 2 by 3, so no start is solved from it
    model = tmp_path / "quartic.toml"
    model.write_text(
        'name = "quartic kinetic energy"\ncoordinates = ["x", "y"]\n'
        'lagrangian = "x_dot^4/12 + y_dot^2/2 - (x^2 + y^2)/2"\n',
        encoding="utf-8",
    )
    path = tmp_path / "quartic.html"
    path.write_text(page_html(lg.load(str(model))), encoding="utf-8")
    opened = open_page(browser, path)
    page = opened.page
    page.evaluate("() => lagrangian.pause()")
    page.evaluate("() => lagrangian.section.configure({axis: 'y', energy: 1})")
    refused = page.evaluate("() => lagrangian.section.launch(0.1, 0.2)")
    expected = "the energy is not a convex quadratic in ẋ: it cannot be solved on the shell"
    assert refused == {"refused": expected}
    assert page.evaluate("() => lagrangian.section.status()") == expected
    assert page.evaluate("() => lagrangian.section.orbits()") == []
    assert opened.errors == []


def test_the_embedded_page_leaves_the_panel_out(browser, tmp_path):
    path = tmp_path / "henon_heiles.html"
    path.write_text(page_html(lg.load("henon_heiles")), encoding="utf-8")
    page = browser.new_page(viewport={"width": 700, "height": 600})
    page.goto(path.resolve().as_uri() + "#embed")
    page.wait_for_function("() => window.lagrangian !== undefined", timeout=20_000)
    assert page.evaluate("() => lagrangian.embedded()")
    assert page.locator("fieldset.poincare").is_hidden()
    page.close()

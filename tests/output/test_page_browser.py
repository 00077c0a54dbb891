"""The page in a real browser (headless Chromium from file://): it loads offline with no
console error and no request, the math is typeset, the motion agrees with ``lagrangian
simulate``, the controls change it, 3-D bodies draw, and a hostile model runs nothing.

One browser for the module; each page is written once (writing derives and analyses).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import lagrangian as lg
from helpers import spring_bar_and_bob
from lagrangian.cli import ExitStatus, main
from lagrangian.examples import example_names
from lagrangian.output.page import page_html
from lagrangian.output.solids import solid_shape
from output.browser import open_page
from output.test_page import HOSTILE_DESCRIPTION, HOSTILE_MODEL, HOSTILE_NAME

pytestmark = pytest.mark.slow

#: How many canvas pixels must be drawn in a colour for a part to count as drawn.
DRAWN_PIXELS = 30
#: The opacities the mechanism's parts are drawn at (page.js: the planar bodies at 0.85),
#: on the canvas' opaque white.
DRAWN_OPACITIES = (1.0, 0.85)


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """name -> path of the example's page, written on first use."""
    folder = tmp_path_factory.mktemp("pages")
    pages: dict = {}

    def page_of(name: str):
        if name not in pages:
            pages[name] = folder / f"{name}.html"
            pages[name].write_text(page_html(lg.load(name)), encoding="utf-8")
        return pages[name]

    return page_of


@pytest.fixture(scope="module")
def double_pendulum(browser, written):
    opened = open_page(browser, written("double_pendulum"))
    yield opened
    opened.page.close()


def test_page_loads_offline_without_errors_or_requests(double_pendulum):
    double_pendulum.page.wait_for_timeout(500)  # a few frames of the animation
    assert double_pendulum.errors == []
    assert [url for url in double_pendulum.requests if not url.startswith("file://")] == []
    assert len(double_pendulum.requests) == 1  # the page itself, nothing else


def test_math_is_typeset(double_pendulum):
    page = double_pendulum.page
    assert page.locator(".katex").count() >= 5
    assert page.locator(".katex-error").count() == 0
    text = page.locator("#solution").inner_text()
    for raw in ("\\begin", "\\frac", "\\dot", "\\theta"):
        assert raw not in text


def test_run_agrees_with_lagrangian_simulate(double_pendulum, capsys):
    argv = ["simulate", "double_pendulum", "--t-end", "10", "--rtol", "1e-12", "--atol", "1e-12"]
    assert main([*argv, "--json"]) == ExitStatus.SUCCESS
    final = json.loads(capsys.readouterr().out)["final_state"]
    page = double_pendulum.page
    state = page.evaluate("() => { lagrangian.reset(); return lagrangian.run(10); }")
    assert state["t"] == 10
    for name in ("theta1", "theta2"):
        assert state["q"][name] == pytest.approx(final[name], abs=1e-8)
        assert state["q_dot"][name] == pytest.approx(final[f"{name}_dot"], abs=1e-8)


def test_an_input_held_constant_as_simulate_holds_it(browser, written, capsys):
    argv = ["simulate", "cart_pole", "--t-end", "1", "--set", "F=0.5"]
    argv += ["--rtol", "1e-12", "--atol", "1e-12", "--json"]
    assert main(argv) == ExitStatus.SUCCESS
    final = json.loads(capsys.readouterr().out)["final_state"]
    opened = open_page(browser, written("cart_pole"))
    page = opened.page
    assert page.evaluate("() => lagrangian.inputs") == {"F": 0}
    state = page.evaluate(
        "() => { lagrangian.pause(); lagrangian.set('F', 0.5); return lagrangian.run(1); }"
    )
    for name, value in state["q"].items():
        assert value == pytest.approx(final[name], abs=1e-8)
    assert page.get_by_role("slider", name="F", exact=True).count() == 1
    assert opened.errors == []
    page.close()


def test_moving_a_slider_changes_the_motion(double_pendulum):
    page = double_pendulum.page
    page.evaluate("() => lagrangian.pause()")  # no frames between the steps of the test
    before = page.evaluate("() => { lagrangian.reset(); return lagrangian.run(2); }")
    slider = page.get_by_role("slider", name="g", exact=True)
    slider.evaluate("(node) => { node.value = '3'; node.dispatchEvent(new Event('input')); }")
    assert page.evaluate("() => lagrangian.parameters.g") == pytest.approx(3, abs=0.05)  # its step
    after = page.evaluate("() => lagrangian.run(2)")
    assert abs(after["q"]["theta1"] - before["q"]["theta1"]) > 1e-3
    # set() restarts from the initial state at t = 0
    page.evaluate("() => lagrangian.set('g', 9.81)")
    assert page.evaluate("() => lagrangian.state().t") == 0
    again = page.evaluate("() => lagrangian.run(2)")
    assert again["q"]["theta1"] == pytest.approx(before["q"]["theta1"], abs=1e-12)


def test_initial_values_and_energy_through_the_hook(double_pendulum):
    page = double_pendulum.page
    page.evaluate("() => lagrangian.pause()")
    state = page.evaluate("() => { lagrangian.set('theta1', 0.1); lagrangian.set('theta2', 0);"
                          " return lagrangian.state(); }")  # fmt: skip
    assert state == {"t": 0, "q": {"theta1": 0.1, "theta2": 0}, "q_dot": {"theta1": 0, "theta2": 0}}
    # h = -(m1 + m2) g l1 cos(theta1) - m2 g l2 cos(theta2) at rest
    expected = -2 * 9.81 * 0.9950041652780258 - 9.81
    assert page.evaluate("() => lagrangian.energy()") == pytest.approx(expected, rel=1e-14)
    page.evaluate("() => { lagrangian.set('theta1', 2.0); lagrangian.set('theta2', 0.5); }")


def test_dragging_a_mass_sets_the_initial_state(double_pendulum):
    page = double_pendulum.page
    page.evaluate("() => { lagrangian.pause(); lagrangian.reset(); }")
    box = page.evaluate(
        "() => { const p = document.querySelector('canvas.mechanism').getBoundingClientRect();"
        " return [p.left, p.top, p.width, p.height]; }"
    )
    bob = page.evaluate("() => window.lagrangian.screenPosition('bob1')")
    page.mouse.move(box[0] + bob[0], box[1] + bob[1])
    page.mouse.down()
    page.mouse.move(box[0] + bob[0] + 40, box[1] + bob[1] + 40, steps=5)
    page.mouse.up()
    state = page.evaluate("() => lagrangian.state()")
    assert state["t"] == 0 and abs(state["q"]["theta1"] - 2.0) > 0.01
    assert state["q_dot"] == {"theta1": 0, "theta2": 0}
    page.evaluate("() => { lagrangian.set('theta1', 2.0); lagrangian.set('theta2', 0.5); }")


def test_variational_integrator_keeps_the_energy_and_follows_dop853(double_pendulum):
    page = double_pendulum.page
    page.evaluate("() => { lagrangian.pause(); lagrangian.reset(); }")
    reference = page.evaluate("() => lagrangian.run(1)")
    page.select_option("select[aria-label=integrator]", "variational")
    assert page.evaluate("() => lagrangian.stats().method") == "variational"
    start = page.evaluate(
        "() => { lagrangian.pause(); lagrangian.reset(); return lagrangian.energy(); }"
    )
    state = page.evaluate("() => lagrangian.run(1)")
    # second order at dt = 0.001 over 1 s of the chaotic motion: about 1e-5
    for name in ("theta1", "theta2"):
        assert state["q"][name] == pytest.approx(reference["q"][name], abs=1e-4)
    page.evaluate("() => lagrangian.run(20)")
    energy = page.evaluate("() => lagrangian.energy()")
    assert abs(energy - start) < 1e-4 * abs(start)  # bounded: the method is symplectic
    assert page.evaluate("() => lagrangian.stats().steps") == pytest.approx(20_000, abs=2)
    page.select_option("select[aria-label=integrator]", "dop853")


def _drawn_pixels(page, color: str) -> int:
    """Pixels of the mechanism's canvas within a small distance of ``color`` (#rrggbb) drawn
    at one of :data:`DRAWN_OPACITIES` over the canvas' white."""
    return page.evaluate(
        """([color, opacities]) => {
          const canvas = document.querySelector('canvas.mechanism');
          const data = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
          const rgb = [1, 3, 5].map((i) => parseInt(color.slice(i, i + 2), 16));
          const wants = opacities.map((a) => rgb.map((c) => a * c + (1 - a) * 255));
          let count = 0;
          for (let i = 0; i < data.length; i += 4) {
            if (wants.some((want) => Math.abs(data[i] - want[0]) + Math.abs(data[i + 1] - want[1])
                + Math.abs(data[i + 2] - want[2]) < 30)) count += 1;
          }
          return count;
        }""",
        [color, list(DRAWN_OPACITIES)],
    )


def test_heavy_top_draws_its_disc_in_two_views(browser, written):
    opened = open_page(browser, written("heavy_top"))
    page = opened.page
    page.evaluate("() => { lagrangian.pause(); lagrangian.run(1); }")
    page.wait_for_timeout(200)
    style = page.evaluate(
        "() => JSON.parse(document.getElementById('lagrangian-model').textContent).scene.style"
    )
    assert _drawn_pixels(page, style["solid"]) > DRAWN_PIXELS
    assert page.evaluate("() => lagrangian.state().q.theta") != 0
    assert opened.errors == []
    page.close()


def test_a_3d_body_is_drawn_at_the_parameters_of_the_moment(browser, written):
    """The outline follows the mass and moments: the top's disc grows with I3, and becomes
    the box of lagrangian.output.solids when the moments no longer make it flat."""
    opened = open_page(browser, written("heavy_top"))
    page = opened.page
    page.evaluate("() => lagrangian.pause()")
    values = {"M": 1.0, "I1": 0.01, "I3": 0.02}
    # I1 first: I3 = 0.05 beside I1 = 0.01 is no body (I3 > I1 + I1), refused by the page
    for name, value in (("I1", 0.03), ("I3", 0.05), ("M", 2.5)):
        values[name] = value
        page.evaluate("([name, value]) => lagrangian.set(name, value)", [name, value])
        page.evaluate("() => lagrangian.run(0.2)")
        (body,) = page.evaluate("() => lagrangian.solids()")
        drawn = np.linalg.norm(np.array(body["outline"]) - np.array(body["center"]), axis=1)
        inertia = np.diag([values["I1"], values["I1"], values["I3"]])
        shape = solid_shape(values["M"], inertia)
        assert len(drawn) == len(shape.points), name
        assert np.sort(drawn) == pytest.approx(np.sort(np.linalg.norm(shape.points, axis=1)))
    assert shape.kind == "box"
    assert opened.errors == []
    page.close()


def test_springs_planar_bodies_and_particles_draw(browser, tmp_path):
    system = spring_bar_and_bob()
    path = tmp_path / "spring.html"
    path.write_text(page_html(system), encoding="utf-8")
    opened = open_page(browser, path)
    page = opened.page
    page.evaluate("() => { lagrangian.pause(); lagrangian.run(0.3); }")
    page.wait_for_timeout(200)
    scene = page.evaluate(
        "() => JSON.parse(document.getElementById('lagrangian-model').textContent).scene"
    )
    for color in (scene["style"]["spring"], scene["style"]["body"], scene["particles"][0]["color"]):
        assert _drawn_pixels(page, color) > DRAWN_PIXELS, color
    assert opened.errors == []
    page.close()


def test_hostile_model_text_runs_nothing(browser, tmp_path):
    path = tmp_path / "hostile.html"
    path.write_text(page_html(lg.loads(HOSTILE_MODEL)), encoding="utf-8")
    opened = open_page(browser, path)
    page = opened.page
    page.wait_for_timeout(300)
    assert page.evaluate("() => window.pwned") is None
    assert page.locator("#title").inner_text() == HOSTILE_NAME
    assert page.locator("#description").inner_text() == HOSTILE_DESCRIPTION
    assert page.title() == HOSTILE_NAME
    assert page.locator("body img").count() == 0
    assert opened.errors == [] and not [m for m in opened.messages if m[0] == "dialog"]
    page.close()


#: Examples with unspecified functions: their page has the solution, and says why no motion.
UNSPECIFIED = ("velocity_dependent_potential",)


@pytest.mark.parametrize("name", [n for n in example_names() if n not in UNSPECIFIED])
def test_every_example_page_loads_and_runs(browser, written, name):
    opened = open_page(browser, written(name))
    page = opened.page
    state = page.evaluate("() => { lagrangian.reset(); return lagrangian.run(0.5); }")
    page.wait_for_timeout(200)
    assert state["t"] == 0.5
    values = [*state["q"].values(), *state["q_dot"].values()]
    assert all(isinstance(v, float | int) for v in values)
    assert page.locator(".katex-error").count() == 0
    assert opened.errors == []
    assert len(opened.requests) == 1
    page.close()


@pytest.mark.parametrize("name", UNSPECIFIED)
def test_a_model_with_unspecified_functions_shows_its_solution_and_why(browser, written, name):
    opened = open_page(browser, written(name))
    page = opened.page
    assert "unspecified" in page.evaluate("() => lagrangian.unavailable")
    assert "unspecified" in page.locator("#live").inner_text()
    assert page.locator(".katex").count() >= 3 and page.locator(".katex-error").count() == 0
    assert opened.errors == []
    page.close()


def test_given_definitions_make_it_run(browser, tmp_path):
    system = lg.load("velocity_dependent_potential")
    path = tmp_path / "defined.html"
    # a charge in a harmonic well and a uniform magnetic field along z
    definitions = {"V": "(x^2 + y^2 + z^2)/2", "A": "-y/2", "B": "x/2", "C": "0"}
    path.write_text(page_html(system, definitions=definitions), encoding="utf-8")
    opened = open_page(browser, path)
    state = opened.page.evaluate("() => { lagrangian.reset(); return lagrangian.run(0.5); }")
    assert state["t"] == 0.5 and opened.errors == []
    opened.page.close()

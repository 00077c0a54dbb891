"""The page's share link and embed mode in a real browser (headless Chromium): a link
opened in a second page reproduces the run of the first to the last digit (values,
initial state, integrator, time), a link that does not fit is said, and the embed mode
runs inside ``<iframe sandbox="allow-scripts">`` with no console error."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.output.page import page_html
from output.browser import open_page

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    path = tmp_path_factory.mktemp("pages") / "double_pendulum.html"
    path.write_text(page_html(lg.load("double_pendulum")), encoding="utf-8")
    return path


def _opened_with(browser, address: str):
    page = browser.new_page(viewport={"width": 1300, "height": 900})
    errors: list[str] = []
    page.on("console", lambda m: m.type == "error" and errors.append(m.text))
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(address)
    page.wait_for_function("() => window.lagrangian !== undefined", timeout=20_000)
    return page, errors


@pytest.mark.parametrize("method", ["dop853", "variational"])
def test_a_shared_link_reproduces_the_run_to_the_last_digit(browser, written, method):
    first = open_page(browser, written)
    page = first.page
    page.evaluate("() => { lagrangian.set('g', 3.7); lagrangian.set('theta2', 1.1); }")
    page.get_by_label("integrator").select_option(method)
    page.evaluate("() => lagrangian.play()")
    page.wait_for_timeout(700)  # frames of the animation: steps that end at frame times
    link = page.evaluate("() => lagrangian.link()")
    shared = page.evaluate("() => lagrangian.state()")
    assert shared["t"] > 0.1
    assert f"method={method}" in link and "p.g=3.7" in link and "q.theta2=1.1" in link
    second, errors = _opened_with(browser, link)
    assert second.evaluate("() => lagrangian.state()") == shared  # every digit
    assert second.evaluate("() => lagrangian.parameters") == page.evaluate(
        "() => lagrangian.parameters"
    )
    assert second.evaluate("() => lagrangian.stats().method") == method
    # opened at the moment of the link, paused there
    second.wait_for_timeout(200)
    assert second.evaluate("() => lagrangian.state().t") == shared["t"]
    assert errors == [] and first.errors == []
    page.close()
    second.close()


def test_the_share_button_offers_the_link(browser, written):
    opened = open_page(browser, written)
    page = opened.page
    page.get_by_role("button", name="Share link").click()
    field = page.get_by_label("link to share")
    assert field.input_value() == page.evaluate("() => lagrangian.link()")
    page.get_by_role("button", name="Embed").click()
    snippet = field.input_value()
    assert snippet.startswith('<iframe sandbox="allow-scripts" src="file://')
    assert "#embed&amp;p.m1=1" in snippet
    page.close()


def test_a_link_that_does_not_fit_the_model_is_said(browser, written):
    address = written.resolve().as_uri() + "#p.g=2&p.mass=3&q.theta1=x&method=rk4"
    page, errors = _opened_with(browser, address)
    assert page.evaluate("() => lagrangian.parameters.g") == 2
    status = page.get_by_role("status").inner_text()
    assert status == (
        "The link: q.theta1: not a finite number: 'x'; 'mass' is not a parameter of this"
        " model; 'rk4' is not an integrator of this page (dop853, variational) (left out)."
    )
    assert errors == []
    page.close()


def test_the_embed_runs_in_a_sandboxed_frame_without_console_errors(browser, written, tmp_path):
    host = tmp_path / "course.html"
    source = written.resolve().as_uri() + "#embed&p.g=3.7"
    host.write_text(
        "<!DOCTYPE html><html><body><h1>Week 3</h1>"
        f'<iframe sandbox="allow-scripts" src="{source}" width="640" height="560"></iframe>'
        "</body></html>",
        encoding="utf-8",
    )
    page, errors = _opened_with_frame(browser, host)
    frame = page.frames[1]
    frame.wait_for_function("() => window.lagrangian !== undefined", timeout=20_000)
    assert frame.evaluate("() => lagrangian.embedded()") is True
    assert frame.evaluate("() => lagrangian.parameters.g") == 3.7
    # the animation and its controls only
    assert frame.locator("#solution").is_hidden() and frame.locator("header").is_hidden()
    assert frame.locator("canvas.mechanism").is_visible()
    frame.wait_for_function("() => lagrangian.state().t > 0.2", timeout=20_000)  # it runs
    frame.get_by_role("button", name="Share link").click()  # no clipboard in a sandbox
    page.wait_for_timeout(200)
    assert errors == []
    page.close()


def _opened_with_frame(browser, host):
    page = browser.new_page(viewport={"width": 900, "height": 700})
    errors: list[str] = []
    page.on("console", lambda m: m.type == "error" and errors.append(m.text))
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(host.resolve().as_uri())
    return page, errors

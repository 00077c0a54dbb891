"""The editor in a real browser: `lagrangian serve` run as a process, driven by Playwright.

Chromium is Debian's, found as the page's checks find it (tests/output/browser.py), never
a download; the test skips, saying so, where there is none.  The server is stopped, and
waited for, however the test ends; every wait is bounded.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from output.test_page import HOSTILE_MODEL, HOSTILE_NAME

pytest.importorskip("uvicorn", reason="the serve extra (uvicorn) is not installed")
playwright_errors = pytest.importorskip("playwright.sync_api", reason="no Playwright")
SOURCES = Path(__file__).resolve().parents[2] / "src"
#: Seconds for the server to say where it listens, and for a page or error to show.
START_SECONDS = 120
SHOW_SECONDS = 120


@pytest.fixture(scope="module")
def editor_url():
    """The address of a `lagrangian serve --port 0` process, stopped after the module."""
    environment = dict(os.environ, PYTHONPATH=str(SOURCES))
    server = subprocess.Popen(
        [sys.executable, "-m", "lagrangian", "serve", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=environment,
        start_new_session=True,  # its worker too is in the group stopped below
    )
    try:
        lines: list[str] = []
        reader = threading.Thread(target=lambda: lines.append(server.stdout.readline()))
        reader.start()
        reader.join(START_SECONDS)
        found = re.search(r"http://\S+", lines[0]) if lines else None
        if found is None:
            pytest.fail(f"the server did not start: {server.stderr.read() if lines else ''}")
        yield found[0]
        server.send_signal(signal.SIGINT)  # as Ctrl-C: the server stops its worker
        assert server.wait(timeout=30) == 0
    finally:
        if server.poll() is None:
            os.killpg(server.pid, signal.SIGKILL)
            server.wait(timeout=30)


@pytest.mark.slow
def test_the_editor_shows_the_error_line_then_the_page(browser, editor_url):
    page = browser.new_page()
    problems: list[str] = []
    page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda error: problems.append(str(error)))
    page.on("dialog", lambda dialog: problems.append(f"a dialog: {dialog.message}"))
    page.set_default_timeout(SHOW_SECONDS * 1000)
    page.goto(editor_url)
    frame = page.frame_locator("#page")
    frame.locator("body").wait_for()  # the first example's page

    editor = page.locator("#model")
    editor.fill("")
    editor.type("m*x_dot**2/2 - k*x**2/2 + </p><b>bold</b><script>alert(1)</script>")
    error = page.locator("#error")
    error.wait_for(state="visible")
    assert error.text_content() == (
        "editor: lagrangian: unexpected character '<' at position 27 in "
        "'m*x_dot**2/2 - k*x**2/2 + </p><b>bold</b><script>alert(1)...'"
    )
    assert page.locator("#error *").count() == 0  # shown as text, not markup

    editor.fill("")
    editor.type("m*x_dot**2/2 - k*x**2/2")
    error.wait_for(state="hidden")
    # the oscillator's page, running: its hook has the parameters of the typed Lagrangian
    frame_shows(page, "window.lagrangian?.parameters", {"k": 1, "m": 1})
    assert page.frames[1].evaluate("Object.keys(window.lagrangian.state().q)") == ["x"]

    editor.fill(HOSTILE_MODEL)  # its name and description try to break out of the page
    frame_shows(page, "document.getElementById('title')?.textContent", HOSTILE_NAME)
    assert page.frames[1].evaluate("window.pwned") is None
    assert page.evaluate("window.pwned") is None
    assert problems == []
    page.close()


RESTORED_NAME = "A model typed before the reload"
RESTORED_MODEL = f"""name = "{RESTORED_NAME}"
coordinates = ["x"]
lagrangian = "m*x_dot**2/2 - k*x**4/4"

[parameters]
m = 1.0
k = 2.0
"""


@pytest.mark.slow
def test_a_reload_restores_the_users_model_not_the_first_example(browser, editor_url):
    # issue 37 item 12: after a server crash, reloading the editor replaced the user's
    # model with the first example
    page = browser.new_page()
    page.set_default_timeout(SHOW_SECONDS * 1000)
    page.goto(editor_url)
    page.frame_locator("#page").locator("body").wait_for()  # the first example's page
    editor = page.locator("#model")
    editor.fill(RESTORED_MODEL)
    frame_shows(page, "document.getElementById('title')?.textContent", RESTORED_NAME)

    page.reload()
    page.locator("#examples option").nth(1).wait_for(state="attached")  # examples loaded
    assert editor.input_value() == RESTORED_MODEL
    assert page.locator("#examples").input_value() == ""  # not an example's text
    frame_shows(page, "document.getElementById('title')?.textContent", RESTORED_NAME)

    page.select_option("#examples", "harmonic_oscillator")  # an example chosen is kept too
    page.reload()
    page.locator("#examples option").nth(1).wait_for(state="attached")
    assert page.locator("#examples").input_value() == "harmonic_oscillator"
    page.close()


@pytest.mark.slow
def test_text_typed_before_the_examples_arrive_is_not_replaced_by_the_first(browser, editor_url):
    """The first example goes only into an editor nobody typed in: when the examples came
    after the user had begun to type, they replaced the text, and the rest of the typing
    went after the example (a CI run of the test above, under load, saw that: invalid TOML
    at line 32).  Here the list of examples is held back until the text is typed."""
    page = browser.new_page()
    page.set_default_timeout(SHOW_SECONDS * 1000)
    held: list = []
    page.route("**/examples", lambda route: held.append(route))
    page.goto(editor_url)
    for _ in range(SHOW_SECONDS * 10):
        if held:
            break
        page.wait_for_timeout(100)
    assert held, "the editor never asked for its examples"
    editor = page.locator("#model")
    editor.type(RESTORED_MODEL[:40])
    editor.type(RESTORED_MODEL[40:])
    held[0].continue_()
    page.locator("#examples option").nth(1).wait_for(state="attached")  # examples loaded
    assert editor.input_value() == RESTORED_MODEL
    assert page.locator("#examples").input_value() == ""
    frame_shows(page, "document.getElementById('title')?.textContent", RESTORED_NAME)
    page.close()


def frame_shows(page, expression: str, expected: object) -> None:
    """Wait (bounded) until ``expression`` in the page's frame is ``expected``: the frame
    shows the new document some time after the editor received it."""
    for _ in range(SHOW_SECONDS * 10):
        try:
            if page.frames[1].evaluate(expression) == expected:
                return
        except playwright_errors.Error:  # evaluated while the frame navigated
            pass
        page.wait_for_timeout(100)
    raise AssertionError(f"the frame never showed {expected!r} as {expression}")


@pytest.mark.slow
def test_the_exercise_toggle_makes_the_page_an_exercise(browser, editor_url):
    page = browser.new_page()
    problems: list[str] = []
    page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda error: problems.append(str(error)))
    page.set_default_timeout(SHOW_SECONDS * 1000)
    page.goto(editor_url)
    page.frame_locator("#page").locator("body").wait_for()
    page.locator("#model").fill("m*x_dot**2/2 - k*x**2/2")
    frame_shows(page, "window.lagrangian?.parameters", {"k": 1, "m": 1})
    assert page.frames[1].evaluate("typeof window.lagrangianCheck") == "undefined"
    page.locator("#exercise").check()
    frame_shows(page, "typeof window.lagrangianCheck", "function")
    # the exercise of the typed model, checked in the frame
    frame_shows(page, "window.lagrangianCheck('kinetic', 'm*x_dot^2/2').verdict", "right")
    page.locator("#exercise").uncheck()
    frame_shows(page, "typeof window.lagrangianCheck", "undefined")
    assert problems == []
    page.close()

"""``System.page()`` as Jupyter shows it: its ``_repr_html_`` (the page in an escaped srcdoc
frame) opened in headless Chromium runs the page inside the frame, and nothing outside."""

from __future__ import annotations

import pytest

import lagrangian as lg
from output.test_page import HOSTILE_MODEL, HOSTILE_NAME


@pytest.mark.slow
def test_the_inline_page_runs_in_its_frame(browser, tmp_path):
    shown = lg.loads(HOSTILE_MODEL).page()._repr_html_()
    notebook = tmp_path / "notebook.html"
    notebook.write_text(f"<!doctype html><meta charset='utf-8'><body>{shown}</body>")
    page = browser.new_page()
    problems: list[str] = []
    page.on("console", lambda m: problems.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda error: problems.append(str(error)))
    page.on("dialog", lambda dialog: problems.append(f"a dialog: {dialog.message}"))
    page.goto(notebook.as_uri())
    frame = page.frame_locator("iframe")
    frame.locator("#title").wait_for(timeout=60_000)
    assert frame.locator("#title").text_content() == HOSTILE_NAME
    inner = page.frames[1]
    for _ in range(600):  # the page's script sets its hook once its model is read
        if inner.evaluate("window.lagrangian !== undefined"):
            break
        page.wait_for_timeout(100)
    assert inner.evaluate("Object.keys(window.lagrangian.state().q)") == ["x"]
    assert page.evaluate("window.pwned") is None and inner.evaluate("window.pwned") is None
    assert page.locator("body > *").count() == 1  # the frame alone: nothing escaped it
    page.close()
    assert problems == []

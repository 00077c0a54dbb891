"""The page's long rows in a real browser (headless Chromium): a linkage's solved rows are
not typeset at load, each is typeset whole when its <details> is opened, and the folded
section "Step by step" only when it is opened."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.output.page import page_html
from output.browser import open_page

pytestmark = pytest.mark.slow

#: What the worked solution holds once the page has loaded: its elements, the folded rows,
#: those typeset, and the typeset elements inside the (closed) step-by-step section.
SOLUTION = """() => {
  const solution = document.getElementById("solution");
  const rows = [...solution.querySelectorAll("details.folded-row")];
  const steps = [...solution.querySelectorAll("details")].find((d) =>
    d.querySelector("summary").textContent === "Step by step");
  return {
    elements: solution.querySelectorAll("*").length,
    rows: rows.length,
    typeset: rows.filter((d) => d.querySelector(".math .katex")).length,
    steps: steps.querySelectorAll(".katex").length,
  };
}"""


def test_a_linkages_long_rows_are_typeset_only_when_opened(browser, tmp_path):
    path = tmp_path / "slider_crank.html"
    path.write_text(page_html(lg.load("slider_crank")), encoding="utf-8")
    opened = open_page(browser, path)
    page = opened.page
    before = page.evaluate(SOLUTION)
    # its five solved rows (21k-28k characters each) folded; typeset whole (with the
    # steps) they made the solution 187,000 elements (5,053 now; the four-bar's 299,000)
    assert before["rows"] == 5 and before["typeset"] == 0 and before["steps"] == 0
    assert before["elements"] < 10_000
    first = page.locator("details.folded-row").first
    assert "in full (" in first.locator("summary").inner_text()
    first.locator("summary").click()
    first.locator(".math .katex").first.wait_for()
    assert page.evaluate(SOLUTION)["typeset"] == 1
    assert first.locator(".katex-error").count() == 0
    # opening the steps typesets them, their own long rows folded in turn
    page.locator("#solution details > summary", has_text="Step by step").click()
    after = page.evaluate(SOLUTION)
    assert after["steps"] > 0 and after["rows"] == 8 and after["typeset"] == 1
    assert page.locator("#solution .katex-error").count() == 0
    assert opened.errors == []
    page.close()

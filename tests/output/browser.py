"""A headless Chromium for the page's checks: Debian's package driven by Playwright.

No browser is downloaded: Playwright runs the chromium found on the PATH (``.ci/run``
installs Debian's).  Where none is found, or Playwright is missing, the tests that need
one skip and say why.
"""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import pytest

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome")


def chromium_path() -> str:
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    pytest.skip(f"no Chromium found on the PATH (looked for {', '.join(CHROMIUM_NAMES)})")


@contextmanager
def chromium() -> Iterator[object]:
    """A headless Chromium (Playwright's Browser): tests/conftest.py's ``browser``, one a run."""
    sync_api = pytest.importorskip("playwright.sync_api", reason="Playwright is not installed")
    executable = chromium_path()
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=executable, args=["--no-sandbox", "--disable-gpu"]
        )
        try:
            yield browser
        finally:
            browser.close()


@dataclass
class OpenPage:
    """A page opened from a file, with what it printed to the console and requested."""

    page: object
    messages: list[tuple[str, str]] = field(default_factory=list)
    requests: list[str] = field(default_factory=list)

    @property
    def errors(self) -> list[str]:
        return [text for kind, text in self.messages if kind in ("error", "pageerror")]


def open_page(browser, path: Path, *, width: int = 1300, height: int = 900) -> OpenPage:
    """``path`` opened from the disk (file://), the hook ``window.lagrangian`` ready."""
    page = browser.new_page(viewport={"width": width, "height": height})
    opened = OpenPage(page)
    page.on("console", lambda message: opened.messages.append((message.type, message.text)))
    page.on("pageerror", lambda error: opened.messages.append(("pageerror", str(error))))
    page.on("request", lambda request: opened.requests.append(request.url))
    page.on("dialog", lambda dialog: opened.messages.append(("dialog", dialog.message)))
    page.goto(path.resolve().as_uri())
    page.wait_for_function("() => window.lagrangian !== undefined", timeout=20_000)
    return opened

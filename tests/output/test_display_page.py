"""A model's page in Jupyter: ``System.page()`` shown in a sandboxed, escaped srcdoc frame."""

from __future__ import annotations

from html.parser import HTMLParser

import lagrangian as lg
from lagrangian.output.display import ModelPage, sandboxed_frame
from lagrangian.output.page import page_html

HOSTILE = '<!doctype html><p title="a\'b">x</p></iframe><script>alert("&amp;")</script>'


class Tags(HTMLParser):
    """The start tags of an HTML text with their attributes (values unescaped)."""

    def __init__(self, text: str):
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []
        self.feed(text)
        self.close()

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))


def test_the_frame_holds_the_document_whole_and_runs_only_scripts():
    tags = Tags(sandboxed_frame(HOSTILE, height=300)).tags
    assert [tag for tag, _ in tags] == ["iframe"]  # nothing of the document escaped the frame
    attributes = tags[0][1]
    assert attributes["srcdoc"] == HOSTILE
    assert attributes["sandbox"] == "allow-scripts"  # no allow-same-origin: an origin of its own
    assert "height: 300px" in attributes["style"]


def test_system_page_is_the_models_page_shown_in_a_frame(tmp_path):
    system = lg.load("harmonic_oscillator")
    page = system.page()
    assert isinstance(page, ModelPage)
    assert page.html == page_html(system)
    assert Tags(page._repr_html_()).tags[0][1]["srcdoc"] == page.html
    assert "doctype" not in repr(page)  # a terminal shows a line, not the document
    page.save(tmp_path / "oscillator.html")
    assert (tmp_path / "oscillator.html").read_text(encoding="utf-8") == page.html

"""`lagrangian page` of a model seen before: written from the cache of pages, the same bytes;
what is not kept (an analysis cut short, a warning), a damaged or foreign entry ignored, and
the ways around the cache (--no-cache, LAGRANGIAN_NO_CACHE)."""

from __future__ import annotations

import os
import warnings

import pytest

from lagrangian.cli import ExitStatus, main
from lagrangian.examples import example_path
from lagrangian.output import page, page_cache

MODEL = example_path("harmonic_oscillator").read_text(encoding="utf-8")
NAME = "Harmonic oscillator"


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """The cache of pages on, in a folder of this test; the model file beside it."""
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("LAGRANGIAN_NO_CACHE")
    (tmp_path / "oscillator.toml").write_text(MODEL, encoding="utf-8")
    return tmp_path / "cache" / "pages"


@pytest.fixture
def builds(monkeypatch):
    """The pages made (not read from the cache) during the test."""
    made = []
    original = page.built_page

    def counted(*args, **kwargs):
        made.append(args[0].name)
        return original(*args, **kwargs)

    monkeypatch.setattr(page, "built_page", counted)
    return made


def _write(tmp_path, name, *extra) -> bytes:
    out = tmp_path / name
    status = main(["page", str(tmp_path / "oscillator.toml"), "--out", str(out), *extra])
    assert status == ExitStatus.SUCCESS
    return out.read_bytes()


def test_a_page_made_before_is_written_from_the_cache_byte_for_byte(cache, builds, tmp_path):
    first = _write(tmp_path, "a.html")
    assert builds == [NAME] and len(list(cache.iterdir())) == 1
    again = _write(tmp_path, "b.html")
    assert builds == [NAME]  # not made again
    assert again == first
    assert _write(tmp_path, "c.html", "--no-cache") == first
    assert builds == [NAME, NAME]


def test_other_values_or_another_model_text_make_another_page(cache, builds, tmp_path):
    _write(tmp_path, "a.html")
    _write(tmp_path, "b.html", "--set", "k=4")
    (tmp_path / "oscillator.toml").write_text(MODEL.replace("k = 1.0", "k = 2.0"))
    _write(tmp_path, "c.html")
    assert len(builds) == 3 and len(list(cache.iterdir())) == 3


def test_a_damaged_or_foreign_entry_is_ignored_and_written_again(cache, builds, tmp_path):
    first = _write(tmp_path, "a.html")
    (entry,) = cache.iterdir()
    entry.write_bytes(entry.read_bytes().replace(b"Harmonic", b"Pwned"))
    assert _write(tmp_path, "b.html") == first
    assert len(builds) == 2 and entry.read_bytes().count(b"Pwned") == 0
    entry.chmod(0o666)  # others may write it: not trusted
    assert _write(tmp_path, "c.html") == first
    assert len(builds) == 3


def test_the_oldest_pages_go_beyond_the_limit(cache, tmp_path, monkeypatch):
    for k in range(3):  # written a second apart, oldest first
        page_cache.cached_page(f"model {k}".encode(), {}, lambda k=k: page.Page(f"{k}", True))
    for path in cache.iterdir():
        k = int(path.read_bytes().rsplit(b"\n", 1)[-1])
        os.utime(path, (1_000_000 + k, 1_000_000 + k))
    monkeypatch.setattr(page_cache, "KEPT_PAGES", 2)
    page_cache.cached_page(b"model 3", {}, lambda: page.Page("3", True))
    kept = sorted(path.read_bytes().rsplit(b"\n", 1)[-1] for path in cache.iterdir())
    assert kept == [b"2", b"3"]


def test_the_variable_turns_the_cache_off(cache, builds, tmp_path, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_NO_CACHE", "1")
    _write(tmp_path, "a.html")
    _write(tmp_path, "b.html")
    assert len(builds) == 2 and not cache.exists()


def test_an_undecided_analysis_or_a_warning_is_not_kept(cache, tmp_path):
    def undecided():
        return page.Page("<html>cut short</html>", decided=False)

    def warned():
        warnings.warn("something to say", UserWarning, stacklevel=1)
        return page.Page("<html>warned</html>", decided=True)

    assert page_cache.cached_page(b"model", {}, undecided) == "<html>cut short</html>"
    with pytest.warns(UserWarning, match="something to say"):
        assert page_cache.cached_page(b"other", {}, warned) == "<html>warned</html>"
    assert not cache.exists() or list(cache.iterdir()) == []

"""The code cache: only intact text is imported; numba's files are vouched for; a folder that
cannot be written falls back to a temporary one with one warning."""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import tempfile
import textwrap

import pytest

from lagrangian.codegen import cache as code_cache
from lagrangian.errors import CacheWarning


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A fresh cache folder and no module remembered by this process."""
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(code_cache, "_MODULES", {})
    monkeypatch.setattr(code_cache, "_CHOSEN", {})
    monkeypatch.setattr(code_cache, "_LOADED", set())
    return tmp_path / "cache" / "numba"


def _digest(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def test_a_module_is_written_with_the_hash_of_its_text(cache):
    digest = _digest("X = 1\n")
    module = code_cache.load_text(digest, "X = 1\n")
    assert module.X == 1
    first, body = (cache / f"{digest}.py").read_text().split("\n", 1)
    assert first == "# lagrangian code cache: sha256=" + _digest(body)
    assert module.__file__ == str(cache / f"{digest}.py")


@pytest.mark.parametrize(
    "damage",
    [
        lambda text: text[: len(text) // 2],  # truncated by a crash or a full disk
        lambda text: text.replace("X = 1", "X = 9"),  # edited: the header no longer matches
        lambda text: text.split("\n", 1)[1],  # no header (an older version's file)
        lambda text: "# lagrangian code cache: sha256=" + "0" * 64 + "\nraise SystemExit(3)\n",
        lambda text: "\udcff",  # not UTF-8
    ],
)
def test_a_damaged_or_edited_entry_is_rebuilt_never_run(cache, monkeypatch, damage):
    digest = _digest("X = 1\n")
    code_cache.load_text(digest, "X = 1\n")
    path = cache / f"{digest}.py"
    text = path.read_text()
    path.write_bytes(damage(text).encode("utf-8", "surrogateescape"))
    monkeypatch.setattr(code_cache, "_MODULES", {})  # as a new process would
    assert code_cache.load_text(digest, "X = 1\n").X == 1
    assert path.read_text() == text


def test_an_intact_entry_is_kept_as_it_is(cache, monkeypatch):
    digest = _digest("X = 1\n")
    code_cache.load_text(digest, "X = 1\n")
    path = cache / f"{digest}.py"
    os.utime(path, ns=(0, 0))
    monkeypatch.setattr(code_cache, "_MODULES", {})
    assert code_cache.load_text(digest, "X = 1\n").X == 1
    assert path.stat().st_mtime_ns == 0  # not written again: numba's files stay usable


def test_a_replanted_module_with_a_recomputed_digest_is_never_run(cache, monkeypatch, tmp_path):
    digest = _digest("X = 1\n")
    code_cache.load_text(digest, "X = 1\n")
    marker = tmp_path / "marker"
    body = f"open({str(marker)!r}, 'w').close()\nX = 1\n"
    path = cache / f"{digest}.py"
    path.write_text("# lagrangian code cache: sha256=" + _digest(body) + "\n" + body)
    monkeypatch.setattr(code_cache, "_MODULES", {})  # as a new process would
    assert code_cache.load_text(digest, "X = 1\n").X == 1
    assert not marker.exists()
    assert "marker" not in path.read_text()  # replaced by the generated text


def test_the_cache_folder_is_private(cache):
    code_cache.load_text(_digest("X = 1\n"), "X = 1\n")
    assert cache.stat().st_mode & 0o777 == 0o700


@pytest.mark.parametrize("danger", ["mode-0777", "mode-0775", "foreign-owner"])
def test_a_folder_others_can_write_or_own_is_not_used(cache, danger):
    digest = _digest("X = 1\n")
    code_cache.load_text(digest, "X = 1\n")
    code_cache._CHOSEN.clear()
    code_cache._MODULES.clear()
    if danger == "foreign-owner":
        if os.geteuid() != 0:
            pytest.skip("changing a folder's owner needs root")
        os.chown(cache, 12345, 12345)
        expected = r"it is owned by another user \(uid 12345\)"
    else:
        cache.chmod(int(danger[-4:], 8))
        expected = rf"others may write to it \(mode {danger[-4:]}\)"
    with pytest.warns(CacheWarning, match=rf"cache/numba cannot be used \({expected}\)"):
        module = code_cache.load_text(digest, "X = 1\n")
    assert module.X == 1
    assert not module.__file__.startswith(str(cache))


def test_numba_files_others_can_write_are_forgotten(cache, monkeypatch):
    digest = _digest("X = 1\n")
    code_cache.load_text(digest, "X = 1\n")
    files = [_numba_file(cache, digest, ".nbi"), _numba_file(cache, digest, ".1.nbc")]
    code_cache._list_numba_files()
    files[0].chmod(0o666)
    monkeypatch.setattr(code_cache, "_MODULES", {})
    code_cache.load_text(digest, "X = 1\n")
    assert not any(f.exists() for f in files)


def test_a_cache_path_through_a_file_falls_back_with_one_warning(tmp_path, cache):
    (tmp_path / "cache").write_text("a file")
    with pytest.warns(CacheWarning, match=r"cache/numba cannot be used \(not a directory\)"):
        module = code_cache.load_text(_digest("X = 1\n"), "X = 1\n")
    assert module.X == 1
    assert module.__file__.startswith(tempfile.gettempdir())
    assert oct(os.stat(os.path.dirname(module.__file__)).st_mode & 0o777) == "0o700"
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the second module: no second warning
        code_cache.load_text(_digest("Y = 2\n"), "Y = 2\n")


def test_a_read_only_cache_falls_back(cache, monkeypatch):
    cache.mkdir(parents=True)
    if os.geteuid() == 0:  # root writes anyway: refuse as the kernel would for a user

        def refuse(*args, **kwargs):
            raise PermissionError(13, "Permission denied")

        monkeypatch.setattr(tempfile, "TemporaryFile", refuse)
    else:
        cache.chmod(0o555)
    with pytest.warns(CacheWarning, match=r"cannot be used \(permission denied\)"):
        module = code_cache.load_text(_digest("X = 1\n"), "X = 1\n")
    cache.chmod(0o755)
    assert module.X == 1
    assert list(cache.iterdir()) == []


def _numba_file(cache, digest, suffix):
    folder = cache / "__pycache__"
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{digest}.f-4.py311{suffix}"
    path.write_bytes(os.urandom(64))
    return path


@pytest.mark.parametrize("manifest", ["none", "matching", "other"])
def test_numba_files_are_kept_only_when_the_exit_listing_vouches_for_them(
    cache, monkeypatch, manifest
):
    digest = _digest("X = 1\n")
    code_cache.load_text(digest, "X = 1\n")
    files = [_numba_file(cache, digest, ".nbi"), _numba_file(cache, digest, ".1.nbc")]
    if manifest != "none":
        code_cache._list_numba_files()  # what the exit of the run that compiled them writes
    if manifest == "other":
        files[1].write_bytes(os.urandom(64))  # damaged after that run
    monkeypatch.setattr(code_cache, "_MODULES", {})
    code_cache.load_text(digest, "X = 1\n")
    assert all(f.exists() for f in files) == (manifest == "matching")


_NUMBA_RUN = """
import sys
from lagrangian.codegen.cache import load_text
TEXT = "from numba import njit\\n\\n@njit(cache=True)\\ndef twice(x):\\n    return 2.0 * x\\n"
print(load_text("0123456789abcdef" * 4, TEXT).twice(1.5))
"""


@pytest.mark.slow
def test_a_damaged_numba_index_is_recompiled_not_a_crash(tmp_path):
    pytest.importorskip("numba")
    script = tmp_path / "run.py"
    script.write_text(textwrap.dedent(_NUMBA_RUN))
    environment = {**os.environ, "LAGRANGIAN_CACHE": str(tmp_path / "cache")}

    def run():
        return subprocess.run(
            [sys.executable, str(script)], env=environment, capture_output=True, text=True
        )

    assert run().stdout.strip() == "3.0"
    pycache = tmp_path / "cache" / "numba" / "__pycache__"
    index = list(pycache.glob("*.nbi"))
    assert index and list(pycache.glob("*.nbc"))
    for path in index:  # numba itself raises UnpicklingError on this, on every later run
        path.write_bytes(b"\x80\x04garbage")
    second = run()
    assert second.returncode == 0, second.stderr
    assert second.stdout.strip() == "3.0"
    assert run().stdout.strip() == "3.0"  # and the files numba wrote again are trusted


_TWICE = (
    "from numba import njit\n"
    "from lagrangian.codegen.numba_cache import tolerate_full_disk\n"
    "tolerate_full_disk()\n\n"
    "@njit(cache=True)\ndef twice(x):\n    return 2.0 * x\n"
)

_LOAD_TWICE = """
from lagrangian.codegen.cache import load_text
module = load_text({digest!r}, {text!r})
stats = module.twice(1.5), module.twice.stats
print(stats[0], sum(stats[1].cache_hits.values()), sum(stats[1].cache_misses.values()))
"""


@pytest.mark.slow
def test_machine_code_is_vouched_for_when_saved_so_a_process_beside_this_one_loads_it(cache):
    # a second pytest worker, a subprocess or a command run beside a long session: before,
    # the files were listed only at this process's exit, so every other process deleted
    # and compiled them again
    pytest.importorskip("numba")
    digest = _digest(_TWICE)
    module = code_cache.load_text(digest, _TWICE)
    assert module.twice(1.5) == 3.0  # compiled and saved by this process, which goes on
    assert (cache / f"{digest}.numba-sha256").read_text() == code_cache._listing(
        code_cache._numba_files(cache / f"{digest}.py")
    )
    script = _LOAD_TWICE.format(digest=digest, text=_TWICE)
    beside = subprocess.run(
        [sys.executable, "-c", script], env=dict(os.environ), capture_output=True, text=True
    )
    assert beside.returncode == 0, beside.stderr
    assert beside.stdout.split() == ["3.0", "1", "0"]  # loaded from disk, nothing compiled

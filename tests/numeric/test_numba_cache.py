"""numba's own machine-code cache on a full disk: a warning, never the end of the run."""

from __future__ import annotations

import errno

import pytest

pytest.importorskip("numba")

from numba.core import caching

from lagrangian.cli import ExitStatus, main


@pytest.mark.slow
def test_a_full_disk_while_numba_saves_its_code_is_a_warning(capsys, tmp_path, monkeypatch):
    def full(self, key, data):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(caching.IndexDataCacheFile, "save", full)
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(tmp_path / "cache"))  # nothing cached yet
    # a compiled rk4 run: the least machine code a run compiles (DOP853's method is 3x more)
    argv = ["simulate", "harmonic_oscillator", "--t-end", "0.5", "--method", "rk4", "--dt", "0.01"]
    status = main([*argv, "--backend", "numba"])
    captured = capsys.readouterr()
    assert status == ExitStatus.SUCCESS, captured.err
    assert "final state" in captured.out
    assert (
        "lagrangian: warning: numba could not keep its machine code on disk "
        "(No space left on device); it is compiled again next time"
    ) in captured.err


def test_other_errors_of_the_save_pass_through(monkeypatch):
    from lagrangian.codegen.numba_cache import tolerate_full_disk

    tolerate_full_disk()  # installs the wrapper

    def broken(self, sig, data):
        raise OSError(errno.EIO, "Input/output error")

    monkeypatch.setattr(caching.Cache, "_save_overload", broken)
    with pytest.raises(OSError, match="Input/output error"):
        caching.Cache.save_overload(object.__new__(caching.Cache), "sig", "data")

"""`lagrangian.files`: atomic writes (failure, signals, permissions) and one-line path errors."""

from __future__ import annotations

import errno
import os
import signal
import stat
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from lagrangian.errors import FileError
from lagrangian.files import check_input_file, check_output_path, write_atomically


def _write_text(text: str):
    return lambda temporary: temporary.write_text(text)


class Boom(RuntimeError):
    pass


def test_a_write_replaces_the_target_and_leaves_nothing_else(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    assert write_atomically(target, _write_text("new")) == target
    assert target.read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_a_failing_writer_leaves_the_target_untouched_and_no_temporary(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")

    def half(temporary: Path) -> None:
        temporary.write_text("half of the ne")
        raise Boom

    with pytest.raises(Boom):
        write_atomically(target, half)
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_disk_full_is_one_line_and_leaves_nothing(tmp_path):
    target = tmp_path / "out.nc"
    target.write_text("old")

    def full(temporary: Path) -> None:
        with open(temporary, "w") as stream:
            stream.write("part")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    with pytest.raises(FileError, match=r"out\.nc: cannot write: no space left on the device"):
        write_atomically(target, full)
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.nc"]


def test_an_error_about_another_file_passes_through(tmp_path):
    def other(temporary: Path) -> None:
        (tmp_path / "missing" / "font.ttf").read_bytes()  # the writer's resource, not the output

    with pytest.raises(FileNotFoundError):
        write_atomically(tmp_path / "out.png", other)
    assert list(tmp_path.iterdir()) == []


def test_an_overwritten_file_keeps_its_permissions_and_a_new_one_gets_the_umask(tmp_path):
    target = tmp_path / "out.csv"
    target.write_text("old")
    target.chmod(0o640)
    write_atomically(target, _write_text("new"))
    assert stat.S_IMODE(target.stat().st_mode) == 0o640
    fresh = write_atomically(tmp_path / "fresh.csv", _write_text("x"))
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o666 & ~umask


def test_a_symbolic_link_is_written_through(tmp_path):
    real = tmp_path / "real.csv"
    real.write_text("old")
    (tmp_path / "link.csv").symlink_to(real)
    write_atomically(tmp_path / "link.csv", _write_text("new"))
    assert (tmp_path / "link.csv").is_symlink()
    assert real.read_text() == "new"


def test_a_long_name_that_fits_is_written(tmp_path):
    # the temporary name adds a random part: it must not push a legal name over NAME_MAX
    target = tmp_path / ("x" * 250 + ".csv")
    write_atomically(target, _write_text("ok"))
    assert target.read_text() == "ok"


@pytest.mark.parametrize(
    ("where", "message"),
    [
        ("missing/out.csv", r"missing/out\.csv: cannot write: the folder .*missing does not exist"),
        ("plain/out.csv", r"plain/out\.csv: cannot write: .*plain is not a folder"),
        ("plain/deeper/out.csv", r"cannot write: .*deeper is not a folder"),
        ("folder", r"folder: cannot write: it is a folder, not a file"),
        ("x" * 300 + ".csv", r"x+\.csv: cannot write: the file name is too long"),
        ("y" * 300 + "/out.csv", r"out\.csv: cannot write: the file name is too long"),
    ],
)
def test_output_path_problems_are_one_line(tmp_path, where, message):
    (tmp_path / "plain").write_text("a file")
    (tmp_path / "folder").mkdir()
    with pytest.raises(FileError, match=message) as raised:
        write_atomically(tmp_path / where, _write_text("never"))
    assert "\n" not in str(raised.value)
    assert len(str(raised.value)) < 300  # a long path is shortened in the middle
    assert sorted(p.name for p in tmp_path.iterdir()) == ["folder", "plain"]


def test_a_read_only_folder_is_one_line(tmp_path, monkeypatch):
    folder = tmp_path / "ro"
    folder.mkdir()
    if os.geteuid() == 0:  # root writes anyway: refuse the create as the kernel would
        real_open = os.open

        def refuse(path, flags, *args, **kwargs):
            if str(path).startswith(str(folder)) and flags & os.O_CREAT:
                raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(path))
            return real_open(path, flags, *args, **kwargs)

        monkeypatch.setattr(os, "open", refuse)
    else:
        folder.chmod(0o555)
    with pytest.raises(FileError, match=r"ro/out\.csv: cannot write: permission denied"):
        write_atomically(folder / "out.csv", _write_text("never"))
    folder.chmod(0o755)
    assert list(folder.iterdir()) == []


def test_check_output_path_passes_a_plain_path(tmp_path):
    assert check_output_path(tmp_path / "a.csv") == tmp_path / "a.csv"


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (None, "no such file"),
        (lambda p: p.mkdir(), "is a folder, not a trajectory"),
        (lambda p: p.write_bytes(b""), "is empty, not a trajectory"),
        (lambda p: p.write_bytes(b"12345"), r"is too large to be read"),
    ],
)
def test_check_input_file(tmp_path, make, message):
    path = tmp_path / "in.nc"
    if make is not None:
        make(path)
    with pytest.raises(FileError, match=rf"in\.nc: {message}"):
        check_input_file(path, what="a trajectory file", max_bytes=4)


_BLOCKED_WRITER = """
import signal, sys, time
from pathlib import Path
from lagrangian.files import write_atomically

# the default dispositions, as a terminal gives them: under nohup (or a service manager)
# SIGHUP arrives ignored, and an ignored signal is left ignored (the test below)
for signum in (signal.SIGTERM, signal.SIGHUP):
    signal.signal(signum, signal.SIG_DFL)

def slow(temporary):
    with open(temporary, "w") as stream:
        stream.write("partial")
        stream.flush()
        print("writing", flush=True)
        time.sleep(60)  # the parent sends the signal now

write_atomically(Path(sys.argv[1]), slow)
print("finished", flush=True)
"""


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP])
def test_a_signal_during_a_write_removes_the_temporary_and_ends_the_process(tmp_path, signum):
    target = tmp_path / "out.csv"
    target.write_text("old")
    script = tmp_path / "writer.py"
    script.write_text(textwrap.dedent(_BLOCKED_WRITER))
    process = subprocess.Popen(
        [sys.executable, str(script), str(target)], stdout=subprocess.PIPE, text=True
    )
    try:
        assert process.stdout.readline().strip() == "writing"
        assert len(list(tmp_path.glob(".out.csv.*.tmp"))) == 1  # the write is under way
        process.send_signal(signum)
        status = process.wait(timeout=30)
    finally:
        process.kill()
    assert status == -signum  # ended by the signal, as without us
    assert process.stdout.read() == ""  # it did not go on after the write
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv", "writer.py"]


def test_an_ignored_hangup_stays_ignored_during_a_write(tmp_path):
    """Under nohup SIGHUP is ignored: the write installs no handler for it."""
    seen = {}

    def write(temporary):
        seen["during"] = signal.getsignal(signal.SIGHUP)
        temporary.write_text("x")

    previous = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    try:
        write_atomically(tmp_path / "a.txt", write)
        assert seen["during"] is signal.SIG_IGN
        assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGHUP, previous)


def test_handlers_are_restored_after_a_write(tmp_path):
    before = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGHUP)}
    write_atomically(tmp_path / "a.txt", _write_text("x"))
    with pytest.raises(Boom):
        write_atomically(tmp_path / "b.txt", lambda temporary: (_ for _ in ()).throw(Boom()))
    assert {s: signal.getsignal(s) for s in before} == before


def test_a_fifo_that_appears_during_the_write_is_not_replaced(tmp_path):
    # check_output_path ran before; the node appears while the content is written
    target = tmp_path / "out.csv"

    def write(temporary):
        temporary.write_text("data")
        os.mkfifo(target)

    with pytest.raises(FileError, match=r"out\.csv: cannot write: it is a FIFO"):
        write_atomically(target, write)
    assert stat.S_ISFIFO(os.stat(target).st_mode)
    assert sorted(path.name for path in tmp_path.iterdir()) == ["out.csv"]

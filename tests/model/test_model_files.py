"""Model files that are not files, too large, or made to slow the TOML reader: refused fast."""

from __future__ import annotations

import os
import signal
import socket

import pytest

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.model import limits, loads

SMALL = 'coordinates = ["x"]\nlagrangian = "x_dot**2/2"\n'


class Blocked(BaseException):
    """Raised by the alarm: not an Exception, so nothing under test can swallow it."""


@pytest.fixture
def deadline():
    """``with deadline(seconds):`` fails the test instead of hanging (a FIFO open blocks)."""

    def handler(signum, frame):
        raise Blocked

    previous = signal.signal(signal.SIGALRM, handler)

    class Deadline:
        def __init__(self, seconds: float):
            self.seconds = seconds

        def __enter__(self):
            signal.setitimer(signal.ITIMER_REAL, self.seconds)

        def __exit__(self, *exc):
            signal.setitimer(signal.ITIMER_REAL, 0)

    yield Deadline
    signal.setitimer(signal.ITIMER_REAL, 0)
    signal.signal(signal.SIGALRM, previous)


def refused(path, deadline) -> str:
    with deadline(5), pytest.raises(ModelError) as caught:
        lg.load(path)
    message = str(caught.value)
    assert str(path) in message and "\n" not in message
    return message


def test_a_fifo_is_refused_without_blocking(tmp_path, deadline):
    fifo = tmp_path / "model.toml"
    os.mkfifo(fifo)
    assert "is a named pipe (FIFO), not a model file" in refused(fifo, deadline)


def test_devices_folders_and_sockets_are_refused(tmp_path, deadline):
    assert "is a character device, not a model file" in refused("/dev/zero", deadline)
    assert "is a folder, not a model file" in refused(tmp_path, deadline)
    folder = tmp_path / "folder.toml"
    folder.mkdir()
    assert "is a folder" in refused(folder, deadline)
    path = tmp_path / "s.toml"
    with socket.socket(socket.AF_UNIX) as server:
        server.bind(str(path))
        assert "is a socket, not a model file" in refused(path, deadline)


def test_a_link_to_a_device_is_refused(tmp_path, deadline):
    link = tmp_path / "model.toml"
    link.symlink_to("/dev/zero")
    assert "is a character device" in refused(link, deadline)


def test_a_file_over_the_size_limit_is_refused_before_reading(tmp_path, deadline):
    big = tmp_path / "big.toml"
    with open(big, "wb") as file:
        file.truncate(limits.MAX_FILE_BYTES + 1)  # sparse: nothing to read if refused by size
    message = refused(big, deadline)
    assert f"file too large ({limits.MAX_FILE_BYTES + 1} bytes, limit 1048576 = 1 MiB)" in message
    with pytest.raises(ModelError, match="1048577 characters, limit 1048576"):
        loads(" " * (limits.MAX_FILE_BYTES + 1))


def test_a_file_of_bytes_that_are_not_utf8(tmp_path, deadline):
    path = tmp_path / "model.toml"
    path.write_bytes(b"coordinates = ['\xff']\n")
    assert "cannot read: not UTF-8 text" in refused(path, deadline)


HOSTILE_TOML = {
    "deep arrays": ("a = " + "[" * 10_000 + "]" * 10_000, "arrays or tables nested too deeply"),
    "deep inline tables": ("a = " + "{b=" * 5_000 + "1" + "}" * 5_000, "nested too deeply"),
    "long dotted key": (
        "parameters." + ".".join(["a"] * 100_000) + " = 1",
        "a dotted key of more than 32 parts (line 3)",
    ),
    "long quoted dotted key": (".".join(['"a"'] * 40) + " = 1", "more than 32 parts"),
    "escaped dotted key": ('"\\u0041".' + ".".join(["a"] * 40) + " = 1", "more than 32 parts"),
    "spaced dotted key": (" . ".join(["a"] * 40) + " = 1", "more than 32 parts"),
    "long table header": ("[" + ".".join(["a"] * 40) + "]", "more than 32 parts"),
    "50,000 coordinates": (None, "coordinates: too many (50000, limit 200)"),
    "5,000 parameters": (
        "[parameters]\n" + "".join(f"p{i} = 1\n" for i in range(5_000)),
        "parameters: too many (5000, limit 1000)",
    ),
    "1,000 particles": ('[[particles]]\nmass = 1\nposition = ["x", 0]\n' * 1_000, "particles"),
    "300 constraints": ("constraints = [" + '"x_dot",' * 300 + "]", "constraints: too many"),
}


@pytest.mark.parametrize("name", HOSTILE_TOML, ids=list(HOSTILE_TOML))
def test_hostile_toml_is_refused_fast(name, deadline):
    extra, message = HOSTILE_TOML[name]
    if extra is None:
        text = "coordinates = [" + ",".join(f'"q{i}"' for i in range(50_000)) + "]\n"
    else:
        text = SMALL + extra + "\n"
    with deadline(5), pytest.raises(ModelError) as caught:  # a hard stop, not a timing
        loads(text, source="hostile.toml")
    assert message in str(caught.value) and "hostile.toml" in str(caught.value)


def test_dotted_keys_up_to_the_limit_are_read():
    keys = ".".join(["a"] * limits.MAX_KEY_PARTS)
    with pytest.raises(ModelError, match="a: unknown key"):  # read, then refused by name
        loads(SMALL + keys + " = 1\n")
    text = SMALL + 'description = "' + ".".join(["word"] * 60) + '"\n'
    assert loads(text).description.startswith("word.word")  # a string value, not a key


def test_the_counts_hold_for_python_constructors_too():
    with pytest.raises(ModelError, match="coordinates: too many \\(201, limit 200\\)"):
        lg.System.from_lagrangian("q0_dot**2", coordinates=[f"q{i}" for i in range(201)])
    with pytest.raises(ModelError, match="expressions too long in all"):
        lg.System.from_lagrangian(
            "x_dot**2", coordinates=["x"], forces={"x": "+".join(["x"] * 9_000)},
            constraints=tuple("+".join(["x_dot"] * 3_000) for _ in range(12)),
        )  # fmt: skip


def test_an_error_quoting_a_huge_value_stays_one_short_line():
    text = SMALL + "[parameters]\nm = [" + ",".join(["1"] * 100_000) + "]\n"
    with pytest.raises(ModelError) as caught:
        loads(text, source="model.toml")
    message = str(caught.value)
    assert message.startswith("model.toml: parameters.m: expected a number, got [1, 1, ")
    assert len(message) < 400 and message.endswith("...")


def _particles(count: int, moving_with: int) -> str:
    """``count`` particles, each moving with the first ``moving_with`` of 200 coordinates."""
    names = [f"q{i}" for i in range(200)]
    text = "coordinates = [" + ",".join(f'"{q}"' for q in names) + "]\n[parameters]\nm = 1.0\n"
    x = "+".join(f"sin({q})" for q in names[:moving_with])
    return text + f'[[particles]]\nmass = "m"\nposition = ["{x}", "0"]\n' * count


def test_geometry_too_costly_to_assemble_is_refused_before_it_starts(deadline):
    with deadline(5), pytest.raises(ModelError) as caught:  # a hard stop, not a timing
        loads(_particles(10, 200), source="model.toml")  # 10 x 20,100 pairs
    assert str(caught.value) == (
        "model.toml: particles: kinetic energy too large to assemble: the particles and bodies "
        "couple 201000 pairs of velocities (limit 200000); give fewer points that each move "
        "with fewer coordinates"
    )
    assert loads(_particles(3, 20)).kinetic is not None  # 630 pairs

"""The same verdict on a busy machine (issue 22): budgets count CPU time, not waiting.

A busy machine makes a process wait for the CPU; here the process waits by
sleeping 4 ms after every millisecond of wall time (a SIGALRM sleeping 4),
as if four busy processes shared its core, and ``analyze`` must say exactly what
it says without the wait, with a budget that the waiting alone would exceed in
wall time.  No timing is asserted.  benchmarks/load.py runs the examples, the
README and the tutorial commands beside real busy processes.
"""

from __future__ import annotations

import contextlib
import json
import re
import signal
import time

import pytest

from helpers import timer_handler
from lagrangian.cli import ExitStatus, main


@contextlib.contextmanager
def busy_machine(share: float = 0.2, slice_seconds: float = 0.001):
    """While inside, the process sleeps (1 - share) of the wall time, in short slices."""
    pause = slice_seconds * (1 - share) / share

    def wait(signum, frame):
        time.sleep(pause)
        signal.setitimer(signal.ITIMER_REAL, slice_seconds)  # one shot: none while asleep

    with timer_handler(signal.ITIMER_REAL, signal.SIGALRM, wait, slice_seconds):
        yield


def _analyze(capsys, *argv: str) -> dict:
    capsys.readouterr()
    assert main(["analyze", *argv, "--json"]) == ExitStatus.SUCCESS
    return json.loads(capsys.readouterr().out)


def test_analyze_says_the_same_when_the_process_waits_four_fifths_of_the_time(capsys):
    # the oscillator's longest stage (equilibria) needs about 0.6 s of CPU: 2 s decide
    # all of them, where five times the wall time (waiting) would cut it on a wall clock
    quiet = _analyze(capsys, "harmonic_oscillator", "--timeout", "2")
    assert quiet["undecided"] == []
    with busy_machine():
        busy = _analyze(capsys, "harmonic_oscillator", "--timeout", "2")
    assert busy == quiet


#: Durations in the text output (a run's wall time), which may differ.
DURATION = re.compile(r"\b[0-9][0-9.]*(e[+-]?[0-9]+)? s\b")


@pytest.mark.parametrize(
    "argv",
    [
        ("derive", "rotating_wire_bead"),
        ("simulate", "cart_pole", "--set", "F=0.5", "--t-end", "2"),
        ("analyze", "simple_pendulum", "--timeout", "2"),
    ],
    ids=" ".join,
)
def test_a_command_prints_the_same_text_when_the_process_waits(capsys, argv):
    # the commands of the README and the tutorial, as benchmarks/load.py runs them beside
    # busy processes, here with the process waiting four fifths of the time instead
    outputs = []
    for waiting in (contextlib.nullcontext(), busy_machine()):
        capsys.readouterr()
        with waiting:
            assert main(list(argv)) == ExitStatus.SUCCESS
        outputs.append(DURATION.sub("* s", capsys.readouterr().out))
    assert outputs[1] == outputs[0]

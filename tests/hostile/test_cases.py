"""Every hostile CLI case ends with its expected status and one clear line, well within a deadline.

In-process (through :func:`lagrangian.cli.main`) so that the suite stays fast;
``benchmarks/hostile.py`` times the same cases as real processes.  The alarm
is a hard stop for a hang, not a timing assertion: the budget of each case is
its own (under 5 s measured as a process), the alarm only keeps a hang from
stalling the suite.
"""

from __future__ import annotations

import signal

import pytest

from helpers import slow_where
from hostile.case import all_cases
from lagrangian.cli import main

HANG_ALARM_S = 60


class Hung(Exception):
    pass


def _alarm(signum, frame):
    raise Hung


@pytest.mark.parametrize(
    "case",
    slow_where(all_cases(), lambda case: case.slow),
    ids=lambda case: case.name,
)
def test_hostile_case(case, tmp_path, capsys, monkeypatch):
    argv = case.prepare(tmp_path)
    for name, value in case.environment(tmp_path).items():
        monkeypatch.setenv(name, value)
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(HANG_ALARM_S)
    try:
        status = main(argv)
    except Hung:
        pytest.fail(f"{case.name}: still running after {HANG_ALARM_S} s")
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    captured = capsys.readouterr()
    case.check(int(status), captured.out, captured.err)


def test_case_files_are_isolated():
    # every case writes only into its own folder: nothing in argv points elsewhere by accident
    for case in all_cases():
        for argument in case.argv:
            assert not argument.startswith("/") or argument.startswith("/dev/"), case.name

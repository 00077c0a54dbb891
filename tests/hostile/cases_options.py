"""Command-line options checked as the library checks them: time budgets (--timeout),
assignment lists (--set, --at, --output, --momentum, --define) and the parameter values
they give (the model file's own sign and inertia checks)."""

import re

from hostile.case import HostileCase

TIMEOUT_REFUSED = r"Invalid value for '--timeout': must be a number of seconds > 0 and at most"

CASES = [
    *(
        HostileCase(
            f"{command[0]}-timeout-{value}-refused",
            (*command, "--timeout", value),
            error=TIMEOUT_REFUSED + rf".*not {re.escape(value)}$",
        )
        for command in (
            ("analyze", "simple_pendulum"),
            ("simulate", "simple_pendulum", "--t-end", "1"),
            ("ensemble", "simple_pendulum", "--grid", "theta=0:1:3", "--t-end", "1"),
            ("plot", "simple_pendulum", "--out", "{dir}/p.png"),
            ("animate", "simple_pendulum", "--out", "{dir}/a.gif"),
        )
        for value in ("nan", "inf", "-inf", "1e+09")
    ),
    HostileCase(
        # the stages' deadlines are due almost at once: each reported undecided, never a
        # traceback (an alarm firing before the guarded block escaped as exit 1)
        "analyze-timeout-1e-5-reports-undecided",
        ("analyze", "double_pendulum", "--timeout", "1e-5"),
        exit_code=0,
        output=r"not decided within 1e-05 s",
    ),
]

"""The command line: a thin shell over the library (no physics here).

``main(argv) -> ExitStatus`` runs in-process (tests call it directly);
``run()`` is the console script.  Exit status 0 on success, 2 on bad input
(one line on stderr naming the problem), 1 on an internal error.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from enum import IntEnum

import click

from ..errors import LagrangianError
from .app import app


class ExitStatus(IntEnum):
    SUCCESS = 0
    INTERNAL_ERROR = 1
    BAD_INPUT = 2


def main(argv: Sequence[str] | None = None) -> ExitStatus:
    """Run the CLI on ``argv`` (default: ``sys.argv[1:]``) and return the exit status."""
    try:
        result = app.main(
            args=list(sys.argv[1:] if argv is None else argv),
            prog_name="lagrangian",
            standalone_mode=False,
        )
    except LagrangianError as error:
        return _fail(ExitStatus.BAD_INPUT, str(error))
    except click.ClickException as error:
        return _fail(ExitStatus.BAD_INPUT, error.format_message())
    except click.Abort:
        return _fail(ExitStatus.INTERNAL_ERROR, "aborted")
    except Exception as error:  # a bug: say so on one line, traceback on request
        if os.environ.get("LAGRANGIAN_DEBUG"):
            raise
        return _fail(
            ExitStatus.INTERNAL_ERROR,
            f"internal error: {type(error).__name__}: {error} (set LAGRANGIAN_DEBUG=1 for details)",
        )
    return (
        ExitStatus(result)
        if isinstance(result, int) and result in (0, 1, 2)
        else ExitStatus.SUCCESS
    )


def _fail(status: ExitStatus, message: str) -> ExitStatus:
    line = " ".join(message.split())
    print(f"lagrangian: error: {line}", file=sys.stderr)
    return status


def run() -> None:
    """Console-script entry point."""
    sys.exit(int(main()))

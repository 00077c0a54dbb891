"""The command line: a thin shell over the library (no physics here).

``main(argv) -> ExitStatus`` runs in-process (tests call it directly);
``run()`` is the console script.  Exit status 0 on success, 2 on bad input
(one line on stderr naming the problem), 1 on an internal error.

:mod:`.app` holds the click group, its shared options and the core commands;
:mod:`.basins`, :mod:`.chaos`, :mod:`.check`, :mod:`.ensemble`, :mod:`.export`, :mod:`.fit`,
:mod:`.orbits`, :mod:`.report`, :mod:`.sensitivity`, :mod:`.server` and :mod:`.visual` add
theirs to it when they are imported, here (never the other way round: ``lint-imports`` checks it).
"""

from __future__ import annotations

import os
import sys
import warnings
from collections.abc import Sequence
from enum import IntEnum

import click

from ..budget import OutOfTime
from ..errors import LagrangianError, LagrangianWarning, Spelled
from . import (  # noqa: F401  (each registers its commands)
    basins,
    chaos,
    check,
    ensemble,
    export,
    fit,
    orbits,
    report,
    sensitivity,
    server,
    visual,
)
from .app import FLAGS, app


class ExitStatus(IntEnum):
    SUCCESS = 0
    INTERNAL_ERROR = 1
    BAD_INPUT = 2


def main(argv: Sequence[str] | None = None) -> ExitStatus:
    """Run the CLI on ``argv`` (default: ``sys.argv[1:]``) and return the exit status.

    Warnings raised during the command are held back: on success our own
    (:class:`~lagrangian.errors.LagrangianWarning`) are printed, one line each,
    and other libraries' (NumPy's RuntimeWarning, xarray's, matplotlib's) only
    with ``LAGRANGIAN_DEBUG=1``; on failure only the error line is printed.
    """
    args = list(sys.argv[1:] if argv is None else argv)
    command = _command(args)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")  # each distinct warning once, ours included
        status = _run(args, command)
    if status == ExitStatus.SUCCESS:
        spelling = command_flags(command)
        _show_warnings(caught, spelling, debug=bool(os.environ.get("LAGRANGIAN_DEBUG")))
    return status


def _run(args: list[str], command: click.Command | None) -> ExitStatus:
    try:
        result = app.main(args=args, prog_name="lagrangian", standalone_mode=False)
    except LagrangianError as error:
        return _fail(ExitStatus.BAD_INPUT, error.spelled(command_flags(command)))
    except OutOfTime as error:  # a BaseException: a deadline no stage caught is the user's budget
        return _fail(ExitStatus.BAD_INPUT, f"{error} ({_more_time(command)})")
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


def _command(args: Sequence[str]) -> click.Command | None:
    """The command ``args`` run (the group's own options come before it and take no value)."""
    name = next((arg for arg in args if not arg.startswith("-")), None)
    return app.commands.get(name) if name is not None else None


def command_flags(command: click.Command | None) -> dict[str, str]:
    """How ``command`` spells the library's settings: the entries of :data:`FLAGS` whose
    option it has.  A setting it has no option for keeps its Python name, so that no
    message suggests an option the command does not have (``derive --timeout``)."""
    if command is None:
        return dict(FLAGS)
    options = {name for parameter in command.params for name in parameter.opts}
    return {key: flag for key, flag in FLAGS.items() if flag.split()[0] in options}


def _more_time(command: click.Command | None) -> str:
    if command is not None and "timeout" in command_flags(command):
        return "allow more time with --timeout SECONDS"
    name = f"lagrangian {command.name}" if command is not None else "this command"
    return f"{name} has no --timeout: the budgets of its stages are fixed"


def _show_warnings(
    caught: list[warnings.WarningMessage], spelling: dict[str, str], *, debug: bool
) -> None:
    """Ours as ``lagrangian: warning: ...`` (each text once); the rest only when debugging."""
    shown = set()
    for record in caught:
        ours = issubclass(record.category, LagrangianWarning)
        if not (ours or debug):
            continue
        message = record.message
        text = message.spelled(spelling) if isinstance(message, Spelled) else str(message)
        line = " ".join(text.split())
        if not ours:
            line = f"{record.category.__name__}: {line} ({record.filename}:{record.lineno})"
        if line not in shown:
            shown.add(line)
            print(f"lagrangian: warning: {line}", file=sys.stderr)


def _fail(status: ExitStatus, message: str) -> ExitStatus:
    line = " ".join(message.split())
    print(f"lagrangian: error: {line}", file=sys.stderr)
    return status


def run() -> None:
    """Console-script entry point."""
    sys.exit(int(main()))

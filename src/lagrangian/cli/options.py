"""What the commands share: options, the parsers of their values, the progress bar.

Used as ``options.choice(...)``, ``options.define``, ``options.assignments(values, system)``:
an option that two commands take is written once here, and its choices come from a registry
(:func:`choice`) so that the lists cannot drift.
"""

from __future__ import annotations

import contextlib
import json
import math
import sys
import time
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING

import click

from ..budget import RUN_SECONDS, checked_seconds

if TYPE_CHECKING:
    from ..ensemble.members import GridAxis
    from ..model.system import System

#: --define NAME=EXPR, read by :func:`definitions` (simulate, ensemble).
define = click.option(
    "--define",
    "definitions",
    multiple=True,
    metavar="NAME=EXPR",
    help="Define an unspecified function of the model, e.g. V='x^2 + y^2' (repeatable).",
)


def checked_timeout(value: float) -> float:
    """A --timeout checked by the library's own rule (:func:`lagrangian.budget.checked_seconds`):
    NaN, infinity (which would switch the budget off), 0 or over a week is a usage error."""
    from ..errors import ModelError

    try:
        return checked_seconds(value, "timeout")
    except ModelError as error:
        raise click.BadParameter(error.message) from None


def seconds(default: float, help: str):
    """--timeout SECONDS with its check (a usage error) and its default shown."""
    return click.option(
        "--timeout",
        type=float,
        callback=lambda ctx, param, value: checked_timeout(value),
        metavar="SECONDS",
        default=default,
        show_default=True,
        help=help,
    )


#: --timeout of every command that runs an integration (simulate, ensemble, plot, animate).
timeout = seconds(
    RUN_SECONDS,
    "CPU seconds the runs may take (wall seconds on a GPU or dask; > 0, at most a week); "
    "a run whose pace shows it would take longer is stopped at once.",
)


def run_methods() -> Iterable[str]:
    """The integrators of a single run (their registry is imported when the names are
    read: a command that runs nothing loads no integrator)."""
    from ..integrate.registry import METHODS

    return METHODS


def run_backends() -> list[str]:
    """The compiled code a single run may use (read, like :func:`run_methods`, on use)."""
    from ..numeric.compile import RUN_BACKENDS

    return sorted(RUN_BACKENDS)


def ensemble_choices(name: str) -> Callable[[], Iterable[str]]:
    """The ensemble's choices ``name`` (``BACKENDS``, ``METHODS``, ``PRECISIONS`` of
    :mod:`lagrangian.ensemble.choices`), read on use like :func:`run_methods`."""

    def names() -> Iterable[str]:
        from ..ensemble import choices

        return getattr(choices, name)

    return names


def export_languages() -> Iterable[str]:
    """The languages ``export --to`` writes (read on use, like :func:`run_methods`)."""
    from ..export import LANGUAGES

    return LANGUAGES


class RegistryChoice(click.Choice):
    """One of the names of a registry, read each time they are needed (parsing, --help),
    not when the command is defined: a registry extended after the import (a test's
    target, a plugin's method) is offered at once."""

    def __init__(self, names: Callable[[], Iterable[str]]) -> None:
        self._names = names  # click.Choice.__init__ would freeze them into a tuple
        self.case_sensitive = True

    @property
    def choices(self) -> tuple[str, ...]:
        return tuple(self._names())


def choice(flag: str, choices, help: str, *, dest: str | None = None, **options):
    """``flag`` taking one of ``choices``: the names of a registry (a mapping or a sequence,
    or a function returning it, read when the command runs), so that the list cannot
    drift; a default, when given, is shown in --help."""
    names = choices if callable(choices) else lambda: choices
    return click.option(
        flag, *((dest,) if dest else ()), type=RegistryChoice(names), help=help,
        show_default=options.get("default") is not None, **options,
    )  # fmt: skip


def out(help: str):
    """--out FILE (a file, not a folder; the command checks its suffix)."""
    return click.option("--out", type=click.Path(dir_okay=False), help=help)


def required(flag: str, metavar: str, help: str, *, dest: str | None = None):
    """``flag`` that must be given, its value shown as ``metavar`` in --help."""
    return click.option(
        flag, *((dest,) if dest else ()), required=True, metavar=metavar, help=help
    )  # fmt: skip


def repeated(flag: str, dest: str, metavar: str, help: str, *, required: bool = False):
    """``flag`` given any number of times, its values collected in ``dest`` (a tuple)."""
    return click.option(
        flag, dest, multiple=True, required=required, metavar=metavar, help=help
    )  # fmt: skip


def number(flag: str, help: str):
    """``flag`` taking a float (--t-end, --dt, ...); left out: None, the library's default."""
    return click.option(flag, type=float, help=help)


def tolerances(rtol: str, atol: str):
    """--rtol and --atol of an adaptive integration, with their help texts."""

    def add(command):
        return number("--rtol", rtol)(number("--atol", atol)(command))

    return add


def as_json(help: str = "Print the result as JSON."):
    """--json, the flag ``as_json`` (see :func:`echo_json`)."""
    return click.option("--json", "as_json", is_flag=True, help=help)


def echo_json(document: dict, as_json: bool) -> bool:
    """Print ``document`` as JSON when --json was given; whether it was (the command then
    prints nothing else)."""
    if as_json:
        click.echo(json.dumps(document, indent=2))
    return as_json


def set_values(help: str = "A parameter value or an initial coordinate / velocity (repeatable)."):
    """--set NAME=VALUE, repeatable (parsed by :func:`assignments`)."""
    return click.option("--set", "assignments", multiple=True, metavar="NAME=VALUE", help=help)


def pairs(values: tuple[str, ...], hint: str, metavar: str = "NAME=EXPR") -> dict[str, str]:
    """The NAME=TEXT items of a repeatable option (--set, --define, --at, --output,
    --momentum, --grid), in order; the one parser of them all.

    A malformed item, or a name given twice (which would keep the last silently), is a
    usage error naming it.  The text is read later: by ``float`` or by the safe parser.
    """
    result: dict[str, str] = {}
    for item in values:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name or not text.strip():
            raise click.BadParameter(f"expected {metavar}, got {item!r}", param_hint=hint)
        if name in result:
            raise click.BadParameter(f"'{name}' is given twice", param_hint=hint)
        result[name] = text
    return result


def numbers(pairs: dict[str, str], hint: str) -> dict[str, float]:
    """NAME=VALUE pairs with plain numbers (read by float, never evaluated)."""
    numbers = {}
    for name, text in pairs.items():
        try:
            numbers[name] = float(text)
        except ValueError:
            raise click.BadParameter(
                f"expected NAME=NUMBER, got {f'{name}={text}'!r}", param_hint=hint
            ) from None
    return numbers


def check_width(name: str, low: float, high: float, hint: str) -> None:
    """A usage error where LO to HI of ``name`` (--grid, --spread, --vary) is too wide for
    a float: +-1e308 would make every value between nan."""
    if not math.isfinite(high - low):
        raise click.BadParameter(
            f"'{name}' from {low:g} to {high:g}: the range's width overflows", param_hint=hint
        )


@contextlib.contextmanager
def progress_bar(*, enabled: bool):
    """A progress bar on stderr for runs longer than a second, only on a terminal.

    Yields the callback for :func:`~lagrangian.simulation.simulate_system`
    (``None`` when piped, with ``--json``, or off a terminal).
    """
    stream = sys.stderr
    if not enabled or not stream.isatty():
        yield None
        return
    start = time.monotonic()
    state = {"bar": None, "shown": 0}

    def progress(fraction: float) -> None:
        if state["bar"] is None:
            if time.monotonic() - start < 1.0:
                return
            state["bar"] = click.progressbar(length=1000, label="simulating", file=stream)
            state["bar"].__enter__()
        step = int(1000 * fraction) - state["shown"]
        if step > 0:
            state["bar"].update(step)
            state["shown"] += step

    try:
        yield progress
    finally:
        if state["bar"] is not None:
            state["bar"].__exit__(None, None, None)


def assignments(values: tuple[str, ...], system: System) -> tuple[System, dict[str, float]]:
    """NAME=VALUE pairs of --set as numbers in SI units, with the system they are for.

    A value may carry a unit (``l=50cm``, ``g=32.2ft/s^2``): it is converted, and refused
    unless it has the name's dimension; a bare number is in the unit the model declares
    for the name (:func:`lagrangian.model.units.values_given`).  A unit given to a model
    without units makes it dimensioned: the system returned is then that model, checked.
    A value that is neither is a usage error naming it.
    """
    return given_values(pairs(values, "--set", "NAME=NUMBER"), system, "--set")


def given_values(
    texts: dict[str, str], system: System, hint: str
) -> tuple[System, dict[str, float]]:
    """NAME=VALUE texts of ``hint`` (--set, --grid) as numbers in SI, as :func:`assignments`."""
    from ..model.quantities import has_unit
    from ..model.units import values_given

    numbers({name: text for name, text in texts.items() if not has_unit(text)}, hint)
    return values_given(system, texts, hint)


def operating_point(texts: dict[str, str], system: System) -> tuple[System, dict[str, str]]:
    """NAME=EXPR of --at with their units: a number with a unit (``theta=90deg``) is
    converted to SI and a bare number is in the unit declared for the name, as for --set;
    an expression (``theta=pi``) is read as written, in SI units."""
    from ..model.quantities import has_unit

    numeric = {}
    for name, text in texts.items():
        with contextlib.suppress(ValueError):
            float(text)
            numeric[name] = text
        if has_unit(text):
            numeric[name] = text
    from ..model.units import exact_text

    system, _ = given_values(numeric, system, "--at")  # checked against the model's units
    return system, {**texts, **{name: exact_text(system, name, numeric[name]) for name in numeric}}


def definitions(values: tuple[str, ...]) -> dict[str, str]:
    """NAME=EXPR pairs of --define (the expression is parsed later by the safe parser)."""
    return pairs(values, "--define")


def grid_axes(
    values: tuple[str, ...], system: System, option: str = "--grid"
) -> tuple[System, dict[str, GridAxis]]:
    """NAME=LO:HI:N of --grid, each on its own axis (a bad one: a usage error naming
    ``option``, the one the user typed: bifurcation's --vary too); the values are made
    only once the ensemble is known to fit in memory.

    LO and HI may carry units (``l=20cm:1m:50``), converted as --set's values are
    (:func:`given_values`): the system returned is dimensioned if they made it so.
    """
    from ..ensemble.members import GridAxis
    from ..model.quantities import has_unit

    specs: dict[str, tuple[str, str, int]] = {}
    for name, text in pairs(values, option, "NAME=LO:HI:N").items():
        parts = text.split(":")
        try:
            if len(parts) != 3:
                raise ValueError
            for part in parts[:2]:
                if not has_unit(part) and not math.isfinite(float(part)):
                    raise ValueError
            count = int(parts[2])
            if count < 1:
                raise ValueError
        except ValueError:
            raise click.BadParameter(
                f"expected NAME=LO:HI:N (N a whole number >= 1), got {f'{name}={text}'!r}",
                param_hint=option,
            ) from None
        specs[name] = (parts[0], parts[1], count)
    system, lows = given_values({n: s[0] for n, s in specs.items()}, system, option)
    system, highs = given_values({n: s[1] for n, s in specs.items()}, system, option)
    for name in specs:
        check_width(name, float(lows[name]), float(highs[name]), option)
    ndim = len(specs)
    return system, {
        name: GridAxis(lows[name], highs[name], count, axis, ndim)
        for axis, (name, (_, _, count)) in enumerate(specs.items())
    }


def check_outputs(out: str | None, suffixes: tuple[str, ...], picture: str | None) -> None:
    """Usage errors, before any run, for an --out without one of ``suffixes`` or a --plot
    that is not a .png, and for either where it cannot be written."""
    if out is not None and not out.endswith(suffixes):
        raise click.BadParameter(
            f"the output file must end in {' or '.join(suffixes)}", param_hint="--out"
        )
    if out is not None:
        from ..files import check_output_path

        check_output_path(out)
    check_png(picture, "--plot")


def wrote(*paths: str | None) -> None:
    """A line "wrote PATH" for each file written (None: not asked for)."""
    for path in paths:
        if path is not None:
            click.echo(f"wrote {path}")


def check_png(path: str | None, hint: str) -> None:
    """A usage error unless ``path`` (when given) is a PNG file that can be written."""
    if path is None:
        return
    if not path.endswith(".png"):
        raise click.BadParameter("the picture must be a .png file", param_hint=hint)
    from ..files import check_output_path

    check_output_path(path)  # before the run: a typo fails at once

"""``lagrangian orbits``: the periodic orbits of a strobe map (registered on ``app``)."""

from __future__ import annotations

import click

from . import options
from .app import MODEL_HELP, app
from .chaos import _one_section, backend_option, phase_option, section_options


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@click.option(
    "--strobe",
    type=float,
    metavar="PERIOD",
    help="The drive's period: the map from t to t + PERIOD.",
)
@phase_option
@section_options
@click.option("--energy", type=float, help="With --section: the energy shell of the orbits.")
@click.option(
    "--t-end", type=float, help="With --section: how long the returns are looked for (default: "
    "the model's t_end).",
)  # fmt: skip
@click.option(
    "--period",
    type=int,
    default=1,
    show_default=True,
    help="K: the orbits of the K-fold map (each at its least period, a divisor of K); with "
    "--section, of at most K returns.",
)
@options.repeated(
    "--grid",
    "grids",
    "NAME=LO:HI:N",
    "Start Newton's method from N values of NAME from LO to HI (repeatable: all "
    "combinations; the other values from the initial state).",
)
@click.option(
    "--starts",
    "attractor",
    type=int,
    default=20,
    show_default=True,
    help="Also start from this many strobe points of the motion from the initial state "
    "after --transient (on its attractor); with --section, this many starts spread over "
    "the energy shell.",
)
@click.option("--transient", type=float, help="Time before those points (default 50 periods).")
@options.tolerances("Relative tolerance (default 1e-11).", "Absolute tolerance (default 1e-12).")
@click.option(
    "--vary",
    metavar="NAME=LO:HI:N",
    help="Follow each orbit found at NAME = LO to HI by pseudo-arclength continuation (steps "
    "of at most (HI - LO)/(N - 1)): its branch, bifurcations and doubled branches.",
)
@click.option(
    "--max-doublings",
    type=click.IntRange(0, 8),
    default=3,
    show_default=True,
    help="With --vary: how many period doublings to follow.",
)
@click.option(
    "--axis",
    "variable",
    metavar="NAME",
    help="With --vary: the coordinate or velocity drawn (default: the first velocity).",
)
@click.option(
    "--out",
    "outputs",
    multiple=True,
    type=click.Path(dir_okay=False),
    help="With --vary: draw the branches to F.png, or write them to F.csv (repeatable).",
)
@click.option(
    "--no-background",
    is_flag=True,
    help="With --vary: draw the branches without the brute-force bifurcation diagram.",
)
@options.set_values()
@options.define
@backend_option
@options.as_json()
@options.timeout
def orbits(
    model, strobe, phase, section, direction, energy, t_end, period, grids, attractor,
    transient, rtol, atol, vary, max_doublings, variable, outputs, no_background, assignments,
    definitions, backend, as_json, timeout,
) -> None:  # fmt: skip
    """Periodic orbits of MODEL's strobe map (or through --section on the --energy shell
    of an autonomous MODEL), by Newton's method with the monodromy matrix: their points,
    Floquet multipliers, stability and kind; with --vary, followed in a parameter."""
    from ..facade import load
    from ..output.orbits import orbits_json, orbits_text
    from ..simulation import orbits_of_system

    _one_section(section, strobe, phase)
    if section is not None and (grids or transient is not None):
        raise click.BadParameter("--grid and --transient go with --strobe", param_hint="--section")
    if section is not None and vary is not None:
        raise click.BadParameter("--vary goes with --strobe", param_hint="--section")
    if strobe is not None and (energy is not None or t_end is not None):
        raise click.BadParameter("--energy and --t-end go with --section", param_hint="--strobe")
    given = {
        "--out": bool(outputs),
        "--axis": variable is not None,
        "--no-background": no_background,
    }
    for flag in (flag for flag, used in given.items() if used and vary is None):
        raise click.BadParameter(f"{flag} goes with --vary", param_hint=flag)
    system = load(model)
    grid = {}
    if grids:
        system, grid = options.grid_axes(grids, system, "--grid")
    if vary is not None:
        system, varied = _varied(vary, system)
        _continued(
            system, varied, strobe=strobe, phase=phase, period=period, grid=grid,
            attractor=attractor, transient=transient, rtol=rtol, atol=atol,
            max_doublings=max_doublings, variable=variable, outputs=outputs,
            background=not no_background, assignments=assignments, definitions=definitions,
            backend=backend, as_json=as_json, timeout=timeout,
        )  # fmt: skip
        return
    system, values = options.assignments(assignments, system)
    with options.progress_bar(enabled=not as_json) as progress:
        search = orbits_of_system(
            system, strobe=strobe, period=period, phase=phase, section=section,
            direction=direction, energy=energy, t_end=t_end, grid=grid, attractor=attractor,
            transient=transient, rtol=rtol, atol=atol, assignments=values, progress=progress,
            definitions=options.definitions(definitions), backend=backend, timeout=timeout,
        )  # fmt: skip
    if options.echo_json(orbits_json(search), as_json):
        return
    click.echo(orbits_text(search))


#: The brute-force diagram behind the drawn branches: its transient (in strobe periods),
#: its points per value, and at least this many values (the continuation's N if more).
BACKGROUND_PERIODS, BACKGROUND_SAMPLES, BACKGROUND_VALUES = 300, 40, 200


def _varied(text: str, system):
    """(the system, {name: (low, high, count)}) from --vary NAME=LO:HI:N: a usage error
    naming the problem (not a parameter, LO >= HI, N < 2); LO and HI may carry units."""
    ((name, spec),) = options.pairs((text,), "--vary", "NAME=LO:HI:N").items()
    parts = spec.split(":")
    if len(parts) != 3:
        raise click.BadParameter(f"expected NAME=LO:HI:N, got {text!r}", param_hint="--vary")
    names = [parameter.name for parameter in system.parameters]
    if name not in names:
        raise click.BadParameter(
            f"'{name}' is not a parameter of the model (parameters: {', '.join(names) or 'none'})",
            param_hint="--vary",
        )
    try:
        count = int(parts[2])
    except ValueError:
        count = 0
    if count < 2:
        raise click.BadParameter(
            f"N must be a whole number >= 2 (the number of values of {name} the steps are "
            f"sized by), got {parts[2]!r}",
            param_hint="--vary",
        )
    system, lows = options.given_values({name: parts[0]}, system, "--vary")
    system, highs = options.given_values({name: parts[1]}, system, "--vary")
    low, high = float(lows[name]), float(highs[name])
    if not low < high:
        raise click.BadParameter(
            f"'{name}' from {low:g} to {high:g}: LO must be below HI", param_hint="--vary"
        )
    return system, {name: (low, high, count)}


def _continued(
    system, varied, *, strobe, phase, period, grid, attractor, transient, rtol, atol,
    max_doublings, variable, outputs, background, assignments, definitions, backend, as_json,
    timeout,
) -> None:  # fmt: skip
    """--vary: the branches followed, as text or JSON, drawn or written to --out."""
    from ..output.continuation import (
        continuation_json,
        continuation_text,
        plot_continuation,
        write_continuation_csv,
    )
    from ..simulation import continuation_of_system

    if strobe is None:
        raise click.BadParameter("--vary follows the orbits of a --strobe", param_hint="--vary")
    for path in outputs:
        if path.endswith(".png"):
            options.check_png(path, "--out")
        elif path.endswith(".csv"):
            from ..files import check_output_path

            check_output_path(path)
        else:
            raise click.BadParameter("the output file must end in .png or .csv", param_hint="--out")
    coordinates = [coordinate.name for coordinate in system.coordinates]
    names = [*coordinates, *(f"{q}_dot" for q in coordinates)]
    variable = f"{coordinates[0]}_dot" if variable is None else variable
    if variable not in names:
        raise click.BadParameter(
            f"'{variable}' is not a coordinate or velocity ({', '.join(names)})",
            param_hint="--axis",
        )
    system, values = options.assignments(assignments, system)
    with options.progress_bar(enabled=not as_json) as progress:
        result = continuation_of_system(
            system, vary=varied, strobe=strobe, phase=phase, period=period, grid=grid,
            attractor=attractor, transient=transient, rtol=rtol, atol=atol,
            max_doublings=max_doublings, assignments=values, progress=progress,
            definitions=options.definitions(definitions), backend=backend, timeout=timeout,
        )  # fmt: skip
    pictures = [path for path in outputs if path.endswith(".png")]
    diagram = None
    if pictures and background:
        diagram = _background(system, result, variable, values, definitions, timeout)
    for path in outputs:
        if path.endswith(".csv"):
            write_continuation_csv(result, path)
    if pictures:
        from ..output.plots import save_figure

        figure = plot_continuation(result, variable, diagram)
        for path in pictures:
            save_figure(figure, path, dpi=150)
    summary = continuation_json(result)
    if outputs:
        summary["out"] = list(outputs)
    if options.echo_json(summary, as_json):
        return
    click.echo(continuation_text(result))
    options.wrote(*outputs)


def _background(system, result, variable, assigned, definitions, timeout):
    """The brute-force bifurcation diagram over the continuation's range (its N values, at
    least BACKGROUND_VALUES), from the initial state, by the numba ensemble where numba is
    installed."""
    import numpy as np

    from ..ensemble import bifurcation_of_system
    from ..integrate.compiled_dop853 import numba_installed
    from ..simulation import split_assignments

    initial, params = split_assignments(system, assigned)
    count = max(result.settings["values"], BACKGROUND_VALUES)
    return bifurcation_of_system(
        system, vary={result.parameter: np.linspace(result.low, result.high, count)},
        variable=variable, period=result.strobe.period, phase=result.strobe.phase,
        transient=BACKGROUND_PERIODS * result.strobe.period, samples=BACKGROUND_SAMPLES,
        initial=initial, params=params, backend="numba" if numba_installed() else "numpy",
        definitions=options.definitions(definitions), timeout=timeout,
    )  # fmt: skip

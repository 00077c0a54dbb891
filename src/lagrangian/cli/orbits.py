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
@options.set_values()
@options.define
@backend_option
@options.as_json()
@options.timeout
def orbits(
    model, strobe, phase, section, direction, energy, t_end, period, grids, attractor,
    transient, rtol, atol, assignments, definitions, backend, as_json, timeout,
) -> None:  # fmt: skip
    """Periodic orbits of MODEL's strobe map (or through --section on the --energy shell
    of an autonomous MODEL), by Newton's method with the monodromy matrix: their points,
    Floquet multipliers, stability and kind."""
    from ..facade import load
    from ..output.orbits import orbits_json, orbits_text
    from ..simulation import orbits_of_system
    from .ensemble import _grids

    _one_section(section, strobe, phase)
    if section is not None and (grids or transient is not None):
        raise click.BadParameter("--grid and --transient go with --strobe", param_hint="--section")
    if strobe is not None and (energy is not None or t_end is not None):
        raise click.BadParameter("--energy and --t-end go with --section", param_hint="--strobe")
    system = load(model)
    grid = {}
    if grids:
        system, grid = _grids(grids, system, "--grid")
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

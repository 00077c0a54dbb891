"""``lagrangian basins``: the basins of attraction of a strobe map or a sampled flow
(registered on ``app``)."""

from __future__ import annotations

import click

from . import options
from .app import MODEL_HELP, app
from .chaos import phase_option, phase_with_strobe


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.repeated(
    "--grid",
    "grids",
    "NAME=LO:HI:N",
    "N starts from LO to HI of a coordinate or velocity; one for each (the box of the cells too).",
    required=True,
)
@click.option("--strobe", type=float, metavar="PERIOD", help="The drive's period: the map "
              "from t to t + PERIOD.")  # fmt: skip
@phase_option
@click.option(
    "--interval",
    type=float,
    metavar="DT",
    help="Without --strobe (an autonomous model): the flow sampled every DT is the map "
    "(default: the model's t_end / 100).",
)
@click.option("--steps", type=int, default=100, show_default=True, help="rk4 steps per iteration.")
@click.option(
    "--cells", type=int, default=250, show_default=True,
    help="The most cells of the recurrence grid along each variable.",
)  # fmt: skip
@click.option(
    "--max-iterations", type=int, default=2000, show_default=True,
    help="Iterations after which a start that reached nothing gets -1.",
)  # fmt: skip
@click.option(
    "--basin-hits", type=int, default=5, show_default=True,
    help="Iterations in a row in cells of one attractor's basin (cells only its starts "
    "passed) that label a start with it (fewer can be faster).",
)  # fmt: skip
@options.choice(
    "--backend",
    lambda: _backends(),
    "Where the starts are integrated (jax: the same rk4 steps on JAX's device, a GPU "
    "where JAX has one; the labelling stays on numba).",
    default="numba",
)
@options.out("Write F.csv (the grid and an attractor column), F.nc or a map F.png.")
@options.set_values("A parameter value (repeatable).")
@options.define
@options.as_json()
@options.timeout
def basins(
    model, grids, strobe, phase, interval, steps, cells, max_iterations, basin_hits, backend,
    out, assignments, definitions, as_json, timeout,
) -> None:  # fmt: skip
    """Basins of attraction of MODEL: each start of the grid labelled by the attractor of
    the strobe map (or of the flow sampled every --interval) it reaches, found by
    recurrence on a grid of cells; the attractors listed (fixed point, period K, chaotic)."""
    from ..ensemble.system import basins_of_system
    from ..facade import load
    from ..output.basins import basins_json, basins_text
    from ..simulation import split_assignments

    options.check_outputs(out, (".csv", ".nc", ".png"), None)
    phase_with_strobe(strobe, phase)
    if strobe is not None and interval is not None:
        raise click.BadParameter("give --strobe or --interval, not both", param_hint="--interval")
    system, grid = options.grid_axes(grids, load(model), "--grid")
    system, given = options.assignments(assignments, system)
    initial, params = split_assignments(system, given)
    if initial:
        name = next(iter(initial))
        raise click.BadParameter(
            f"'{name}' is a coordinate or velocity: its values come from --grid",
            param_hint="--set",
        )
    if len(grid) != 2 and out is not None and out.endswith(".png"):
        raise click.BadParameter("a basin map picture needs two --grid", param_hint="--out")
    with options.progress_bar(enabled=not as_json) as progress:
        result = basins_of_system(
            system, grid=grid, period=strobe, phase=phase, interval=interval, params=params,
            steps=steps, cells=cells, max_iterations=max_iterations, basin_hits=basin_hits,
            backend=backend, definitions=options.definitions(definitions), timeout=timeout,
            progress=progress,
        )  # fmt: skip
    if out is not None:
        _write(result, out)
    document = {**basins_json(result), **({"out": out} if out is not None else {})}
    if options.echo_json(document, as_json):
        return
    click.echo(basins_text(result))
    options.wrote(out)


def _backends() -> tuple[str, ...]:
    """Read when the command runs: the CLI stays light, the list cannot drift."""
    from ..ensemble.basins import BACKENDS

    return BACKENDS


def _write(result, out: str) -> None:
    if out.endswith(".csv"):
        result.to_csv(out)
    elif out.endswith(".nc"):
        result.to_netcdf(out)
    else:
        from ..output.basins import plot_basins
        from ..output.plots import save_figure

        save_figure(plot_basins(result), out, dpi=150)

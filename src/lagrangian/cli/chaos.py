"""The commands that measure chaos: ``lyapunov`` (registered on ``app``)."""

from __future__ import annotations

import json

import click

from ..numeric.compile import RUN_BACKENDS
from .app import (
    MODEL_HELP,
    _assignments,
    _definitions,
    _progress_bar,
    app,
    define_option,
    timeout_option,
)

#: --set NAME=VALUE of the chaos commands.
set_option = click.option(
    "--set",
    "assignments",
    multiple=True,
    metavar="NAME=VALUE",
    help="A parameter value or an initial coordinate / velocity (repeatable).",
)
backend_option = click.option(
    "--backend",
    type=click.Choice(sorted(RUN_BACKENDS)),
    default=None,
    help="Compiled code (default llvm where SymEngine has it, else numpy).",
)


def _png(path: str | None, hint: str) -> None:
    """A usage error unless ``path`` (when given) is a PNG file that can be written."""
    if path is None:
        return
    if not path.endswith(".png"):
        raise click.BadParameter("the picture must be a .png file", param_hint=hint)
    from ..files import check_output_path

    check_output_path(path)  # before the run: a typo fails at once


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@click.option("--t-end", type=float, help="Averaging time (default: the model's t_end).")
@click.option(
    "--transient",
    type=float,
    default=0.0,
    show_default=True,
    help="Time run first and not averaged (to settle on an attractor).",
)
@click.option("--count", type=int, help="How many exponents, largest first (default: all 2n).")
@click.option("--largest", is_flag=True, help="Only the largest exponent (--count 1).")
@click.option(
    "--interval",
    type=float,
    help="Time between re-orthonormalisations of the displacements (default 1).",
)
@click.option("--rtol", type=float, help="Relative tolerance (default 1e-9).")
@click.option("--atol", type=float, help="Absolute tolerance (default 1e-11).")
@set_option
@define_option
@backend_option
@click.option(
    "--plot",
    "picture",
    type=click.Path(dir_okay=False),
    help="Draw the convergence of the estimates to FILE.png.",
)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
@timeout_option
def lyapunov(
    model, t_end, transient, count, largest, interval, rtol, atol, assignments, definitions,
    backend, picture, as_json, timeout,
) -> None:  # fmt: skip
    """Lyapunov exponents of MODEL along its motion from the initial state (variational
    equations from the symbolic Jacobian, QR re-orthonormalisation)."""
    from ..facade import load
    from ..output.lyapunov import lyapunov_summary, lyapunov_text
    from ..simulation import lyapunov_of_system

    if largest and count not in (None, 1):
        raise click.BadParameter("--largest is --count 1", param_hint="--count")
    _png(picture, "--plot")
    system = load(model)
    with _progress_bar(enabled=not as_json) as progress:
        spectrum = lyapunov_of_system(
            system, t_end=t_end, count=1 if largest else count, transient=transient,
            interval=interval, rtol=rtol, atol=atol, assignments=_assignments(assignments),
            progress=progress, definitions=_definitions(definitions), backend=backend,
            timeout=timeout,
        )  # fmt: skip
    if picture is not None:
        from ..output.lyapunov import plot_lyapunov
        from ..output.plots import save_figure

        save_figure(plot_lyapunov(spectrum), picture, dpi=120)
    if as_json:
        summary = lyapunov_summary(spectrum)
        if picture is not None:
            summary["plot"] = picture
        click.echo(json.dumps(summary, indent=2))
        return
    click.echo(lyapunov_text(spectrum))
    if picture is not None:
        click.echo(f"wrote {picture}")

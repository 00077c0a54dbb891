"""``lagrangian sensitivity``: d(state)(t)/d(parameter or initial value) along one run
(the library's ``System.sensitivities``; registered on ``app``)."""

from __future__ import annotations

import click

from . import options
from .app import MODEL_HELP, app


def _names(text: str) -> list[str]:
    """NAME,NAME,... of --wrt; an empty entry is a usage error."""
    names = [name.strip() for name in text.split(",")]
    if not all(names):
        raise click.BadParameter(
            f"expected names separated by commas, got {text!r}", param_hint="--wrt"
        )
    return names


def _check_outputs(out: str | None, picture: str | None) -> None:
    """Usage errors, before the run, for an --out that is not .nc or .csv, a --plot that
    is not .png, and either where it cannot be written."""
    from ..files import check_output_path
    from ..output.sensitivity import SENSITIVITY_FORMATS

    if out is not None:
        if not out.lower().endswith(SENSITIVITY_FORMATS):
            raise click.BadParameter("the output file must end in .nc or .csv", param_hint="--out")
        check_output_path(out)
    if picture is not None:
        if not picture.lower().endswith(".png"):
            raise click.BadParameter("the picture must be a .png file", param_hint="--plot")
        check_output_path(picture)


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.required(
    "--wrt",
    "NAME,...",
    "Parameters, or coordinates / velocities for their initial values, to differentiate by.",
)
@options.number("--t-end", "End time (default: the model's t_end).")
@click.option(
    "--points", type=int, default=201, show_default=True, help="Output times from 0 to t_end."
)
@options.tolerances("Relative tolerance (default 1e-10).", "Absolute tolerance (default 1e-12).")
@options.set_values()
@options.define
@options.choice(
    "--backend",
    options.run_backends,
    "Compiled code (default llvm where SymEngine has it, else numpy; numba: the whole "
    "loop compiled, seconds to build once, then cached).",
)
@options.out("Write the motion and its sensitivities to FILE.nc or FILE.csv.")
@click.option(
    "--plot", "picture", type=click.Path(dir_okay=False), help="Draw d q / d w to FILE.png."
)
@options.as_json()
@options.timeout
def sensitivity(
    model, wrt, t_end, points, rtol, atol, assignments, definitions, backend, out, picture,
    as_json, timeout,
) -> None:  # fmt: skip
    """d(state)(t)/d(w) of MODEL along its run from the initial state, for each w in --wrt,
    from the forward sensitivity equations integrated with the motion."""
    from ..facade import load
    from ..output.sensitivity import sensitivity_summary, sensitivity_text

    names = _names(wrt)
    _check_outputs(out, picture)
    system, values = options.assignments(assignments, load(model))
    with options.progress_bar(enabled=not as_json) as progress:
        result = system.sensitivities(
            names, t_end=t_end, points=points, rtol=rtol, atol=atol, assignments=values,
            progress=progress, definitions=options.definitions(definitions), backend=backend,
            timeout=timeout,
        )  # fmt: skip
    if out is not None:
        from ..output.sensitivity import write_sensitivities

        write_sensitivities(result, out, system)
    if picture is not None:
        from ..output.plots import save_figure
        from ..output.sensitivity import plot_sensitivities

        save_figure(plot_sensitivities(result, system), picture, dpi=120)
    written = {key: path for key, path in (("out", out), ("plot", picture)) if path is not None}
    if options.echo_json({**sensitivity_summary(result, system), **written}, as_json):
        return
    click.echo(sensitivity_text(result, system))
    for path in written.values():
        click.echo(f"wrote {path}")

"""``lagrangian fit``: the parameters (and initial values) that fit a measured time series
(the library's ``System.fit``; registered on ``app``)."""

from __future__ import annotations

import click

from . import options
from .app import MODEL_HELP, app

DATA_HELP = (
    "DATA is a CSV file (a header naming the columns: t, then coordinates, velocities or "
    "--observe names, each optionally with a unit, 't [ms]', 'x [cm]') or a NetCDF file "
    "(a time coordinate t or time). Rows with an empty or NaN cell are dropped, and said "
    "on stderr."
)


def _vary(values: tuple[str, ...]) -> list[str]:
    """NAME[=GUESS],... of each --vary, in order; an empty entry is a usage error."""
    names = [name.strip() for value in values for name in value.split(",")]
    if not names or not all(names):
        raise click.BadParameter(
            f"expected NAME or NAME=GUESS separated by commas, got {','.join(values)!r}",
            param_hint="--vary",
        )
    return names


def _noise(text: str | None) -> float | dict[str, str] | None:
    """--noise SIGMA (a number) or NAME=SIGMA,... (the library checks the values)."""
    if text is None or "=" not in text:
        return text
    return options.pairs(tuple(text.split(",")), "--noise", "NAME=SIGMA")


def _check_picture(picture: str | None, residuals: bool) -> None:
    from ..files import check_output_path
    from ..output.plots import FIGURE_FORMATS

    if picture is None:
        if residuals:
            raise click.BadParameter(
                "give the picture's file with --out", param_hint="--plot-residuals"
            )
        return
    if not picture.lower().endswith(FIGURE_FORMATS):
        raise click.BadParameter(
            f"the picture must be a {', '.join(FIGURE_FORMATS)} file", param_hint="--out"
        )
    check_output_path(picture)


@app.command(epilog=f"{MODEL_HELP} {DATA_HELP}")
@click.argument("model")
@click.argument("data")
@options.repeated(
    "--vary",
    "vary",
    "NAME[=GUESS],...",
    "Parameters, or coordinates / velocities for their initial values, to fit (a start "
    "guess after '=', else the model's value; repeatable).",
    required=True,
)
@options.repeated(
    "--observe",
    "observe",
    "'NAME = EXPR'",
    "A measured expression of the coordinates, velocities, parameters and t, compared with "
    "the data's column NAME (repeatable).",
)
@click.option(
    "--starts", type=int, default=1, show_default=True,
    help="Starts of the search: the guesses, then random ones within a factor 3 of them.",
)  # fmt: skip
@click.option(
    "--noise", metavar="SIGMA|NAME=SIGMA,...",
    help="The measurements' standard deviation, one for all columns or one per column: "
    "a bare number in the unit the model declares for the column, or with a unit "
    "(0.3deg, x=2mm); weights the columns and gives chi^2 per degree of freedom.",
)  # fmt: skip
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the random starts.")
@options.tolerances("Relative tolerance (default 1e-9).", "Absolute tolerance (default 1e-11).")
@options.set_values()
@options.define
@options.choice(
    "--backend",
    options.run_backends,
    "Compiled code (default numba where installed: the sensitivity equations' compiled "
    "loop, seconds to build once, then cached).",
)
@options.out("Draw the data and the fit against t to FILE (.png, .pdf, .svg).")
@click.option(
    "--plot-residuals", "residuals", is_flag=True, help="Add the residuals below each panel."
)
@options.as_json()
@options.timeout
def fit(
    model, data, vary, observe, starts, noise, seed, rtol, atol, assignments, definitions,
    backend, out, residuals, as_json, timeout,
) -> None:  # fmt: skip
    """The values of the --vary names that make MODEL's motion fit the time series DATA
    (least squares with the sensitivity equations' exact Jacobian), with standard
    errors, correlations and warnings for what the data cannot tell apart."""
    from ..facade import load
    from ..output.fit import fit_summary, fit_text

    names = _vary(vary)
    noise = _noise(noise)
    _check_picture(out, residuals)
    system, values = options.assignments(assignments, load(model))
    result = system.fit(
        data, names, observe=list(observe), starts=starts, noise=noise, seed=seed, rtol=rtol,
        atol=atol, assignments=values, definitions=options.definitions(definitions),
        backend=backend, timeout=timeout,
    )  # fmt: skip
    if result.dropped:
        click.echo(result.warnings[0], err=True)
    if out is not None:
        from ..output.fit import plot_fit
        from ..output.plots import save_figure

        save_figure(plot_fit(result, system, residuals=residuals), out, dpi=120)
    written = {"out": out} if out is not None else {}
    if options.echo_json({**fit_summary(result, system), **written}, as_json):
        return
    click.echo(fit_text(result, system))
    if out is not None:
        click.echo(f"wrote {out}")

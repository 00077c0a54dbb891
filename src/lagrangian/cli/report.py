"""The ``report`` command: the worked solution of a model as a document for lecture notes."""

from __future__ import annotations

from pathlib import Path

import click

from ..budget import STAGE_SECONDS
from . import options
from .app import MODEL_HELP, app


def _formats():
    """The formats of the report (their registry is imported when the names are read)."""
    from ..output.worked_solution import FORMATS

    return FORMATS


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.choice(
    "--to",
    _formats,  # read when the command runs
    "The format: LaTeX (compiles with pdflatex), Markdown with TeX mathematics, or "
    "HTML that typesets offline (default: by the suffix of --out).",
    dest="to",
)
@options.out("Write FILE (default: <name>.tex, .md or .html); the pictures go beside it.")
@options.set_values(
    "A parameter value, or an initial coordinate / velocity of the phase portrait's run "
    "(repeatable): the numbers are at these values."
)
@options.define
@click.option("--no-figures", is_flag=True, help="Leave out the phase portrait and mode shapes.")
@options.seconds(
    STAGE_SECONDS,
    "CPU seconds for each stage of the analysis (> 0, at most a week); a stage out of time "
    "is said undecided in the document.",
)
def report(model, to, out, assignments, definitions, no_figures: bool, timeout: float) -> None:
    """Write the worked solution of MODEL for lecture notes: the system, T, V, L, each
    step of Lagrange's equations, M q'' = f, conserved quantities with their reasons, H,
    equilibria with their stability, normal modes with numbers, and pictures."""
    import dataclasses

    from ..errors import ModelError
    from ..facade import load
    from ..files import check_output_path
    from ..model.values import with_values
    from ..output.worked_solution import FORMATS, report_format, worked_solution, write_report

    if out is None and to is None:
        raise click.UsageError(f"choose the format with --to ({', '.join(FORMATS)})")
    name = Path(model).stem if model.endswith(".toml") else Path(model).name
    out = out or f"{name}{FORMATS[to].suffixes[0]}"
    if to is None and not any(Path(out).suffix.lower() in f.suffixes for f in FORMATS.values()):
        raise click.UsageError(
            f"choose the format with --to ({', '.join(FORMATS)}),"
            " or an --out ending in .tex, .md or .html"
        )
    chosen = report_format(to, out)
    check_output_path(out)  # before the work: a typo in --out fails at once
    system, values = options.assignments(assignments, load(model))  # units converted
    states = {n for c in system.coordinates for n in (c.name, c.q_dot.name)}
    for key in values:
        if key not in states and key not in system.parameter_names:
            raise ModelError(f"'{key}' is neither a parameter nor a coordinate or velocity")
    parameters = {k: v for k, v in values.items() if k in system.parameter_names}
    if parameters:
        system = with_values(system, parameters)
    initial = {k: v for k, v in values.items() if k in states}
    if initial:
        system = dataclasses.replace(system, initial={**system.initial, **initial})
    if not no_figures:
        import matplotlib

        matplotlib.use("Agg")  # no display needed
    solution = worked_solution(
        system,
        given=bool(parameters),
        figures=not no_figures,
        timeout=timeout,
        definitions=options.definitions(definitions),
    )
    written = write_report(solution, out, chosen.name)
    pictures = [path.name for path in written[:-1]]
    beside = f" (pictures: {', '.join(pictures)})" if pictures else ""
    click.echo(f"wrote {out}{beside}")

"""The ``export`` command: the right-hand side as a file in one of the export languages."""

from __future__ import annotations

import click

from . import options
from .app import MODEL_HELP, app


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.choice(
    "--to",
    options.export_languages,  # read when the command runs: a target added is offered
    "The language of the file.",
    dest="language",
    required=True,
)
@options.out("Write FILE (a MATLAB function is named after it); default: print.")
@options.define
@click.option(
    "--baumgarte",
    type=float,  # its range is checked by the library, which names it
    default=None,
    help="Stabilisation rate alpha of the constraints, 0 (none) to 1e6 (default 10).",
)
def export(model, language, out, definitions, baumgarte) -> None:
    """Write the right-hand side, mass matrix and forcing of MODEL as self-contained code."""
    from ..codegen.forms import DEFAULT_BAUMGARTE, checked_baumgarte
    from ..export import export_code, write_code
    from ..facade import load

    baumgarte = checked_baumgarte(DEFAULT_BAUMGARTE if baumgarte is None else baumgarte)
    if out is not None:
        from ..files import check_output_path

        check_output_path(out)  # a bad path fails before the work
    system = load(model)
    settings = {
        "definitions": options.definitions(definitions),
        "baumgarte": baumgarte,
    }
    if out is None:
        click.echo(export_code(system, language, **settings), nl=False)
        return
    write_code(system, language, out, **settings)
    click.echo(f"wrote {out}")

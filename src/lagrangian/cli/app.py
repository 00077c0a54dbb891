"""The click application: one small function per command, no physics."""

from __future__ import annotations

import json

import click

MODEL_HELP = "MODEL is a model file (TOML) or the name of a built-in example."


@click.group(
    name="lagrangian",
    help="Analytical mechanics: derive, analyse and simulate Lagrange's equations of motion.",
    context_settings={"help_option_names": ["-h", "--help"]},
)
@click.version_option(package_name="lagrangian")
def app() -> None:
    pass


@app.command()
def examples() -> None:
    """List the built-in example models."""
    from ..examples import example_names
    from ..model import load

    for name in example_names():
        system = load(name)  # built, not just listed: a broken example shows up here
        click.echo(f"{name:30s} {system.name}  ({', '.join(system.coordinate_names)})")


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@click.option("--json", "as_json", is_flag=True, help="Print the JSON document.")
@click.option("--latex", "as_latex", is_flag=True, help="Print LaTeX.")
@click.option("--steps", is_flag=True, help="Show the derivation step by step, as by hand.")
def derive(model: str, as_json: bool, as_latex: bool, steps: bool) -> None:
    """Derive Lagrange's equations of motion of MODEL."""
    from .. import output
    from ..model import load

    if as_json and as_latex:
        raise click.UsageError("choose one of --json and --latex")
    eom = load(model).equations_of_motion()
    if as_json:
        click.echo(json.dumps(output.derive_document(eom), indent=2, ensure_ascii=False))
    elif as_latex:
        click.echo(output.latex_steps(eom) if steps else output.latex_equations(eom))
    else:
        click.echo(output.format_steps(eom) if steps else output.format_equations(eom))


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@click.option("--json", "as_json", is_flag=True, help="Print the JSON document.")
@click.option("--latex", "as_latex", is_flag=True, help="Print LaTeX.")
def analyze(model: str, as_json: bool, as_latex: bool) -> None:
    """Conserved quantities, Hamiltonian, equilibria and small oscillations of MODEL."""
    from ..analysis import analyze as run_analysis
    from ..model import load
    from ..output.analysis import analysis_document, format_analysis, latex_analysis

    if as_json and as_latex:
        raise click.UsageError("choose one of --json and --latex")
    analysis = run_analysis(load(model).equations_of_motion())
    if as_json:
        click.echo(json.dumps(analysis_document(analysis), indent=2, ensure_ascii=False))
    elif as_latex:
        click.echo(latex_analysis(analysis))
    else:
        click.echo(format_analysis(analysis))

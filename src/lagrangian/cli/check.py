"""``lagrangian check``: a student's answers against the model (the library's ``check``)."""

from __future__ import annotations

import json

import click

from . import options
from .app import MODEL_HELP, app


@app.command(epilog=MODEL_HELP + " Answers use the model's names (also LaTeX).")
@click.argument("model")
@click.option("--kinetic", metavar="EXPR", help="The kinetic energy T.")
@click.option("--potential", metavar="EXPR", help="The potential energy V (up to a constant).")
@click.option("--lagrangian", metavar="EXPR", help="The Lagrangian L.")
@click.option(
    "--equation",
    "equations",
    multiple=True,
    metavar="EXPR",
    help="An equation of motion, 'lhs = rhs' or an expression equal to 0 (repeatable, one "
    "per coordinate), e.g. 'l*theta_ddot = -g*sin(theta)'.",
)
@click.option("--hamiltonian", metavar="EXPR", help="The Hamiltonian H(q, p_q, t).")
@click.option(
    "--conserved", multiple=True, metavar="EXPR", help="A conserved quantity (repeatable)."
)
@click.option(
    "--momentum",
    "momenta",
    multiple=True,
    metavar="NAME=EXPR",
    help="A conjugate momentum dL/dq_dot, e.g. p_theta='m*l^2*theta_dot' (repeatable).",
)
@options.as_json("Print the JSON document (verdict, reason, terms, answers).")
def check(model, kinetic, potential, lagrangian, equations, hamiltonian, conserved, momenta,
          as_json) -> None:  # fmt: skip
    """Check a student's T, V, L, equations, H, momenta or conserved quantities against
    MODEL: right, right up to what does not change the physics, or wrong with the terms
    at fault."""
    from ..facade import load

    pairs = options.pairs(momenta, "--momentum", "NAME=EXPR") if momenta else {}
    if not any((kinetic, potential, lagrangian, equations, hamiltonian, conserved, pairs)):
        raise click.UsageError(
            "give an answer to check: --kinetic, --potential, --lagrangian, --equation, "
            "--hamiltonian, --conserved or --momentum"
        )
    result = load(model).check(
        kinetic=kinetic,
        potential=potential,
        lagrangian=lagrangian,
        equations=equations,
        hamiltonian=hamiltonian,
        conserved=conserved,
        momenta=pairs,
    )
    if as_json:
        click.echo(json.dumps(result.document(), indent=2, ensure_ascii=False))
        return
    for answer in result.answers:
        click.echo(f"{answer.quantity} {answer.given}: {answer.verdict}")
        if answer.reason not in ("right", answer.verdict):
            click.echo(f"  {answer.reason}")

"""The click application: one small function per command, no physics."""

from __future__ import annotations

import json

import click

from ..budget import STAGE_SECONDS
from . import options

MODEL_HELP = "MODEL is a model file (TOML) or the name of a built-in example."

#: The library's settings named in its messages (:func:`lagrangian.errors.setting`), as
#: this command line spells them.
FLAGS = {
    "t_end": "--t-end",
    "dt": "--dt",
    "rtol": "--rtol",
    "atol": "--atol",
    "timeout": "--timeout SECONDS",
    "backend": "--backend",
    "params": "--set",
    "params=": "--set NAME=VALUE",
    "definitions=": "--define NAME=EXPR",
    "grid": "--grid",
    "at": "--at",
    "at=": "--at NAME=VALUE",
    "language": "--to",
    "path": "--out",
    "n_out": "--samples",
    "dt_out": "--dt-out",
    "vary": "--vary",
    "samples": "--samples",
    "transient": "--transient",
    "allow_remote": "--allow-remote",
    "kinetic": "--kinetic",
    "potential": "--potential",
    "lagrangian": "--lagrangian",
    "equations": "--equation",
    "hamiltonian": "--hamiltonian",
    "conserved": "--conserved",
    "momenta": "--momentum",
    "exercise": "--exercise",
    "allow_host": "--allow-host",
    "count": "--count",
    "interval": "--interval",
    "wrt": "--wrt",
    "points": "--points",
    "strobe": "--strobe",
    "observe": "--observe",
    "observe=": "--observe 'NAME = EXPR'",
    "noise": "--noise",
    "starts": "--starts",
}


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
    from ..examples import example_names, example_title

    for name in example_names():
        title, coordinates = example_title(name)
        click.echo(f"{name:30s} {title}  ({', '.join(coordinates)})")


def model_or_lagrangian(command):
    """MODEL, or instead a Lagrangian written on the command line (read by :func:`_load`)."""
    command = click.option(
        "--coordinates",
        metavar="NAMES",
        help="The coordinates of --lagrangian, separated by commas, e.g. x,theta.",
    )(command)
    command = click.option(
        "--lagrangian",
        "lagrangian_text",
        metavar="EXPR",
        help="The Lagrangian instead of MODEL, e.g. 'm*l^2*theta_dot^2/2 + m*g*l*cos(theta)'; "
        "every other name is a positive parameter.",
    )(command)
    return click.argument("model", required=False)(command)


def _load(model: str | None, lagrangian_text: str | None, coordinates: str | None):
    """The System of MODEL, or of --lagrangian with --coordinates (read by the safe parser)."""
    from ..facade import System, load

    if lagrangian_text is None:
        if coordinates is not None:
            raise click.UsageError("--coordinates goes with --lagrangian")
        if model is None:
            raise click.UsageError("give MODEL (a model file or example) or --lagrangian")
        return load(model)
    if model is not None:
        raise click.UsageError("give MODEL or --lagrangian, not both")
    names = [name.strip() for name in (coordinates or "").split(",") if name.strip()]
    if not names:
        raise click.UsageError("--lagrangian needs --coordinates, e.g. --coordinates theta")
    return System.from_lagrangian(
        lagrangian_text, coordinates=names, name="Lagrangian", source="--lagrangian"
    )


@app.command(epilog=MODEL_HELP)
@model_or_lagrangian
@click.option("--json", "as_json", is_flag=True, help="Print the JSON document.")
@click.option("--latex", "as_latex", is_flag=True, help="Print LaTeX.")
@click.option("--steps", is_flag=True, help="Show the derivation step by step, as by hand.")
def derive(model, lagrangian_text, coordinates, as_json: bool, as_latex: bool, steps: bool) -> None:
    """Derive Lagrange's equations of motion of MODEL."""
    if as_json and as_latex:
        raise click.UsageError("choose one of --json and --latex")
    eom = _load(model, lagrangian_text, coordinates).equations_of_motion()
    if as_json:  # each format imports its own writer only
        from ..output.json_out import derive_document

        click.echo(json.dumps(derive_document(eom), indent=2, ensure_ascii=False))
    elif as_latex:
        from ..output.latex import latex_equations, latex_steps

        click.echo(latex_steps(eom) if steps else latex_equations(eom))
    else:
        from ..output.text import format_equations, format_steps

        click.echo(format_steps(eom) if steps else format_equations(eom))


@app.command(epilog=MODEL_HELP)
@model_or_lagrangian
@click.option("--json", "as_json", is_flag=True, help="Print the JSON document.")
@click.option("--latex", "as_latex", is_flag=True, help="Print LaTeX.")
@options.seconds(
    STAGE_SECONDS,
    "CPU seconds for each stage (> 0, at most a week); a stage out of time is reported undecided.",
)
@click.option(
    "--state-space",
    "with_state_space",
    is_flag=True,
    help="Also the linearization x' = A x + B u, y = C x + D u (x = [q, q_dot]).",
)
@click.option(
    "--at",
    "at",
    multiple=True,
    metavar="NAME=EXPR",
    help="Operating point of --state-space: a coordinate, a velocity (steady motion), an "
    "input or a parameter, e.g. theta=pi (default: the first equilibrium found).",
)
@click.option(
    "--output",
    "outputs",
    multiple=True,
    metavar="NAME=EXPR",
    help="An output y of --state-space, e.g. tip='x + l*sin(theta)' (default: the state).",
)
@click.option(
    "--set",
    "assignments",
    multiple=True,
    metavar="NAME=VALUE",
    help="A parameter value, or an input's (held at it; default 0), repeatable: the "
    "numbers printed (ω, periods, mode shapes) and numerical searches are at these values.",
)
@click.option(
    "--momentum",
    "momenta",
    multiple=True,
    metavar="NAME=VALUE",
    help="A value of a cyclic momentum for the steady motions, e.g. p_phi=1.",
)
def analyze(
    model: str | None,
    lagrangian_text: str | None,
    coordinates: str | None,
    as_json: bool,
    as_latex: bool,
    timeout: float,
    with_state_space: bool,
    at: tuple[str, ...],
    outputs: tuple[str, ...],
    assignments: tuple[str, ...] = (),
    momenta: tuple[str, ...] = (),
) -> None:
    """Conserved quantities, Hamiltonian, equilibria and small oscillations of MODEL
    (inputs held at 0 or at their --set value); with --state-space also A, B, C, D."""
    from ..analysis import analyze as run_analysis
    from ..output.analysis import analysis_document, format_analysis, latex_analysis

    if as_json and as_latex:
        raise click.UsageError("choose one of --json and --latex")
    if (at or outputs) and not with_state_space:
        raise click.UsageError("--at and --output go with --state-space")
    system, given = options.assignments(assignments, _load(model, lagrangian_text, coordinates))
    system, point = options.operating_point(options.pairs(at, "--at"), system)
    held = {name: given.pop(name) for name in system.input_names if name in given}
    if given:
        from ..model.values import with_values

        system = with_values(system, given)
    linear = None
    if with_state_space:  # first: a bad --at fails before the long analysis
        from ..analysis.state_space import state_space
        from ..budget import OutOfTime, deadline, generous
        from ..errors import LagrangianError

        eom = system.equations_of_motion()
        try:  # a linearization always ends: the budget only stops the unreasonable
            with deadline(generous(timeout), "state space"):
                linear = state_space(
                    eom,
                    point or None,
                    outputs=options.pairs(outputs, "--output") or None,
                )
        except OutOfTime as error:
            raise LagrangianError(f"{error} (more time: --timeout)") from None
    analysis = run_analysis(
        system.without_inputs(held).equations_of_motion(),
        timeout=timeout,
        momenta=options.numbers(options.pairs(momenta, "--momentum", "NAME=NUMBER"), "--momentum"),
    )
    if as_json:
        document = analysis_document(analysis)
        if linear is not None:
            from ..output.state_space import state_space_document

            document["state_space"] = state_space_document(linear)
        click.echo(json.dumps(document, indent=2, ensure_ascii=False))
    elif as_latex:
        click.echo(latex_analysis(analysis, values_given=bool(given or held)))
        if linear is not None:
            from ..output.state_space import latex_state_space

            click.echo(latex_state_space(linear))
    else:
        click.echo(format_analysis(analysis, spelling=FLAGS, values_given=bool(given or held)))
        if linear is not None:
            from ..output.state_space import format_state_space

            click.echo("")
            click.echo(format_state_space(linear))


@app.command(epilog=MODEL_HELP)
@model_or_lagrangian
@click.option("--t-end", type=float, help="End time (default: the model's [simulate] t_end).")
@options.choice(
    "--method",
    options.run_methods,
    "Integrator (default: the model's, else chosen for the run's length: dop853, "
    "its loop compiled for long runs, or taylor: heyoka's where installed, else ours).",
)
@click.option("--dt", type=float, help="Step of the fixed-step methods (rk4, variational).")
@options.tolerances(
    "Relative tolerance of the adaptive methods.", "Absolute tolerance of the adaptive methods."
)
@options.set_values()
@options.define
@options.choice(
    "--backend",
    options.run_backends,
    "Compiled code (default: chosen with the method): llvm compiles in milliseconds; "
    "numba generates machine code, cached on disk (pip install numba), and runs dop853's "
    "whole loop.",
)
@options.out("Write FILE.csv or FILE.nc.")
@click.option(
    "--samples",
    type=int,
    help="Rows of --out: N equally spaced times from 0 to t_end (default: every step).",
)
@click.option(
    "--dt-out", type=float, help="Rows of --out: every DT from 0, and t_end (default: every step)."
)
@options.as_json("Print the JSON summary.")
@options.timeout
def simulate(
    model,
    lagrangian_text,
    coordinates,
    t_end,
    method,
    dt,
    rtol,
    atol,
    assignments,
    definitions,
    backend,
    out,
    samples,
    dt_out,
    as_json,
    timeout,
) -> None:
    """Integrate the equations of motion of MODEL and report the final state and drifts."""
    from ..errors import LagrangianError
    from ..simulation import simulate_system

    system = _load(model, lagrangian_text, coordinates)
    if out is not None and not out.endswith((".csv", ".nc")):
        raise click.BadParameter("the output file must end in .csv or .nc", param_hint="--out")
    if out is not None:
        from ..files import check_output_path

        check_output_path(out)  # before the run: a typo in --out fails at once
    system, values = options.assignments(assignments, system)
    with options.progress_bar(enabled=not as_json) as progress:
        trajectory = simulate_system(
            system,
            t_end=t_end,
            method=method,
            dt=dt,
            rtol=rtol,
            atol=atol,
            assignments=values,
            progress=progress,
            definitions=options.definitions(definitions),
            backend=backend,
            timeout=timeout,
            n_out=samples,
            dt_out=dt_out,
        )
    if trajectory.status == "failed":
        message = trajectory.attrs.get("message", "")
        raise LagrangianError(f"the integration failed: {message}; nothing was written")
    if out is not None:
        trajectory.save(out)
    summary = trajectory.summary()
    if out is not None:
        summary["out"] = out
    if options.echo_json(summary, as_json):
        return
    click.echo(
        f"{system.name}: {summary['method']}, {summary['steps']} steps, "
        f"{summary['wall_time']:.3f} s, {summary['status']}"
    )
    if "choice" in summary:
        click.echo(f"method: {summary['choice']}")
    if "compiled" in summary:
        click.echo(f"compiled: {summary['compiled']}, {summary['compile_time']:.2g} s of CPU")
    click.echo("final state:")
    units = summary.get("units", {})
    for name, value in summary["final_state"].items():
        click.echo(f"  {name} = {value:.12g}" + (f" {units[name]}" if name in units else ""))
    if summary["invariants"]:
        click.echo("drift along the run (max |X(t) - X(0)|, relative where X(0) != 0):")
    for name, value in summary["invariants"].items():
        click.echo(f"  {name}: {value:.3e}")
    for name, entry in summary.get("not_conserved", {}).items():
        click.echo(
            f"{name} is not conserved ({entry['reason']}): it changed by {entry['change']:.3e}"
        )
    for name, entry in summary.get("conserved_in_this_run", {}).items():
        click.echo(
            f"{name} is conserved in this run: not in general ({entry['reason_in_general']}), "
            "but that vanishes at these parameter values"
        )
    if "impacts" in summary:  # a model with contacts (issue 34)
        impacts, held = summary["impacts"], summary["held_contacts"]
        first = f", the first at t = {impacts[0]['t']:.6g} ({impacts[0]['contact']})"
        click.echo(f"impacts: {len(impacts)}" + (first if impacts else ""))
        for entry in held:
            click.echo(
                f"  held: {entry['contact']} from t = {entry['t_from']:.6g} to {entry['t_to']:.6g}"
            )
    if out is not None:
        click.echo(f"wrote {out}")

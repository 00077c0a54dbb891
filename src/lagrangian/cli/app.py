"""The click application: one small function per command, no physics."""

from __future__ import annotations

import contextlib
import json
import sys
import time

import click

from ..budget import STAGE_SECONDS, checked_seconds
from ..integrate.pace import RUN_SECONDS
from ..integrate.registry import METHODS
from ..numeric.compile import RUN_BACKENDS

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
    "allow_remote": "--allow-remote",
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
    from .. import output

    if as_json and as_latex:
        raise click.UsageError("choose one of --json and --latex")
    eom = _load(model, lagrangian_text, coordinates).equations_of_motion()
    if as_json:
        click.echo(json.dumps(output.derive_document(eom), indent=2, ensure_ascii=False))
    elif as_latex:
        click.echo(output.latex_steps(eom) if steps else output.latex_equations(eom))
    else:
        click.echo(output.format_steps(eom) if steps else output.format_equations(eom))


@app.command(epilog=MODEL_HELP)
@model_or_lagrangian
@click.option("--json", "as_json", is_flag=True, help="Print the JSON document.")
@click.option("--latex", "as_latex", is_flag=True, help="Print LaTeX.")
@click.option(
    "--timeout",
    type=float,
    callback=lambda ctx, param, value: _seconds(value),
    metavar="SECONDS",
    default=STAGE_SECONDS,
    show_default=True,
    help="CPU seconds for each stage (> 0, at most a week); a stage out of time is reported "
    "undecided.",
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
    system = _load(model, lagrangian_text, coordinates)
    given = _assignments(assignments)
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
                    eom, _pairs(at, "--at") or None, outputs=_pairs(outputs, "--output") or None
                )
        except OutOfTime as error:
            raise LagrangianError(f"{error} (more time: --timeout)") from None
    analysis = run_analysis(
        system.without_inputs(held).equations_of_motion(),
        timeout=timeout,
        momenta=_numbers(_pairs(momenta, "--momentum", "NAME=NUMBER"), "--momentum"),
    )
    if as_json:
        document = analysis_document(analysis)
        if linear is not None:
            from ..output.state_space import state_space_document

            document["state_space"] = state_space_document(linear)
        click.echo(json.dumps(document, indent=2, ensure_ascii=False))
    elif as_latex:
        click.echo(latex_analysis(analysis))
        if linear is not None:
            from ..output.state_space import latex_state_space

            click.echo(latex_state_space(linear))
    else:
        click.echo(format_analysis(analysis, spelling=FLAGS))
        if linear is not None:
            from ..output.state_space import format_state_space

            click.echo("")
            click.echo(format_state_space(linear))


def _pairs(values: tuple[str, ...], hint: str, metavar: str = "NAME=EXPR") -> dict[str, str]:
    """The NAME=TEXT items of a repeatable option (--set, --define, --at, --output,
    --momentum, --grid), in order; the one parser of them all.

    A malformed item, or a name given twice (which would keep the last silently), is a
    usage error naming it.  The text is read later: by ``float`` or by the safe parser.
    """
    result: dict[str, str] = {}
    for item in values:
        name, sep, text = item.partition("=")
        name = name.strip()
        if not sep or not name or not text.strip():
            raise click.BadParameter(f"expected {metavar}, got {item!r}", param_hint=hint)
        if name in result:
            raise click.BadParameter(f"'{name}' is given twice", param_hint=hint)
        result[name] = text
    return result


def _numbers(pairs: dict[str, str], hint: str) -> dict[str, float]:
    """NAME=VALUE pairs with plain numbers (read by float, never evaluated)."""
    numbers = {}
    for name, text in pairs.items():
        try:
            numbers[name] = float(text)
        except ValueError:
            raise click.BadParameter(
                f"expected NAME=NUMBER, got {f'{name}={text}'!r}", param_hint=hint
            ) from None
    return numbers


@contextlib.contextmanager
def _progress_bar(*, enabled: bool):
    """A progress bar on stderr for runs longer than a second, only on a terminal.

    Yields the callback for :func:`~lagrangian.simulation.simulate_system`
    (``None`` when piped, with ``--json``, or off a terminal).
    """
    stream = sys.stderr
    if not enabled or not stream.isatty():
        yield None
        return
    start = time.monotonic()
    state = {"bar": None, "shown": 0}

    def progress(fraction: float) -> None:
        if state["bar"] is None:
            if time.monotonic() - start < 1.0:
                return
            state["bar"] = click.progressbar(length=1000, label="simulating", file=stream)
            state["bar"].__enter__()
        step = int(1000 * fraction) - state["shown"]
        if step > 0:
            state["bar"].update(step)
            state["shown"] += step

    try:
        yield progress
    finally:
        if state["bar"] is not None:
            state["bar"].__exit__(None, None, None)


def _assignments(values: tuple[str, ...]) -> dict[str, float]:
    """NAME=VALUE pairs of --set as numbers (a bad one is a usage error naming it)."""
    return _numbers(_pairs(values, "--set", "NAME=NUMBER"), "--set")


#: --define NAME=EXPR, read by :func:`_definitions` (simulate, ensemble).
define_option = click.option(
    "--define",
    "definitions",
    multiple=True,
    metavar="NAME=EXPR",
    help="Define an unspecified function of the model, e.g. V='x^2 + y^2' (repeatable).",
)


def _seconds(value: float) -> float:
    """A --timeout checked by the library's own rule (:func:`lagrangian.budget.checked_seconds`):
    NaN, infinity (which would switch the budget off), 0 or over a week is a usage error."""
    from ..errors import ModelError

    try:
        return checked_seconds(value, "timeout")
    except ModelError as error:
        raise click.BadParameter(error.message) from None


#: --timeout of every command that runs an integration (simulate, ensemble, plot, animate).
timeout_option = click.option(
    "--timeout",
    type=float,
    callback=lambda ctx, param, value: _seconds(value),
    metavar="SECONDS",
    default=RUN_SECONDS,
    show_default=True,
    help="CPU seconds the runs may take (wall seconds on a GPU or dask; > 0, at most a week); "
    "a run whose pace shows it would take longer is stopped at once.",
)


def _definitions(values: tuple[str, ...]) -> dict[str, str]:
    """NAME=EXPR pairs of --define (the expression is parsed later by the safe parser)."""
    return _pairs(values, "--define")


@app.command(epilog=MODEL_HELP)
@model_or_lagrangian
@click.option("--t-end", type=float, help="End time (default: the model's [simulate] t_end).")
@click.option(
    "--method",
    type=click.Choice(list(METHODS)),
    help="Integrator (default: the model's, else chosen for the run's length: dop853, "
    "its loop compiled for long runs, or taylor where heyoka is installed).",
)
@click.option("--dt", type=float, help="Step of the fixed-step methods (rk4, variational).")
@click.option("--rtol", type=float, help="Relative tolerance of the adaptive methods.")
@click.option("--atol", type=float, help="Absolute tolerance of the adaptive methods.")
@click.option(
    "--set",
    "assignments",
    multiple=True,
    metavar="NAME=VALUE",
    help="A parameter value or an initial coordinate / velocity (repeatable).",
)
@define_option
@click.option(
    "--backend",
    type=click.Choice(sorted(RUN_BACKENDS)),
    default=None,
    help="Compiled code (default: chosen with the method): llvm compiles in milliseconds; "
    "numba generates machine code, cached on disk (pip install numba), and runs dop853's "
    "whole loop.",
)
@click.option("--out", type=click.Path(dir_okay=False), help="Write FILE.csv or FILE.nc.")
@click.option(
    "--samples",
    type=int,
    help="Rows of --out: N equally spaced times from 0 to t_end (default: every step).",
)
@click.option(
    "--dt-out", type=float, help="Rows of --out: every DT from 0, and t_end (default: every step)."
)
@click.option("--json", "as_json", is_flag=True, help="Print the JSON summary.")
@timeout_option
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
    with _progress_bar(enabled=not as_json) as progress:
        trajectory = simulate_system(
            system,
            t_end=t_end,
            method=method,
            dt=dt,
            rtol=rtol,
            atol=atol,
            assignments=_assignments(assignments),
            progress=progress,
            definitions=_definitions(definitions),
            backend=backend,
            timeout=timeout,
            n_out=samples,
            dt_out=dt_out,
        )
    if trajectory.status == "failed":
        message = trajectory.dataset.attrs.get("message", "")
        raise LagrangianError(f"the integration failed: {message}; nothing was written")
    if out is not None:
        trajectory.save(out)
    summary = trajectory.summary()
    if out is not None:
        summary["out"] = out
    if as_json:
        click.echo(json.dumps(summary, indent=2))
        return
    click.echo(
        f"{system.name}: {summary['method']}, {summary['steps']} steps, "
        f"{summary['wall_time']:.3f} s, {summary['status']}"
    )
    if "choice" in summary:
        click.echo(f"method: {summary['choice']}")
    click.echo("final state:")
    for name, value in summary["final_state"].items():
        click.echo(f"  {name} = {value:.12g}")
    if summary["invariants"]:
        click.echo("drift along the run (max |X(t) - X(0)|, relative where X(0) != 0):")
    for name, value in summary["invariants"].items():
        click.echo(f"  {name}: {value:.3e}")
    for name, entry in summary.get("not_conserved", {}).items():
        click.echo(
            f"{name} is not conserved ({entry['reason']}): it changed by {entry['change']:.3e}"
        )
    if out is not None:
        click.echo(f"wrote {out}")

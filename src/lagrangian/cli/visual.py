"""The commands that draw: ``plot``, ``animate``, ``page`` and ``demo`` (registered on ``app``).

Thin shells: the pictures come from :mod:`lagrangian.output` (plots, phase,
mode_shapes, animation); matplotlib is imported only when one of these runs,
with the Agg backend, so nothing needs a display.
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path

import click

from ..files import check_output_path, output_error
from . import options
from .app import MODEL_HELP, app

PLOT_KINDS = ("timeseries", "phase", "energy", "poincare", "modes")
TRAJECTORY_SUFFIXES = (".csv", ".nc")
PAGE_SUFFIXES = (".html", ".htm")
#: The demo: the double pendulum released from theta1 = 2, theta2 = 0.5 (chaotic).
DEMO_MODEL = "double_pendulum"
DEMO_INITIAL = {"theta1": 2.0, "theta2": 0.5}
DEMO_T_END, DEMO_DT = 10.0, 0.005


def _headless() -> None:
    """matplotlib with the Agg backend (no display needed) before anything draws."""
    import matplotlib

    matplotlib.use("Agg")


def _stem(source: str) -> str:
    return Path(source).stem if source.endswith(".toml") else Path(source).name


def _run_options(function):
    """--t-end, --samples, --method, --set, --define and --timeout, as ``simulate`` has them."""
    decorators = [
        click.option("--t-end", type=float, help="End time (default: the model's t_end)."),
        click.option(
            "--samples",
            type=int,
            help="Draw the run at N equally spaced times from 0 to t_end (default: every "
            "step; a long run keeps only these in memory).",
        ),
        options.choice("--method", options.run_methods, "Integrator."),
        options.set_values(),
        options.define,
        options.timeout,
    ]
    for option in reversed(decorators):
        function = option(function)
    return function


def _simulate(system, **settings):
    """simulate_system with a progress bar on a terminal; a failed run is an error."""
    from ..errors import LagrangianError
    from ..simulation import simulate_system

    with options.progress_bar(enabled=True) as progress:
        run = simulate_system(system, progress=progress, **settings)
    if run.status == "failed":
        message = run.dataset.attrs.get("message", "")
        raise LagrangianError(f"the integration failed: {message}; nothing was written")
    return run


@app.command(epilog=MODEL_HELP + " TRAJECTORY is a .csv or .nc file written by simulate --out.")
@click.argument("source", metavar="MODEL|TRAJECTORY")
@options.choice(
    "--kind",
    PLOT_KINDS,
    "What to draw (modes: normal modes about a stable equilibrium; MODEL only).",
    default="timeseries",
)
@options.out("Write F.png, F.pdf or F.svg (default: <name>-<kind>.png).")
@_run_options
def plot(source, kind, out, t_end, samples, method, assignments, definitions, timeout) -> None:
    """Plot a run of MODEL (simulated with its defaults) or a saved TRAJECTORY.

    The options of the run (--t-end, --method, --set, --define) apply to a MODEL.
    """
    from ..output.plots import FIGURE_FORMATS, PLOTS, save_figure

    out = out or f"{_stem(source)}-{kind}.png"
    if Path(out).suffix.lower() not in FIGURE_FORMATS:
        raise click.BadParameter(
            "the output file must end in .png, .pdf or .svg", param_hint="--out"
        )
    check_output_path(out)  # before the run: a typo in --out fails at once
    _headless()
    if source.lower().endswith(TRAJECTORY_SUFFIXES):
        if any(x is not None for x in (t_end, samples, method)) or assignments or definitions:
            raise click.UsageError(
                "--t-end, --samples, --method, --set and --define apply to a MODEL, not a file"
            )
        if kind == "modes":
            raise click.UsageError("--kind modes needs a MODEL, not a trajectory file")
        from ..trajectory import Trajectory

        figure = PLOTS[kind](Trajectory.load(source))
    else:
        settings = {
            "t_end": t_end,
            "n_out": samples,
            "method": method,
            "assignments": assignments,
            "definitions": options.definitions(definitions),
            "timeout": timeout,
        }
        figure = _model_figure(source, kind, settings)
    save_figure(figure, out)
    click.echo(f"wrote {out}")


def _model_figure(model: str, kind: str, settings: dict):
    from ..facade import load
    from ..output.plots import PLOTS

    system, values = options.assignments(settings["assignments"], load(model))
    settings = {**settings, "assignments": values}
    if kind == "modes":
        from ..output.mode_shapes import plot_normal_modes

        parameters = {k: v for k, v in values.items() if k in system.parameter_names}
        return plot_normal_modes(system, parameters=parameters)
    if kind == "poincare":
        from ..output.poincare import plot_poincare, section_event

        if len(system.coordinates) < 2:
            raise click.UsageError("a Poincaré section needs a model with two or more coordinates")
        return plot_poincare(_simulate(system, events=[section_event(system)], **settings), system)
    run = _simulate(system, **settings)
    if kind == "phase":
        from ..output.phase import conservative_one_dof, phase_family, plot_phase_portrait

        if conservative_one_dof(system) and not values and settings["method"] is None:
            family = phase_family(system, t_end=settings["t_end"])
            return plot_phase_portrait([*family, run], system)
        return plot_phase_portrait(run, system)
    return PLOTS[kind](run, system)


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.out(
    "Write F.gif, F.html (plays in a browser) or F.mp4 (needs ffmpeg); default <name>.gif."
)
@_run_options
@click.option("--fps", type=float, default=25, show_default=True, help="Frames per second.")
@click.option(
    "--max-frames",
    type=int,
    default=500,
    show_default=True,
    help="At most this many frames; longer runs play faster than real time.",
)
@click.option(
    "--reactions",
    is_flag=True,
    help="Draw a linkage's joint reactions as arrows (the force on each joint's second side).",
)
def animate(
    model,
    out,
    t_end,
    samples,
    method,
    assignments,
    definitions,
    timeout,
    fps,
    max_frames,
    reactions: bool,
) -> None:
    """Animate the mechanism of MODEL: a run played in real time."""
    from ..errors import ModelError
    from ..facade import load
    from ..output.animation import animate as write_animation
    from ..output.animation import check_animation_path

    out = out or f"{_stem(model)}.gif"
    check_animation_path(out)
    check_output_path(out)
    # without particles or bodies: the coordinates are drawn
    system, values = options.assignments(assignments, load(model))
    _headless()
    run = _simulate(
        system,
        t_end=t_end,
        n_out=samples,
        method=method,
        assignments=values,
        definitions=options.definitions(definitions),
        timeout=timeout,
    )
    if reactions and not run.reactions:
        raise ModelError(
            "the model has no joint reactions to draw (no [[links]] and [[joints]], or other "
            "masses move with them)",
            field="--reactions",
        )
    result = write_animation(run, system, out, fps=fps, max_frames=max_frames, reactions=reactions)
    click.echo(f"wrote {out}: {result.plan.description}")


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.out("Write F.html (default: <name>.html).")
@options.set_values(
    "A parameter value or an initial coordinate / velocity to start from (repeatable)."
)
@options.define
@click.option(
    "--no-cache",
    is_flag=True,
    help="Make the page anew, neither reading nor keeping it in the cache of pages "
    "(also LAGRANGIAN_NO_CACHE=1).",
)
@click.option(
    "--exercise",
    is_flag=False,
    flag_value="all",
    default=None,
    metavar="[STEPS]",
    help="An exercise: the worked solution hidden, the student asked for these steps "
    "(kinetic, potential, lagrangian, equations, separated by commas; alone: all), each "
    "answer checked in the page as 'lagrangian check' does.",
)
def page(model, out, assignments, definitions, no_cache: bool, exercise: str | None) -> None:
    """Write the page of MODEL: one HTML file, for any browser, offline.

    The worked solution typeset (L, Lagrange's equations, M and f, conserved
    quantities, equilibria and normal modes) beside a live simulation with a control
    for every parameter and initial value.  A page made before from the same model
    file, values and version of the toolkit is written from the cache of pages.
    """
    from ..errors import LagrangianError, ModelError
    from ..facade import load
    from ..files import write_atomically
    from ..model.toml_io import model_bytes
    from ..output.exercise import exercise_steps
    from ..output.page import built_page
    from ..output.page_cache import cache_enabled, cached_page

    out = out or f"{_stem(model)}.html"
    if Path(out).suffix.lower() not in PAGE_SUFFIXES:
        raise click.BadParameter("the output file must end in .html", param_hint="--out")
    check_output_path(out)  # before the work: a typo in --out fails at once

    def build():
        system, values = options.assignments(assignments, load(model))
        states = {n for c in system.coordinates for n in (c.name, c.q_dot.name)}
        for name in values:
            if name not in states and name not in system.parameter_names:
                raise ModelError(f"'{name}' is neither a parameter nor a coordinate or velocity")
        return built_page(
            system,
            parameters={k: v for k, v in values.items() if k in system.parameter_names},
            initial={k: v for k, v in values.items() if k in states},
            definitions=options.definitions(definitions),
            exercise=exercise_steps(exercise) if exercise is not None else None,
        )

    if exercise is not None:
        exercise_steps(exercise)  # before the work: a misspelt step fails at once
    source = None
    if cache_enabled() and not no_cache:
        with contextlib.suppress(OSError, LagrangianError):  # loading says what is wrong
            source = model_bytes(model)
    if source is None:
        text = build().html
    else:
        given = {"set": list(assignments), "define": list(definitions), "exercise": exercise}
        text = cached_page(source, given, build)
    write_atomically(out, lambda temporary: temporary.write_text(text, encoding="utf-8"))
    click.echo(f"wrote {out}: open it in a browser (it needs no server and no network)")


@app.command()
@click.option(
    "--out-dir",
    type=click.Path(file_okay=False),
    default="lagrangian-demo",
    show_default=True,
    help="Folder for the animation and the plots.",
)
def demo(out_dir: str) -> None:
    """Derive, analyse, simulate and animate the double pendulum; say where the files went."""
    from ..analysis import linearize
    from ..facade import load
    from ..integrate import simulate
    from ..numeric import compile_equations
    from ..output import format_equations
    from ..output.animation import animate as write_animation
    from ..output.mode_shapes import mode_numbers, plot_normal_modes
    from ..output.phase import plot_phase_portrait
    from ..output.plots import plot_energy_error, save_figure

    start = time.perf_counter()
    _headless()
    folder = Path(out_dir)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:  # a file in the way, no permission: one line, before any work
        raise output_error(folder, error) from None
    system = load(DEMO_MODEL)
    eom = system.equations_of_motion()
    click.echo("1. Lagrange's equations, derived from the positions of the two bobs\n")
    click.echo(format_equations(eom))

    rest = {"theta1": 0, "theta2": 0}
    modes = linearize(eom, rest).normal_modes()
    _, omega_squared, shapes = mode_numbers(system, rest, modes=modes)
    click.echo("\n2. Small oscillations about the lowest position (normal modes)\n")
    for i, (w2, shape) in enumerate(zip(omega_squared, shapes, strict=True)):
        phase = "in phase" if shape[0] * shape[1] > 0 else "in antiphase"
        click.echo(
            f"  mode {i + 1}: ω = {w2**0.5:.4f} rad/s, period {2 * 3.141592653589793 / w2**0.5:.4f}"
            f" s, shape (θ₁, θ₂) = ({shape[0]:.4g}, {shape[1]:.4g}): the bobs swing {phase}"
        )

    compiled = compile_equations(eom)
    click.echo(
        f"\n3. A chaotic motion: θ₁ = {DEMO_INITIAL['theta1']}, θ₂ = {DEMO_INITIAL['theta2']},"
        f" released at rest, {DEMO_T_END:g} s, variational integrator (dt = {DEMO_DT})"
    )
    run = simulate(
        compiled, t_end=DEMO_T_END, initial=DEMO_INITIAL, method="variational", dt=DEMO_DT
    )
    reference = simulate(compiled, t_end=DEMO_T_END, initial=DEMO_INITIAL, method="dop853")
    click.echo(
        f"   {run.dataset.attrs['steps']} steps; largest relative energy error "
        f"{run.drift('energy'):.2e} (bounded: the method is symplectic); "
        f"dop853 at rtol 1e-10 for comparison: {reference.drift('energy'):.2e}"
    )

    written = []
    animation = write_animation(run, system, folder / "double_pendulum.gif")
    written.append((animation.path, f"the motion, {animation.plan.description}"))
    written.append(
        (
            save_figure(plot_phase_portrait(run, system), folder / "phase.png"),
            "phase portraits (angles wrapped into [-π, π))",
        )
    )
    energy = plot_energy_error([run, reference], system)
    written.append((save_figure(energy, folder / "energy.png"), "energy error, log scale"))
    modes_figure = plot_normal_modes(system, rest, modes=modes)
    written.append((save_figure(modes_figure, folder / "modes.png"), "the two normal modes"))
    click.echo(f"\n4. Files in {folder.resolve()}:")
    for path, what in written:
        click.echo(f"   {path.name:20s} {what}")
    click.echo(f"\ndone in {time.perf_counter() - start:.1f} s")

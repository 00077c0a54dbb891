"""The commands that show and measure chaos: ``lyapunov``, ``poincare`` and
``bifurcation`` (registered on ``app``)."""

from __future__ import annotations

import click
import numpy as np

from . import options
from .app import MODEL_HELP, app

backend_option = options.choice(
    "--backend",
    options.run_backends,
    "Compiled code (default llvm where SymEngine has it, else numpy).",
)


def plot_option(what: str):
    """--plot FILE.png, drawing ``what``."""
    return click.option(
        "--plot", "picture", type=click.Path(dir_okay=False), help=f"Draw {what} to FILE.png."
    )


def section_options(command):
    """--section EXPR=EXPR and --direction (poincare, bifurcation)."""
    command = click.option(
        "--direction",
        type=click.Choice(["+", "-", "both"]),
        default="+",
        show_default=True,
        help="Crossings where left - right increases (+), decreases (-), or both.",
    )(command)
    return click.option(
        "--section", metavar="EXPR=EXPR", help="The surface of section, e.g. 'x = 0'."
    )(command)


def transient_option(help: str):
    """--transient T, the time run before anything is kept (0 unless given)."""
    return click.option("--transient", type=float, default=0.0, show_default=True, help=help)


def _one_section(section: str | None, strobe: float | None, phase: float | None) -> None:
    """A usage error unless exactly one of --section and --strobe is given, and --phase
    only with --strobe."""
    if (section is None) == (strobe is None):
        raise click.BadParameter("give --section or --strobe (one of them)", param_hint="--section")
    phase_with_strobe(strobe, phase)


def phase_with_strobe(strobe: float | None, phase: float | None) -> None:
    """A usage error for --phase without --strobe."""
    if phase is not None and strobe is None:
        raise click.BadParameter("--phase goes with --strobe", param_hint="--phase")


def phase_option(command):
    """--phase PHI: the strobe's times t = PHI + k PERIOD (poincare, bifurcation)."""
    return click.option(
        "--phase",
        type=float,
        metavar="PHI",
        help="With --strobe: the points at t = PHI + k PERIOD from the start (default 0), "
        "whatever --transient (which only drops points).",
    )(command)


def _drawn(picture: str | None, points: int) -> str | None:
    """The picture to draw: none where there are no points (an empty frame is no result;
    the command's warning says why there are none)."""
    if picture is None or points:
        return picture
    import warnings

    from ..errors import LagrangianWarning

    warnings.warn(LagrangianWarning(f"no points to draw: {picture} was not written"), stacklevel=2)
    return None


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@click.option("--t-end", type=float, help="Averaging time (default: the model's t_end).")
@transient_option("Time run first and not averaged (to settle on an attractor).")
@click.option("--count", type=int, help="How many exponents, largest first (default: all 2n).")
@click.option("--largest", is_flag=True, help="Only the largest exponent (--count 1).")
@click.option(
    "--interval",
    type=float,
    help="Time between re-orthonormalisations of the displacements (default 1).",
)
@options.tolerances("Relative tolerance (default 1e-9).", "Absolute tolerance (default 1e-11).")
@options.set_values()
@options.define
@backend_option
@plot_option("the convergence of the estimates")
@options.as_json()
@options.timeout
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
    options.check_png(picture, "--plot")
    system, values = options.assignments(assignments, load(model))
    with options.progress_bar(enabled=not as_json) as progress:
        spectrum = lyapunov_of_system(
            system, t_end=t_end, count=1 if largest else count, transient=transient,
            interval=interval, rtol=rtol, atol=atol, assignments=values,
            progress=progress, definitions=options.definitions(definitions), backend=backend,
            timeout=timeout,
        )  # fmt: skip
    if picture is not None:
        from ..output.lyapunov import plot_lyapunov
        from ..output.plots import save_figure

        save_figure(plot_lyapunov(spectrum, system), picture, dpi=120)
    summary = lyapunov_summary(spectrum, system)
    if options.echo_json(
        {**summary, **({"plot": picture} if picture is not None else {})}, as_json
    ):
        return
    click.echo(lyapunov_text(spectrum, system))
    options.wrote(picture)


def _spread(values: tuple[str, ...]) -> dict[str, tuple[float, float]]:
    """NAME=LO:HI of --spread (a bad one: usage error naming it)."""
    spread = {}
    for name, text in options.pairs(values, "--spread", "NAME=LO:HI").items():
        try:
            low, high = (float(part) for part in text.split(":"))
            if not (np.isfinite(low) and np.isfinite(high)):
                raise ValueError
        except ValueError:
            raise click.BadParameter(
                f"expected NAME=LO:HI (LO and HI finite numbers), got {f'{name}={text}'!r}",
                param_hint="--spread",
            ) from None
        options.check_width(name, low, high, "--spread")
        spread[name] = (low, high)
    return spread


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.required(
    "--axes", "A,B", "The two variables drawn: coordinates, velocities q_dot or momenta p_q."
)
@section_options
@click.option("--strobe", type=float, metavar="PERIOD", help="A stroboscopic section instead.")
@phase_option
@transient_option("Time before the first point kept (strobe or section).")
@click.option("--energy", type=float, help="Start the orbits on this energy shell.")
@click.option("--orbits", type=int, help="How many orbits (default 10 with --energy/--spread).")
@options.repeated(
    "--spread",
    "spreads",
    "NAME=LO:HI",
    "Start the orbits with NAME going from LO to HI (others: the initial state).",
)
@click.option("--t-end", type=float, help="Time each orbit runs (default: the model's t_end).")
@options.tolerances("Relative tolerance (default 1e-10).", "Absolute tolerance (default 1e-12).")
@options.set_values()
@options.define
@backend_option
@options.out("Write the points to F.csv or F.nc.")
@plot_option("the section")
@options.as_json()
@options.timeout
def poincare(
    model, axes, section, direction, strobe, phase, transient, energy, orbits, spreads, t_end,
    rtol, atol, assignments, definitions, backend, out, picture, as_json, timeout,
) -> None:  # fmt: skip
    """Poincaré section of MODEL: where its orbits cross --section, or --strobe PERIOD."""
    from ..facade import load
    from ..simulation import poincare_of_system

    names = tuple(name.strip() for name in axes.split(","))
    if len(names) != 2 or not all(names):
        raise click.BadParameter("give two names, e.g. y,p_y", param_hint="--axes")
    _one_section(section, strobe, phase)
    options.check_outputs(out, (".csv", ".nc"), picture)
    system, values = options.assignments(assignments, load(model))
    with options.progress_bar(enabled=not as_json) as progress:
        points = poincare_of_system(
            system, axes=names, section=section, direction=direction, strobe=strobe,
            phase=phase, transient=transient, energy=energy, orbits=orbits, spread=_spread(spreads),
            t_end=t_end, rtol=rtol, atol=atol, assignments=values,
            progress=progress, definitions=options.definitions(definitions), backend=backend,
            timeout=timeout,
        )  # fmt: skip
    if out is not None:
        points.save(out)
    picture = _drawn(picture, points.count)
    if picture is not None:
        from ..output.plots import save_figure
        from ..output.sections import plot_section

        save_figure(plot_section(points), picture, dpi=120)
    counts = np.bincount(points.orbits, minlength=points.orbit_count)
    summary = {
        "model": points.name,
        "axes": list(points.axes),
        "orbits": points.orbit_count,
        "points": points.count,
        "points_per_orbit": counts.tolist(),
        "energy_spread": float(np.ptp(points.energies)) if points.count else 0.0,
        **points.settings,
        **({"out": out} if out is not None else {}),
        **({"plot": picture} if picture is not None else {}),
    }
    if options.echo_json(summary, as_json):
        return
    where = f"section {section}"
    if strobe is not None:
        where = f"strobe {strobe:g}" + (f" at phase {summary['phase']:g}" if phase else "")
    click.echo(
        f"{points.name}: {where}, {points.orbit_count} orbits to t = {summary['t_end']:g}, "
        f"{points.count} points ({counts.min()} to {counts.max()} per orbit)"
    )
    options.wrote(out, picture)


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.required("--vary", "NAME=LO:HI:N", "N values of the parameter NAME from LO to HI.")
@click.option("--strobe", type=float, metavar="PERIOD", help="Strobe period.")
@phase_option
@section_options
@options.required("--axis", "NAME", "The coordinate or velocity drawn.", dest="variable")
@transient_option("Time dropped first.")
@click.option("--samples", type=int, help="Points kept per value (default 100).")
@click.option("--steps-per-period", type=int, help="Fixed steps per period (default 200).")
@options.number("--t-end", "With --section: time after the transient (default: the model's).")
@options.number("--dt", "With --section: the step (default: chosen for the motion).")
@options.choice(
    "--method", options.ensemble_choices("METHODS"), "Fixed-step method of the runs.", default="rk4"
)
@options.choice(
    "--backend",
    options.ensemble_choices("BACKENDS"),
    "How the values are integrated together (the ensemble's backends).",
    default="numpy",
)
@options.set_values()
@options.define
@options.out("Write the points to F.csv.")
@plot_option("the diagram")
@options.as_json()
@options.timeout
def bifurcation(
    model, vary, strobe, phase, section, direction, variable, transient, samples, steps_per_period,
    t_end, dt, method, backend, assignments, definitions, out, picture, as_json, timeout,
) -> None:  # fmt: skip
    """Bifurcation diagram of MODEL: the --axis every --strobe PERIOD, or where the motion
    crosses --section, against the --vary parameter."""
    from ..ensemble import bifurcation_of_system
    from ..facade import load
    from ..simulation import split_assignments

    _one_section(section, strobe, phase)
    if strobe is not None and (t_end is not None or dt is not None):
        raise click.BadParameter("--t-end and --dt go with --section", param_hint="--t-end")
    if section is not None and steps_per_period is not None:
        raise click.BadParameter("--steps-per-period goes with --strobe", param_hint="--strobe")
    options.check_outputs(out, (".csv",), picture)
    system, grid = options.grid_axes((vary,), load(model), "--vary")
    ((parameter, values),) = grid.items()
    system, given = options.assignments(assignments, system)
    initial, params = split_assignments(system, given)
    sampling = {"samples": samples, "steps_per_period": steps_per_period, "t_end": t_end, "dt": dt}
    where = (
        {"period": strobe, "phase": phase}
        if section is None
        else {"section": section, "direction": direction}
    )
    with options.progress_bar(enabled=not as_json) as progress:
        diagram = bifurcation_of_system(
            system, vary={parameter: values}, variable=variable, **where, transient=transient,
            initial=initial, params=params, method=method, backend=backend,
            definitions=options.definitions(definitions), timeout=timeout, progress=progress,
            **{k: v for k, v in sampling.items() if v is not None},
        )  # fmt: skip
    if out is not None:
        diagram.to_csv(out)
    picture = _drawn(picture, int(np.isfinite(diagram.points).sum()))
    if picture is not None:
        from ..output.bifurcation import plot_bifurcation
        from ..output.plots import save_figure

        save_figure(plot_bifurcation(diagram), picture, dpi=150)
    settings = diagram.settings
    distinct = [len(np.unique(np.round(row[np.isfinite(row)], 6))) for row in diagram.points]
    summary = {
        "model": diagram.name,
        "parameter": parameter,
        "values": len(diagram.values),
        "variable": variable,
        **settings,
        "distinct_points": {"min": min(distinct), "max": max(distinct)},
        **({"out": out} if out is not None else {}),
        **({"plot": picture} if picture is not None else {}),
    }
    if options.echo_json(summary, as_json):
        return
    when = f"where {section} ({direction})"
    if section is None:
        when = f"every {strobe:g}" + (f" at phase {settings['phase']:g}" if phase else "")
    each = f"{settings['samples']}" if section is None else f"at most {settings['samples']}"
    click.echo(
        f"{diagram.name}: {variable} {when} for {len(diagram.values)} values of "
        f"{parameter}, {each} each after t = {settings['transient']:g}; "
        f"{settings['method']} dt={settings['dt']:g}, backend {settings['backend']}, "
        f"{settings['wall_time']:.3f} s"
    )
    options.wrote(out, picture)

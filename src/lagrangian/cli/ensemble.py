"""The ``ensemble`` command: a grid of runs, an observable map (registered on ``app``)."""

from __future__ import annotations

import click
import numpy as np

from . import options
from .app import MODEL_HELP, app


@app.command(epilog=MODEL_HELP)
@click.argument("model")
@options.repeated(
    "--grid",
    "grids",
    "NAME=LO:HI:N",
    "N values from LO to HI of an initial coordinate / velocity or a parameter "
    "(repeatable: one grid axis each).",
    required=True,
)
@options.choice(
    "--backend",
    options.ensemble_choices("BACKENDS"),
    "How the members are integrated (jax and cuda: on a GPU).",
    default="numpy",
)
@options.choice(
    "--precision",
    options.ensemble_choices("PRECISIONS"),
    "Floating point of backends jax and cuda.",
    default="float64",
)
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="A dask scheduler (backend dask).")
@options.repeated(
    "--observable",
    "observables",
    "NAME",
    "final_state, flip_time, energy_drift, lyapunov, or the chaos indicators sali, gali2, "
    "gali3, gali4 (numpy backend; chaotic below 1e-8) (repeatable; default final_state).",
)
@click.option("--t-end", type=float, help="End time (default: the model's t_end).")
@click.option("--dt", type=float, help="Step (default: the model's dt, else t_end / 1000).")
@options.choice("--method", options.ensemble_choices("METHODS"), "Integrator.")
@options.set_values("A fixed parameter value or initial coordinate / velocity (repeatable).")
@options.define
@click.option(
    "--chunk-size", type=int, help="Members per chunk (default 65536; 2^20 for jax and cuda)."
)
@options.out("Write FILE.nc or a map FILE.png.")
@options.timeout
def ensemble(
    model, grids, backend, precision, scheduler, observables, t_end, dt, method, assignments,
    definitions, chunk_size, out, timeout,
) -> None:  # fmt: skip
    """Integrate MODEL over a grid of initial values or parameters."""
    from ..ensemble import ensemble_of_system, observable_names
    from ..ensemble.observables import INDICATORS
    from ..errors import ModelError
    from ..facade import load
    from ..integrate.indicators import CHAOTIC_BELOW, SALI_BELOW

    if scheduler is not None and backend != "dask":
        raise click.BadParameter("--scheduler needs --backend dask", param_hint="--scheduler")
    if scheduler is not None:
        from ..ensemble.dask_backend import check_scheduler

        check_scheduler(scheduler)  # before the model is built
    if out is not None and not out.endswith((".nc", ".png")):
        raise click.BadParameter("the output file must end in .nc or .png", param_hint="--out")
    if out is not None:
        from ..files import check_output_path

        check_output_path(out)  # before the runs: a typo in --out fails at once
    given = options.pairs(assignments, "--set", "NAME=NUMBER")
    both = sorted(set(options.pairs(grids, "--grid", "NAME=LO:HI:N")) & set(given))
    if both:  # one would silently win over the other
        raise click.BadParameter(f"'{both[0]}' is given by --grid too", param_hint="--set")
    names = observable_names(observables or ("final_state",))
    system, grid = options.grid_axes(grids, load(model))
    system, fixed = options.given_values(given, system, "--set")
    initial, params = {}, {}
    for name, values in {**fixed, **grid}.items():
        if name in system.parameter_names:
            params[name] = values
        elif name in system.coordinate_names or name.removesuffix("_dot") in (
            system.coordinate_names
        ):
            initial[name] = values
        else:
            raise ModelError(f"'{name}' is neither a parameter nor a coordinate or velocity")
    with options.progress_bar(enabled=True) as progress:
        result = ensemble_of_system(
            system, t_end=t_end, dt=dt, method=method, initial=initial, params=params,
            backend=backend, precision=precision, scheduler=scheduler, observables=names,
            chunk_size=chunk_size, progress=progress, definitions=options.definitions(definitions),
            timeout=timeout,
        )  # fmt: skip
    if out is not None and out.endswith(".nc"):
        result.to_netcdf(out)
    elif out is not None:
        _draw(result, names[0], out)
    attrs = result.attrs
    shape = " x ".join(f"{d} {s}" for d, s in zip(result.dims, result.shape, strict=True))
    click.echo(
        f"{system.name}: {shape} = {attrs['members']} members, {attrs['method']} "
        f"dt={attrs['dt']:g}, {attrs['steps']} steps, backend {attrs['backend']} "
        f"({attrs['precision']}), "
        f"{attrs['wall_time']:.3f} s, {attrs['trajectory_steps_per_second']:.3g} "
        "trajectory-steps/s"
    )
    if attrs["failed"]:
        click.echo(f"failed: {attrs['failed']} of {attrs['members']} members (state not finite)")
    for name in names:
        if name == "flip_time":
            values = result["flip_time"]
            click.echo(f"flip_time: {np.mean(np.isfinite(values)):.1%} of the members flip")
        elif name == "energy_drift":
            click.echo(f"energy_drift: max {np.nanmax(result['energy_drift']):.3g}")
        elif name == "lyapunov":
            values = result["lyapunov"]
            click.echo(f"lyapunov: median {np.nanmedian(values):.3g}, max {np.nanmax(values):.3g}")
        elif name in INDICATORS:
            chaotic = float(np.mean(result[f"{name}_chaotic"]))
            rule = (
                f"below {SALI_BELOW:g} at some step" if name == "sali"
                else f"{name} < {CHAOTIC_BELOW:g} at t_end"
            )  # fmt: skip
            click.echo(f"{name}: {chaotic:.1%} of the members chaotic ({rule})")
    if out is not None:
        click.echo(f"wrote {out}")


def _draw(result, observable: str, path: str) -> None:
    """A map (2 grid axes) or a curve (1) of ``observable``, saved atomically."""
    from ..ensemble.observables import INDICATORS
    from ..errors import ModelError
    from ..output.plots import math, new_figure, save_figure

    dataset = result.dataset
    variable = observable
    if observable == "final_state":
        variable = next(str(v) for v in dataset.data_vars if str(v).startswith("final_"))
    values = dataset[variable]
    dims = result.dims
    if len(dims) > 2:
        raise ModelError("a .png map needs one or two --grid axes (write .nc instead)")
    figure, axes = new_figure(width=6.5 if len(dims) == 2 else 7.5, height=5.5)
    axis = axes[0, 0]
    label = variable.replace("_", " ")

    def in_unit(text: str, name: str) -> str:  # a dimensioned model's unit (CF attribute)
        unit = dataset[name].attrs.get("units")
        return f"{text} [{unit}]" if unit else text

    if len(dims) == 2:
        from matplotlib.colors import LogNorm

        x, y = dataset[dims[1]].values, dataset[dims[0]].values
        data = np.ma.masked_invalid(values.values)
        norm = None
        if variable == "flip_time" and data.count() and float(data.max()) > 0:
            positive = data[data > 0]
            low = float(positive.min()) if positive.count() else float(result.attrs["dt"])
            norm = LogNorm(vmin=low, vmax=max(float(data.max()), low * 1.0001))
            data = np.ma.masked_less_equal(data, 0) if positive.count() else data
        elif variable in INDICATORS and data.count():  # decades: 1 down to 1e-16 and less
            norm = LogNorm(vmin=1e-16, vmax=max(float(data.max()), 1.0), clip=True)
            data = np.ma.maximum(data, 1e-16)
        image = axis.pcolormesh(x, y, data, shading="auto", norm=norm, cmap="viridis")
        figure.colorbar(image, ax=axis, label=in_unit(label, variable))
        axis.set_xlabel(in_unit(math(dims[1]), dims[1]))
        axis.set_ylabel(in_unit(math(dims[0]), dims[0]))
    else:
        axis.plot(dataset[dims[0]].values, values.values)
        axis.set_xlabel(in_unit(math(dims[0]), dims[0]))
        axis.set_ylabel(in_unit(label, variable))
    attrs = result.attrs
    title = f"{attrs['model']}: {label}, {attrs['method']} dt={attrs['dt']:g}"
    if variable == "flip_time" and len(dims) == 2:
        title += f"\n(white: no flip by t = {attrs['t_end']:g})"
    axis.set_title(title)
    save_figure(figure, path, dpi=120)

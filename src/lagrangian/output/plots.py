"""Plots of a motion: time series, phase portraits, drift of the invariants, Poincaré sections.

Every function takes a :class:`~lagrangian.trajectory.Trajectory` (and, where
the model adds something, the :class:`~lagrangian.model.System`) and returns a
matplotlib ``Figure``; :func:`save_figure` writes one atomically.  Axis labels
use the textbook notation of :func:`~lagrangian.output.notation.latex_name`
(``$\\dot{\\theta}$``), titles name the model.

Figures are built on the Agg canvas directly (``Figure`` + ``FigureCanvasAgg``,
no pyplot): nothing needs a display and no global backend state changes, so
the same code serves scripts, servers, tests and notebooks.  matplotlib is
imported only inside these functions.

The phase portraits and Poincaré sections live in
:mod:`lagrangian.output.phase`, the normal modes in
:mod:`lagrangian.output.mode_shapes`; :data:`PLOTS` maps the names the CLI
accepts to the functions.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..files import write_atomically
from ..trajectory import DRIFT_RELATIVE_FLOOR, Trajectory
from .notation import latex_name

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..model import System

#: Width of a figure and height of one row of panels, inches.
FIGURE_WIDTH, ROW_HEIGHT = 7.5, 1.9
#: Most coordinates drawn in one time series (the rest are left out, and the title says so).
MAX_ROWS = 6
#: File types :func:`save_figure` writes.
FIGURE_FORMATS = (".png", ".pdf", ".svg")
MACHINE_EPSILON = float(np.finfo(float).eps)


def new_figure(
    rows: int = 1,
    columns: int = 1,
    *,
    width: float = FIGURE_WIDTH,
    height: float | None = None,
    sharex: bool = False,
):
    """A Figure on the Agg canvas and its axes (a 2-D array ``rows`` x ``columns``); it
    shows itself in Jupyter (:mod:`.shown_figure`)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from .shown_figure import ShownFigure

    figure = ShownFigure(figsize=(width, height or 1.2 + ROW_HEIGHT * rows), layout="constrained")
    FigureCanvasAgg(figure)
    axes = figure.subplots(rows, columns, sharex=sharex, squeeze=False)
    return figure, axes


def save_figure(figure: Figure, path: str | os.PathLike, *, dpi: int = 100) -> Path:
    """Write ``figure`` to ``path`` (.png, .pdf, .svg) atomically: temporary file, then rename."""
    suffix = Path(path).suffix.lower()
    if suffix not in FIGURE_FORMATS:
        raise ModelError(f"cannot write '{suffix or path}' figures (use .png, .pdf or .svg)")
    return write_atomically(
        path, lambda temporary: figure.savefig(temporary, format=suffix[1:], dpi=dpi)
    )


def model_name(trajectory: Trajectory | None = None, system: System | None = None) -> str:
    """The model's name for titles: the system's, else the trajectory's ``model`` attribute."""
    if system is not None:
        return system.name
    if trajectory is not None and trajectory.dataset.attrs.get("model"):
        return str(trajectory.dataset.attrs["model"])
    return "trajectory"


def run_label(trajectory: Trajectory) -> str:
    """'variational, dt = 0.005' / 'dop853, rtol = 1e-10': how the run was made."""
    attrs = trajectory.dataset.attrs
    parts = [str(attrs["method"])] if attrs.get("method") else []
    for key in ("dt", "rtol"):
        if key in attrs:
            parts.append(f"{key} = {float(attrs[key]):g}")
    return ", ".join(parts)


def math(name: str) -> str:
    """``$\\dot{\\theta}_{1}$`` for 'theta1_dot'."""
    return f"${latex_name(name)}$"


def axis_label(trajectory: Trajectory, name: str) -> str:
    """``$\theta$ [rad]``: the name, and the unit its column carries (a dimensioned model's,
    or a file's ``units`` attribute)."""
    variable = trajectory.dataset.variables.get(name)
    unit = variable.attrs.get("units") if variable is not None else None
    return math(name) + (f" [{unit}]" if unit else "")


def plot_timeseries(trajectory: Trajectory, system: System | None = None) -> Figure:
    """q(t) (left) and q'(t) (right), one row per coordinate."""
    coordinates = trajectory.coordinates[:MAX_ROWS]
    if not coordinates:
        raise ModelError("the trajectory has no coordinates to plot")
    figure, axes = new_figure(len(coordinates), 2, sharex=True)
    t = trajectory.t
    for row, name in zip(axes, coordinates, strict=False):
        for ax, variable, color in zip(row, (name, f"{name}_dot"), ("C0", "C1"), strict=True):
            ax.plot(t, trajectory[variable], color=color, lw=1.3, label=math(variable))
            ax.set_ylabel(axis_label(trajectory, variable))
            ax.grid(True, alpha=0.3)
            ax.legend(loc="best", fontsize=8)
    for ax in axes[-1]:
        ax.set_xlabel(axis_label(trajectory, "t"))
    mark_impacts(axes.ravel(), trajectory)
    left_out = len(trajectory.coordinates) - len(coordinates)
    note = f" (first {len(coordinates)} of {len(trajectory.coordinates)} coordinates)"
    figure.suptitle(f"{model_name(trajectory, system)}: time series" + (note if left_out else ""))
    return figure


#: Impacts marked on a plot at most (the first ones; a ball coming to rest has hundreds).
MAX_IMPACT_MARKS = 400


def mark_impacts(axes, trajectory: Trajectory) -> None:
    """A thin vertical line at each impact's time (a model with contacts), on every axis."""
    times = [record.t for record in trajectory.impacts[:MAX_IMPACT_MARKS]]
    for ax in axes:
        for k, t in enumerate(times):
            label = "impacts" if k == 0 and ax is axes[0] else None
            ax.axvline(t, color="0.55", lw=0.6, ls=":", zorder=0, label=label)
    if times:
        axes[0].legend(loc="best", fontsize=8)


def drift_curve(values: np.ndarray) -> tuple[np.ndarray, bool]:
    """|X(t) - X(0)|, divided by |X(0)| when |X(0)| > 1e-12 (as ``Trajectory.drift``).

    Returns the curve (zeros as NaN: a log axis cannot show them) and whether it
    is relative.
    """
    values = np.asarray(values, dtype=float)
    deviation = np.abs(values - values[0])
    relative = abs(values[0]) > DRIFT_RELATIVE_FLOOR
    if relative:
        deviation = deviation / abs(values[0])
    return np.where(deviation > 0, deviation, np.nan), relative


def plot_energy_error(
    trajectories: Trajectory | Sequence[Trajectory],
    system: System | None = None,
    *,
    labels: Sequence[str] | None = None,
) -> Figure:
    """The drift |X(t) - X(0)| / |X(0)| of the energy and every invariant, log scale.

    One curve per quantity and run; for a conservative model the energy's drift
    is the integrator's error (for a forced, damped or time-dependent one it is
    physics).  The dotted line is double precision's rounding level.
    """
    runs = [trajectories] if isinstance(trajectories, Trajectory) else list(trajectories)
    if not runs:
        raise ModelError("no trajectory to plot")
    labels = list(labels) if labels is not None else [run_label(r) for r in runs]
    figure, axes = new_figure(1, 1, height=4.2)
    ax = axes[0, 0]
    styles = ["-", "--", "-.", ":"]
    shown = False
    for n, (run, label) in enumerate(zip(runs, labels, strict=True)):
        for i, name in enumerate(("energy", *run.invariants)):
            curve, relative = drift_curve(run[name])
            if not np.any(np.isfinite(curve)):
                continue
            what = "energy $h$" if name == "energy" else math(name)
            text = what + ("" if relative else " (absolute)") + (f", {label}" if label else "")
            ax.semilogy(run.t, curve, styles[i % 4], color=f"C{n}", lw=1.2, label=text)
            shown = True
    ax.axhline(MACHINE_EPSILON, color="0.5", lw=0.8, ls=":", label="machine $\\epsilon$")
    ax.set_yscale("log")
    ax.set_xlabel("$t$")
    ax.set_ylabel("$|X(t) - X(0)|\\,/\\,|X(0)|$")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    title = f"{model_name(runs[0], system)}: drift of the conserved quantities"
    figure.suptitle(title if shown else title + " (exactly conserved)")
    return figure


def plot(trajectory: Trajectory, kind: str, system: System | None = None) -> Figure:
    """The plot named ``kind`` (a key of :data:`PLOTS`) of one trajectory."""
    try:
        function = PLOTS[kind]
    except KeyError:
        raise ModelError(f"unknown plot kind '{kind}' (known: {', '.join(PLOTS)})") from None
    return function(trajectory, system)


def _phase(trajectory: Trajectory, system: System | None = None) -> Figure:
    from .phase import plot_phase_portrait

    return plot_phase_portrait(trajectory, system)


def _poincare(trajectory: Trajectory, system: System | None = None) -> Figure:
    from .poincare import plot_poincare

    return plot_poincare(trajectory, system)


#: Plot kinds by name (the CLI's ``--kind``): each f(trajectory, system=None) -> Figure.
PLOTS: dict[str, Callable[..., Figure]] = {
    "timeseries": plot_timeseries,
    "phase": _phase,
    "energy": plot_energy_error,
    "poincare": _poincare,
}

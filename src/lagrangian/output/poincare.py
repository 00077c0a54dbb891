"""Poincaré sections: the states where a run crosses q_c = 0 upwards.

The section is q_c = 0 (mod 2π for an angle, see
:func:`~lagrangian.output.phase.angle_coordinates`), q_c' > 0, with q_c the
first coordinate unless told.  The points are the event ``section`` of a run
(simulate with :func:`section_event`; its root finding puts them on the
section to the integrator's accuracy) or, when the run has none, the
crossings of its samples, linearly interpolated.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import LagrangianWarning, ModelError
from ..integrate import Event
from ..model import System
from ..trajectory import Trajectory
from .notation import latex_name
from .phase import angle_coordinates, pi_ticks, wrap
from .plots import axis_label, model_name, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Events named ``section_<q>`` hold the crossings of the section q = 0 (mod 2π).
SECTION_PREFIX = "section_"


def section_coordinate(system: System) -> str:
    """The default q_c: the first angle of the model, else its first coordinate."""
    angles = angle_coordinates(system)
    return next((q for q in system.coordinate_names if q in angles), system.coordinate_names[0])


def section_event(system: System, coordinate: str | None = None) -> Event:
    """The event ``section_<q_c>``: q_c crosses 0 (sin q_c for an angle, so every
    multiple of 2π, and π too: :func:`poincare_points` keeps the upward crossings of 0)."""
    name = coordinate or section_coordinate(system)
    index = system.coordinate_names.index(name)
    if name in angle_coordinates(system):
        return Event(lambda t, y, p: np.sin(y[index]), name=SECTION_PREFIX + name)
    return Event(lambda t, y, p: y[index], name=SECTION_PREFIX + name)


def recorded_section(trajectory: Trajectory) -> str | None:
    """q_c of the first ``section_<q_c>`` event the run recorded, else None."""
    for name in trajectory.events:
        if (
            name.startswith(SECTION_PREFIX)
            and name[len(SECTION_PREFIX) :] in trajectory.coordinates
        ):
            return name[len(SECTION_PREFIX) :]
    return None


def poincare_points(trajectory: Trajectory, coordinate: str | None = None) -> np.ndarray:
    """The states (2n, k) where q_c = 0 (mod 2π) with q_c' > 0.

    q_c: ``coordinate``, else the one of the run's section event, else the first
    coordinate.  The event's states are used when the run has one for q_c,
    otherwise the crossings between samples (linear interpolation).
    """
    names = trajectory.coordinates
    coordinate = coordinate or recorded_section(trajectory) or names[0]
    c, n = names.index(coordinate), len(names)
    record = trajectory.events.get(SECTION_PREFIX + coordinate)
    if record is not None:
        states = record.states
    else:
        y = np.stack([trajectory[v] for v in (*names, *trajectory.velocities)])
        x = wrap(y[c])
        hits = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0) & (np.diff(x) < np.pi))
        weight = -x[hits] / (x[hits + 1] - x[hits])
        states = y[:, hits] + weight * (y[:, hits + 1] - y[:, hits])
    keep = (states[n + c] > 0) & (np.cos(states[c]) > 0)
    return states[:, keep]


def plot_poincare(
    trajectories: Trajectory | Sequence[Trajectory],
    system: System | None = None,
    *,
    coordinate: str | None = None,
    labels: Sequence[str] | None = None,
    angles: Sequence[str] | None = None,
) -> Figure:
    """The Poincaré section q_c = 0, q_c' > 0: (q_j, q_j') of the other coordinates.

    q_c: ``coordinate``, else that of the first run's section event, else the
    model's first angle (:func:`section_coordinate`), else the first coordinate.
    """
    runs = [trajectories] if isinstance(trajectories, Trajectory) else list(trajectories)
    if not runs:
        raise ModelError("no trajectory to plot")
    names = runs[0].coordinates
    if len(names) < 2:
        raise ModelError("a Poincaré section needs at least two coordinates")
    c = coordinate or recorded_section(runs[0])
    c = c or (section_coordinate(system) if system is not None else names[0])
    others = [name for name in names if name != c][:3]
    wrapped = frozenset(angles) if angles is not None else angle_coordinates(system)
    figure, axes = new_figure(1, len(others), height=4.4)
    total = 0
    for n, run in enumerate(runs):
        points = poincare_points(run, c)
        total += points.shape[1]
        label = labels[n] if labels is not None else (None if len(runs) == 1 else f"run {n + 1}")
        for ax, name in zip(axes[0], others, strict=True):
            j = names.index(name)
            x = wrap(points[j]) if name in wrapped else points[j]
            ax.plot(x, points[len(names) + j], ".", ms=3, color=f"C{n}", label=label)
    for ax in axes[0]:
        _not_magnified(ax)
    for ax, name in zip(axes[0], others, strict=True):
        if name in wrapped:
            pi_ticks(ax)
        ax.set_xlabel(axis_label(runs[0], name))
        ax.set_ylabel(axis_label(runs[0], f"{name}_dot"))
        ax.grid(True, alpha=0.3)
        if labels is not None or len(runs) > 1:
            ax.legend(loc="upper right", fontsize=8, markerscale=3)
    where = f"${latex_name(c)} = 0$, ${latex_name(c + '_dot')} > 0$"
    count = f"{total} points" if total else "no crossing: a longer run may have some"
    if not total:  # the picture says so too, but a picture is not read by a script
        warnings.warn(
            LagrangianWarning(
                f"the run does not cross the section {c} = 0 upwards: the Poincaré section "
                "has no points (a longer run may have some)"
            ),
            stacklevel=2,
        )
    figure.suptitle(f"{model_name(runs[0], system)}: Poincaré section {where} ({count})")
    return figure


def _not_magnified(ax) -> None:
    """Points that (nearly) coincide, e.g. a periodic orbit's one point, stay one point:
    an axis spans at least 10 % of the size of its values, not their 1e-10 scatter."""
    lines = ax.get_lines()
    if not lines:
        return
    data = np.concatenate([line.get_xydata() for line in lines])
    data = data[np.all(np.isfinite(data), axis=1)]
    if data.size == 0:
        return
    for k, setter in ((0, ax.set_xlim), (1, ax.set_ylim)):
        low, high = data[:, k].min(), data[:, k].max()
        least = 0.1 * max(1.0, abs(low), abs(high))
        if high - low < least:
            middle = (low + high) / 2
            setter(middle - least / 2, middle + least / 2)

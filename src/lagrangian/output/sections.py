"""The points of a Poincaré section (:class:`~lagrangian.integrate.poincare.PoincareSection`)
drawn on its two axes, each orbit in its own colour."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..integrate.poincare import PoincareSection
from .phase import angle_coordinates, pi_ticks, wrap
from .plots import math, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Above this many orbits the colours come from a continuous map, not the cycle of ten.
CYCLE_COLOURS = 10


def plot_section(points: PoincareSection, *, size: float = 3.0) -> Figure:
    """The section's points, ``axes[1]`` against ``axes[0]``, coloured by orbit; an angle
    of the model (:func:`~lagrangian.output.phase.angle_coordinates`) wrapped to [-π, π)."""
    figure, axes = new_figure(width=6.5, height=6.0)
    axis = axes[0, 0]
    angles = angle_coordinates(points.system)
    first, second = (wrap(points[name]) if name in angles else points[name] for name in points.axes)
    count = points.orbit_count
    if count <= CYCLE_COLOURS:
        colours = [f"C{k}" for k in points.orbits]
    else:
        from matplotlib import colormaps

        colours = colormaps["turbo"](points.orbits / max(1, count - 1))
    axis.scatter(first, second, s=size, c=colours, linewidths=0, rasterized=True)
    for label, name in ((axis.set_xlabel, points.axes[0]), (axis.set_ylabel, points.axes[1])):
        unit = points.unit(name)  # a dimensioned model's: [rad], [m/s]
        label(math(name) + (f" [{unit}]" if unit else ""))
    axis.grid(True, alpha=0.3)
    if points.axes[0] in angles:
        pi_ticks(axis)
    settings = points.settings
    if settings.get("strobe") is not None:
        phase = settings.get("phase") or 0.0
        at = f" at phase {phase:.6g}" if phase else ""
        where = f"every {settings['strobe']:.6g}{at} after t = {settings['transient']:g}"
    else:
        sign = {1: ", upwards", -1: ", downwards"}.get(settings.get("direction"), "")
        where = f"{settings['section']}{sign}"
    energy = ""
    if points.count and np.ptp(points.energies) < 1e-6 * max(1.0, abs(points.energies[0])):
        energy = f", E = {points.energies[0]:.6g}"
    axis.set_title(
        f"{points.name}: section {where}{energy}\n{count} orbits, {points.count} points",
        fontsize=10,
    )
    return figure

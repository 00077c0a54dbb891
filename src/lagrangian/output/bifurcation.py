"""A bifurcation diagram drawn: the stroboscopic or section values of one variable against
the parameter (:class:`~lagrangian.ensemble.bifurcation.BifurcationDiagram`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..ensemble.bifurcation import BifurcationDiagram
from .phase import angle_coordinates, pi_ticks, wrap
from .plots import math, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def plot_bifurcation(diagram: BifurcationDiagram, *, size: float = 1.5) -> Figure:
    """Every kept point of every parameter value, black dots; an angle wrapped to
    [-π, π)."""
    figure, axes = new_figure(width=7.5, height=5.0)
    axis = axes[0, 0]
    samples = diagram.points.shape[1]
    values = diagram.points.ravel()  # a section's missing crossings (NaN) are not drawn
    angle = diagram.variable in angle_coordinates(diagram.system)
    if angle:
        values = wrap(values)
    axis.scatter(
        np.repeat(diagram.values, samples), values, s=size, c="k", linewidths=0, rasterized=True
    )
    if angle:
        pi_ticks(axis, "y")
    for label, name in ((axis.set_xlabel, diagram.parameter), (axis.set_ylabel, diagram.variable)):
        unit = diagram.unit(name)  # a dimensioned model's: [N], [rad]
        label(math(name) + (f" [{unit}]" if unit else ""))
    axis.grid(True, alpha=0.3)
    settings = diagram.settings
    strobed = "period" in settings
    where = (
        f"every {settings['period']:.6g}"
        + (f" at phase {settings['phase']:.6g}" if settings.get("phase") else "")
        if strobed
        else f"where {settings['section']} ({settings['direction']})"
    )
    per_value = samples if strobed else f"at most {samples}"
    axis.set_title(
        f"{diagram.name}: {math(diagram.variable)} {where} "
        f"after t = {settings['transient']:.6g} ({per_value} per value)",
        fontsize=10,
    )
    return figure

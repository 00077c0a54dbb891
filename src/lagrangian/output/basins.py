"""A basin map drawn and reported: each start coloured by its attractor, the attractors
listed (:class:`~lagrangian.ensemble.basins.BasinMap`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..ensemble.basins import Attractor, BasinMap
from .plots import math, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: The colour of the starts that reached no attractor.
NONE_COLOUR = "#bbbbbb"


def describe(attractor: Attractor) -> str:
    """'fixed point', 'period 3', 'chaotic (412 cells)'."""
    if attractor.kind == "periodic":
        return f"period {attractor.period}"
    if attractor.period is None:
        return f"{attractor.kind} ({attractor.cells} cells)"
    return attractor.kind


def plot_basins(basins: BasinMap) -> Figure:
    """The labels of a 2-D grid as an image, one colour per attractor (grey: none), the
    attractors' points marked, and a legend."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    figure, axes = new_figure(width=7.0, height=5.5)
    axis = axes[0, 0]
    x, y = basins.axes
    palette = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2"]
    count = len(basins.attractors)
    colours = [NONE_COLOUR] + [palette[k % len(palette)] for k in range(count)]
    axis.imshow(
        basins.labels.T + 1, origin="lower", aspect="auto", interpolation="nearest",
        cmap=ListedColormap(colours), vmin=-0.5, vmax=count + 0.5,
        extent=(x[0], x[-1], y[0], y[-1]),
    )  # fmt: skip
    rows = [basins.state_names.index(name) for name in basins.names]
    handles = []
    for attractor in basins.attractors:
        colour = colours[attractor.label + 1]
        points = attractor.points[rows]
        axis.plot(points[0], points[1], "o", ms=5, mfc="white", mec="black")
        share = 100.0 * attractor.starts / basins.labels.size
        text = f"{attractor.label}: {describe(attractor)}, {share:.3g} %"
        handles.append(Patch(facecolor=colour, edgecolor="black", label=text))
    none = int(np.count_nonzero(basins.labels < 0))
    if none:
        share = 100.0 * none / basins.labels.size
        handles.append(
            Patch(facecolor=NONE_COLOUR, edgecolor="black", label=f"none, {share:.3g} %")
        )
    axis.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    axis.set_xlabel(math(basins.names[0]))
    axis.set_ylabel(math(basins.names[1]))
    settings = basins.settings
    where = (
        f"strobe every {settings['period']:.6g}"
        + (f" at phase {settings['phase']:.6g}" if settings.get("phase") else "")
        if "period" in settings
        else f"flow sampled every {settings['interval']:.6g}"
    )
    axis.set_title(f"{basins.name}: basins of attraction ({where})", fontsize=10)
    return figure


def basins_json(basins: BasinMap) -> dict:
    """The attractors (label, kind, period, points as name -> value maps, cells, starts),
    the starts per label and the settings."""
    return {
        "model": basins.name,
        "grid": {
            name: {"from": float(v[0]), "to": float(v[-1]), "count": len(v)}
            for name, v in zip(basins.names, basins.axes, strict=True)
        },
        "attractors": [
            {
                "label": a.label,
                "kind": a.kind,
                "period": a.period,
                "points": [basins.point(point) for point in a.points.T],
                "cells": a.cells,
                "starts": a.starts,
            }
            for a in basins.attractors
        ],
        "counts": {str(label): count for label, count in basins.counts().items()},
        "starts": int(basins.labels.size),
        **dict(basins.settings),
    }


def basins_text(basins: BasinMap) -> str:
    """One line for the map, one per attractor."""
    lines = [
        f"{basins.name}: {len(basins.attractors)} attractors of {basins.labels.size} starts "
        f"({' x '.join(str(len(v)) for v in basins.axes)} of {', '.join(basins.names)})"
    ]
    for a in basins.attractors:
        point = ", ".join(f"{k} = {v:.6g}" for k, v in basins.point(a.points[:, 0]).items())
        lines.append(f"  {a.label}: {describe(a)}, {a.starts} starts; at {point}")
    none = basins.counts()[-1]
    if none:
        lines.append(f"  -1: no attractor reached, {none} starts")
    return "\n".join(lines)

"""Branches of periodic orbits followed in a parameter (``lagrangian orbits --vary``): as
JSON, as text, as a CSV table and drawn over the brute-force bifurcation diagram."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..files import write_csv
from ..integrate.floquet import as_json
from .orbits import multiplier_text, orbits_json

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..ensemble.bifurcation import BifurcationDiagram
    from ..integrate.continuation import Branch, Continuation

#: The markers of the bifurcations drawn, by kind.
MARKERS = {"period doubling": "o", "fold": "s", "branch point": "^", "Neimark-Sacker": "D"}


def continuation_json(continuation: Continuation) -> dict[str, object]:
    """The orbits JSON of the orbits found at the low end (``orbits``, as ``lagrangian
    orbits`` gives them) with the continuation's settings and ``branches``: a list of
    ``{period, parent, ended, points: [{parameter, point, multipliers, stable, kind}],
    bifurcations: [{kind, parameter, point, multipliers}]}``, each point the orbit's first
    as a name -> value map."""
    names = continuation.names
    base = orbits_json(continuation.search) if continuation.search is not None else {}
    return {
        **base,
        **continuation.settings,
        "branches": [
            {
                "period": branch.period,
                "parent": branch.parent,
                "ended": branch.ended,
                "points": [
                    {
                        "parameter": point.value,
                        "point": _named(names, point.points[:, 0]),
                        "multipliers": as_json(point.multipliers),
                        "stable": point.stable,
                        "kind": point.kind,
                    }
                    for point in branch.points
                ],
                "bifurcations": [
                    {
                        "kind": found.kind,
                        "parameter": found.value,
                        "point": _named(names, found.points[:, 0]),
                        "multipliers": as_json(found.multipliers),
                    }
                    for found in branch.bifurcations
                ],
            }
            for branch in continuation.branches
        ],
    }


def continuation_text(continuation: Continuation) -> str:
    """One line for the continuation, then for each branch a line and one per
    bifurcation on it."""
    count = len(continuation.branches)
    name = continuation.parameter
    strobe = continuation.strobe
    at = f" at phase {strobe.phase:.6g}" if strobe.phase else ""
    lines = [
        f"{continuation.name}: {count} branch{'es' if count != 1 else ''} of periodic orbits "
        f"of the strobe every {strobe.period:.6g}{at} followed in {name} from "
        f"{continuation.low:.6g} to {continuation.high:.6g}"
    ]
    names = ", ".join(continuation.names)
    for index, branch in enumerate(continuation.branches, 1):
        lines.append(f"  branch {index}: {_branch_line(continuation, branch)}")
        for found in branch.bifurcations:
            values = ", ".join(multiplier_text(value) for value in found.multipliers)
            point = ", ".join(f"{value:.6g}" for value in found.points[:, 0])
            lines.append(
                f"    {found.kind} at {name} = {found.value:.10g}: ({names}) = ({point}), "
                f"multipliers {values}"
            )
    return "\n".join(lines)


def _branch_line(continuation: Continuation, branch: Branch) -> str:
    first, last = branch.points[0].value, branch.points[-1].value
    origin = (
        f"found at {continuation.parameter} = {first:.6g}"
        if branch.parent is None
        else f"doubled from branch {branch.parent + 1}"
    )
    ended = {
        "range": "to the end of the range",
        "step": "ended where the steps became too small",
        "points": "ended after its most points",
        "closed": "closed: back at orbits it had passed",
    }[branch.ended]
    stable = sum(point.stable for point in branch.points)
    return (
        f"period {branch.period}, {origin}, {len(branch.points)} points from "
        f"{first:.6g} to {last:.6g} ({ended}), {stable} stable"
    )


def continuation_table(continuation: Continuation) -> tuple[np.ndarray, list[str]]:
    """(rows, headers): one row per orbit point of every branch point: the branch's number
    (from 1) and period, the parameter, the point's index in its orbit, the state, whether
    stable (1) or not (0)."""
    rows = []
    for index, branch in enumerate(continuation.branches, 1):
        for point in branch.points:
            for j, state in enumerate(point.points.T):
                rows.append([index, branch.period, point.value, j, *state, float(point.stable)])
    headers = ["branch", "period", continuation.parameter, "orbit_point", *continuation.names]
    return np.array(rows, dtype=float).reshape(-1, len(headers) + 1), [*headers, "stable"]


def write_continuation_csv(continuation: Continuation, path: str | os.PathLike) -> Path:
    """The table of :func:`continuation_table` as CSV, atomically."""
    rows, headers = continuation_table(continuation)
    return write_csv(path, rows, headers)


def plot_continuation(
    continuation: Continuation, variable: str, background: BifurcationDiagram | None = None
) -> Figure:
    """The branches in the plane (parameter, ``variable``): every point of each orbit,
    solid where stable, dashed where not, one colour per period; the bifurcations marked;
    over the brute-force diagram ``background`` (grey dots) when given.  Where an angle
    wraps (a jump over π) the line is broken."""
    from .plots import math, new_figure

    figure, axes = new_figure(width=7.5, height=5.0)
    axis = axes[0, 0]
    row = continuation.names.index(variable)
    if background is not None:
        samples = background.points.shape[1]
        axis.scatter(
            np.repeat(background.values, samples), background.points.ravel(), s=1.0,
            c="0.6", linewidths=0, rasterized=True, label="brute force",
        )  # fmt: skip
    colours = {}
    for branch in continuation.branches:
        colour = colours.setdefault(branch.period, f"C{len(colours) % 10}")
        values = np.array([point.value for point in branch.points])
        stable = np.array([point.stable for point in branch.points])
        for j in range(branch.period):
            y = np.array([point.points[row, j] for point in branch.points])
            for part, style in ((stable, "-"), (~stable, "--")):
                axis.plot(*_broken(values, y, part), style, color=colour, linewidth=1.2)
        for found in branch.bifurcations:
            axis.plot(
                np.full(branch.period, found.value), found.points[row], MARKERS[found.kind],
                color="k", markersize=4, markerfacecolor="none",
            )  # fmt: skip
    for period, colour in colours.items():
        axis.plot([], [], "-", color=colour, label=f"period {period} (dashed: unstable)")
    kinds = {found.kind for branch in continuation.branches for found in branch.bifurcations}
    for kind in sorted(kinds):
        axis.plot([], [], MARKERS[kind], color="k", markerfacecolor="none", label=kind)
    axis.legend(fontsize=8, loc="best")
    axis.set_xlabel(math(continuation.parameter))
    axis.set_ylabel(math(variable))
    axis.grid(True, alpha=0.3)
    axis.set_title(
        f"{continuation.name}: periodic orbits of the strobe every "
        f"{continuation.strobe.period:.6g} followed in {math(continuation.parameter)}",
        fontsize=10,
    )
    return figure


def _broken(x: np.ndarray, y: np.ndarray, keep: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) where ``keep`` (with the next point after each kept run, so that the solid and
    the dashed parts meet), y NaN elsewhere and across jumps over π (a wrapped angle)."""
    shown = keep | np.concatenate([[False], keep[:-1]])
    y = np.where(shown, y, np.nan)
    jumps = np.flatnonzero(np.abs(np.diff(y)) > np.pi) + 1
    return np.insert(x, jumps, np.nan), np.insert(y, jumps, np.nan)


def _named(names, values) -> dict[str, float]:
    return dict(zip(names, map(float, values), strict=True))

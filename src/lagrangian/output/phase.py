"""Phase portraits: (q, q') of every coordinate, with the separatrix for one coordinate.

Angles.  A coordinate on which the model is 2π-periodic (L, the forces and
the dissipation unchanged by q -> q + 2π, checked numerically at random
states) lives on a circle: :func:`angle_coordinates` finds them, and the plots
wrap them into [-π, π), so a rotating pendulum draws a band, not a ramp.

Separatrix.  For one degree of freedom and a conservative autonomous model,
h(q, q') is conserved and the phase curves are its level sets.  The
portrait draws a few of them in grey and, in red, the level of every saddle
(a local maximum of h(q, 0)): the separatrix between librations and rotations,
h = 2 m g l for the pendulum.  :func:`phase_family` simulates runs at a set of
energies below and above the separatrix.

Poincaré sections are in :mod:`lagrangian.output.poincare`.
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from ..algebra import as_expression
from ..analysis import energy_function
from ..derive import derive
from ..errors import ModelError
from ..integrate import simulate
from ..model import System
from ..numeric import compile_equations
from ..simulation import DEFAULT_T_END
from ..trajectory import Trajectory
from .plots import axis_label, model_name, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure


SEPARATRIX_COLOR = "#d62728"
#: Energies of :func:`phase_family`, as fractions of (separatrix - minimum).
FAMILY_FRACTIONS = (0.12, 0.4, 0.7, 0.92, 1.1, 1.35)
#: ... and of (the model's initial energy - minimum) when there is no separatrix.
FAMILY_FRACTIONS_NO_SADDLE = (0.25, 0.5, 1.0, 1.6, 2.3)
_GRID = 401


# -- angles ------------------------------------------------------------------------------
def angle_coordinates(system: System | None) -> frozenset[str]:
    """The coordinates on which the model is 2π-periodic (see the module docstring)."""
    if system is None:
        return frozenset()
    parts = [system.lagrangian, system.dissipation, *system.forces.values(), *system.constraints]
    if any(as_expression(part).atoms(AppliedUndef) for part in parts):
        return frozenset()  # unspecified functions: nothing is known
    arguments = list(system.state_symbols) + [p.symbol for p in system.parameters]
    try:
        functions = [sympy.lambdify(arguments, part, "math") for part in parts]
    except Exception:  # unspecified functions: nothing is known
        return frozenset()
    draw = random.Random(20240611)
    defaults = system.parameter_values
    angles = set()
    for c in system.coordinates:
        index = arguments.index(c.q)
        periodic = True
        for _ in range(4):
            point = [draw.uniform(-2.0, 2.0) for _ in system.state_symbols]
            point += [defaults.get(p.name, draw.uniform(0.5, 2.0)) for p in system.parameters]
            shifted = list(point)
            shifted[index] += 2 * np.pi
            try:
                a = [float(f(*point)) for f in functions]
                b = [float(f(*shifted)) for f in functions]
            except (ArithmeticError, TypeError, ValueError):
                periodic = False
                break
            if not np.allclose(a, b, rtol=1e-9, atol=1e-9):
                periodic = False
                break
        if periodic:
            angles.add(c.name)
    return frozenset(angles)


def wrap(values: np.ndarray) -> np.ndarray:
    """Angles in [-π, π)."""
    return (np.asarray(values, dtype=float) + np.pi) % (2 * np.pi) - np.pi


def _broken(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """NaN between consecutive points more than π apart in x (where a wrapped angle jumps)."""
    jumps = np.flatnonzero(np.abs(np.diff(x)) > np.pi) + 1
    return np.insert(x, jumps, np.nan), np.insert(y, jumps, np.nan)


def pi_ticks(ax, axis: str = "x") -> None:
    ticks = np.pi * np.array([-1, -0.5, 0, 0.5, 1])
    labels = ["$-\\pi$", "$-\\pi/2$", "$0$", "$\\pi/2$", "$\\pi$"]
    if axis == "x":
        ax.set_xlim(-np.pi, np.pi)
        ax.set_xticks(ticks, labels)
    else:
        ax.set_ylim(-np.pi, np.pi)
        ax.set_yticks(ticks, labels)


# -- energy levels -------------------------------------------------------------------------
def conservative_one_dof(system: System | None) -> bool:
    """One coordinate, no forces, dissipation, constraints or explicit time: h is conserved."""
    return (
        system is not None
        and len(system.coordinates) == 1
        and system.is_autonomous
        and not any(f != 0 for f in system.forces.values())
        and system.dissipation == 0
        and not system.constraints
    )


def energy_levels(system: System, parameters=None):
    """h(q, q') of a one-coordinate model as a NumPy function, at the parameter values."""
    c = system.coordinates[0]
    values = dict(system.parameter_values)
    values.update(parameters or {})
    h = energy_function(system).subs({p.symbol: values[p.name] for p in system.parameters})
    h = h.subs(system.time, 0)
    function = sympy.lambdify((c.q, c.q_dot), h, "numpy")

    def levels(q, v):
        shape = np.broadcast_shapes(np.shape(q), np.shape(v))
        return np.broadcast_to(np.asarray(function(q, v), dtype=float), shape)

    return levels


def saddles(h, q_range: tuple[float, float], *, periodic: bool) -> list[tuple[float, float]]:
    """(q, h) of the local maxima of h(q, 0) on ``q_range``: saddles of the phase plane."""
    q = np.linspace(*q_range, 4 * _GRID, endpoint=not periodic)
    u = h(q, np.zeros_like(q))
    if periodic:
        before, after = np.roll(u, 1), np.roll(u, -1)
        candidates = np.flatnonzero((u > before) & (u >= after))
    else:
        candidates = np.flatnonzero((u[1:-1] > u[:-2]) & (u[1:-1] >= u[2:])) + 1
    return [(float(q[i]), float(u[i])) for i in candidates if np.isfinite(u[i])]


def _q_range(runs: Sequence[Trajectory], name: str, angle: bool) -> tuple[float, float]:
    if angle:
        return (-np.pi, np.pi)
    values = np.concatenate([run[name] for run in runs])
    low, high = float(np.nanmin(values)), float(np.nanmax(values))
    pad = 0.15 * max(high - low, 1e-9)
    return (low - pad, high + pad)


# -- phase portrait -------------------------------------------------------------------------
def plot_phase_portrait(
    trajectories: Trajectory | Sequence[Trajectory],
    system: System | None = None,
    *,
    labels: Sequence[str] | None = None,
    angles: Sequence[str] | None = None,
) -> Figure:
    """(q, q') of every coordinate, one panel each; with the separatrix for one coordinate.

    One run is coloured by time; several runs get a colour each and a legend
    (``labels``, default their energy h).  ``angles``: coordinates to wrap into
    [-π, π) (default: those on which ``system`` is periodic).
    """
    runs = [trajectories] if isinstance(trajectories, Trajectory) else list(trajectories)
    if not runs:
        raise ModelError("no trajectory to plot")
    names = runs[0].coordinates[:4]
    wrapped = frozenset(angles) if angles is not None else angle_coordinates(system)
    columns = min(len(names), 2)
    rows = (len(names) + 1) // 2
    figure, axes = new_figure(rows, columns, height=0.9 + 3.6 * rows)
    colors = _run_colors(runs, by_energy=labels is None)
    if labels is None:
        labels = [f"$h$ = {run['energy'][0]:.3g}" for run in runs]
    for ax, name in zip(axes.flat, names, strict=False):
        angle = name in wrapped
        for n, run in enumerate(runs):
            x = wrap(run[name]) if angle else run[name]
            y = run[f"{name}_dot"]
            if len(runs) == 1:
                _time_coloured(figure, ax, run.t, x, y, angle)
            else:
                label = labels[n] if labels[n] not in labels[:n] else None  # mirrored runs
                ax.plot(*_broken(x, y) if angle else (x, y), color=colors[n], lw=1.1, label=label)
        extra = []
        if len(names) == 1 and conservative_one_dof(system):
            extra = _levels(ax, system, runs, name, angle)
        if angle:
            pi_ticks(ax)
        ax.set_xlabel(axis_label(runs[0], name))
        ax.set_ylabel(axis_label(runs[0], f"{name}_dot"))
        ax.grid(True, alpha=0.3)
        handles = ax.get_legend_handles_labels()[0] + extra
        if handles:
            outside = (
                {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0)} if len(names) == 1 else {}
            )
            ax.legend(handles=handles, fontsize=8, **({"loc": "upper right"} | outside))
    for ax in list(axes.flat)[len(names) :]:
        ax.set_visible(False)
    figure.suptitle(f"{model_name(runs[0], system)}: phase portrait")
    return figure


def _time_coloured(figure, ax, t, x, y, angle: bool) -> None:
    from matplotlib.collections import LineCollection

    points = np.column_stack([x, y])
    segments = np.stack([points[:-1], points[1:]], axis=1)
    if angle:  # no segment across the wrap
        segments = segments[np.abs(np.diff(x)) <= np.pi]
        times = t[:-1][np.abs(np.diff(x)) <= np.pi]
    else:
        times = t[:-1]
    lines = LineCollection(segments, cmap="viridis", linewidths=0.9)
    lines.set_array(times)
    ax.add_collection(lines)
    ax.autoscale_view()
    figure.colorbar(lines, ax=ax, label="$t$", pad=0.01)


def _levels(ax, system: System, runs, name: str, angle: bool) -> list:
    """Grey level curves of h, and the separatrix (the saddles' levels) in red; legend handles."""
    from matplotlib.lines import Line2D

    h = energy_levels(system, runs[0].parameters)
    q_low, q_high = _q_range(runs, name, angle)
    found = saddles(h, (q_low, q_high), periodic=angle)
    speeds = np.concatenate([np.abs(run[f"{name}_dot"]) for run in runs])
    top = float(np.nanmax(speeds)) if speeds.size else 1.0
    q = np.linspace(q_low, q_high, _GRID)
    v = np.linspace(0, 10 * max(top, 1.0), 4 * _GRID)
    below = h(q[:, None], v[None, :])
    for _, level in found:  # the separatrix must fit: the largest speed with h <= its level
        inside = (below <= level).any(axis=0)
        if inside.any():
            top = max(top, float(v[inside].max()))
    top = 1.1 * max(top, 1e-9)
    q = np.linspace(q_low, q_high, _GRID)
    v = np.linspace(-top, top, _GRID)
    grid = h(q[None, :], v[:, None])
    ax.contour(q, v, grid, levels=12, colors="0.82", linewidths=0.6, zorder=0)
    handles = []
    for q_s, level in sorted({round(lv, 9): (qs, lv) for qs, lv in found}.values()):
        contour = ax.contour(
            q,
            v,
            grid,
            levels=[level],
            colors=SEPARATRIX_COLOR,
            linewidths=1.8,
            linestyles="--",
            zorder=3,
        )
        contour.set_gid("separatrix")
        ax.plot([q_s], [0], "x", color=SEPARATRIX_COLOR, ms=8, mew=2, zorder=4)
        handles.append(
            Line2D(
                [],
                [],
                color=SEPARATRIX_COLOR,
                ls="--",
                lw=1.8,
                label=f"separatrix $h$ = {level:.4g}",
            )
        )
    ax.set_ylim(-top, top)
    if not angle:
        ax.set_xlim(q_low, q_high)
    return handles


def _run_colors(runs: Sequence[Trajectory], *, by_energy: bool) -> list:
    """A colour per run: along a colour map by initial energy, else the colour cycle."""
    if not by_energy:
        return [f"C{n % 10}" for n in range(len(runs))]
    from matplotlib import colormaps

    energies = np.array([run["energy"][0] for run in runs])
    span = float(np.ptp(energies)) or 1.0
    return [colormaps["viridis"](0.9 * (e - energies.min()) / span) for e in energies]


def phase_family(
    system: System,
    *,
    t_end: float | None = None,
    parameters=None,
    n_out: int = 2000,
    fractions: Sequence[float] | None = None,
) -> list[Trajectory]:
    """Runs of a one-coordinate conservative model at energies below and above its separatrix.

    Each run starts at the minimum q_c of h(q, 0) with q' > 0 chosen so that
    h = h(q_c, 0) + f (h_s - h(q_c, 0)) for f in ``fractions`` (default
    :data:`FAMILY_FRACTIONS`), h_s the lowest saddle level above the minimum;
    without a saddle, the model's initial energy takes its place.
    """
    from scipy.optimize import brentq

    if not conservative_one_dof(system):
        raise ModelError("a phase family needs one coordinate and a conservative model")
    name = system.coordinate_names[0]
    angle = name in angle_coordinates(system)
    h = energy_levels(system, parameters)
    q0 = float(system.initial.get(name, 0.0))
    q0_dot = float(system.initial.get(f"{name}_dot", 0.0))
    width = max(1.0, 2 * abs(q0))
    q_range = (-np.pi, np.pi) if angle else (q0 - width, q0 + width)
    q = np.linspace(*q_range, 4 * _GRID)
    u = h(q, np.zeros_like(q))
    centre = float(q[int(np.nanargmin(u))])
    bottom = float(np.nanmin(u))
    levels = sorted(level for _, level in saddles(h, q_range, periodic=angle) if level > bottom)
    interior = angle or 0 < int(np.nanargmin(u)) < q.size - 1
    reference = levels[0] if levels else float(h(np.array(q0), np.array(q0_dot)))
    if not interior or not reference > bottom:  # no minimum in sight: scale the initial state
        starts = [(q0 * f, q0_dot * f) for f in (0.5, 1.0, 1.5, 2.0)]
    else:
        chosen = fractions or (FAMILY_FRACTIONS if levels else FAMILY_FRACTIONS_NO_SADDLE)
        starts = []
        for f in chosen:
            target = bottom + f * (reference - bottom)
            top = 1.0
            while h(np.array(centre), np.array(top)) < target and top < 1e12:
                top *= 2
            speed = brentq(lambda v, e=target: float(h(np.array(centre), np.array(v))) - e, 0, top)
            starts.append((centre, speed))
            if levels and f > 1:  # a rotation: the one the other way round too
                starts.append((centre, -speed))
    compiled = compile_equations(derive(system))
    t_end = t_end or float(system.simulate_settings.get("t_end", DEFAULT_T_END))
    return [
        simulate(
            compiled,
            t_end=t_end,
            initial={name: a, f"{name}_dot": b},
            params=parameters,
            n_out=n_out,
        )
        for a, b in starts
    ]

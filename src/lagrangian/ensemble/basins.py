"""Basins of attraction: which attractor each start of a grid of states ends on.

The map iterated is the strobe map (the state at t = phase + k period, a driven
system's; its equations must repeat with the period) or, for an autonomous system, the
flow sampled every ``interval`` (the map y(t) -> y(t + interval)).  Attractors are found
by recurrence in a grid of cells over the state, as Attractors.jl's
``AttractorsViaRecurrences`` finds them: the state machine of
:mod:`lagrangian.ensemble.basins_numba` (a start that keeps landing in cells it visited
before has reached an attractor not yet known; one that lands in an attractor's cells a
few times in a row goes to that attractor; one that stays outside the box, or finds
nothing within ``max_iterations``, gets -1).  The box is the grid's: its variables must
be the whole state (every coordinate and velocity), and a coordinate on which the
equations are 2π-periodic (an angle, found as :mod:`lagrangian.integrate.orbits` finds
them) is taken modulo 2π about the middle of its range.  The cells are the grid's
points, at most ``cells`` along each variable (coarser cells find a chaotic attractor's
recurrences sooner).

The starts are integrated by rk4 (``steps`` steps per iteration) on the numba loop whose
terms that depend on time alone (a drive) are read from a table made once
(:mod:`lagrangian.codegen.time_terms`: every start steps at the same times), all members
of a pool together for CHUNK iterations, then labelled; the members done leave the pool
and new starts join it.  The first pool is small and its starts spread over the grid, so
the attractors are found by a few starts; the pool grows (four times, up to POOL) after
each chunk in which some start was labelled, and the later starts are labelled as soon
as they reach an attractor or, most of them, the cells of its basin: cells that only
starts labelled with that attractor passed through before them (where starts of two
attractors passed, on a fractal boundary, a cell counts for neither).
With ``backend="jax"`` the pool steps the same rk4 steps on the same grid through the JAX
ensemble's jitted loop (:mod:`lagrangian.ensemble.basins_jax`; a GPU where JAX has one);
the labeller runs on numba, on the host, for both.

Each attractor is classified from ``locate`` iterations on it: a fixed point (the map's
period 1; for the sampled flow an equilibrium), periodic of period K (K <= 64, the
points repeating to a quarter of a cell), or else ``chaotic`` (a strobe map's attractor
with no short period over many cells) or ``aperiodic`` (over few cells, or a flow's:
a limit cycle or a chaotic attractor of a flow sampled at a fixed interval have no period).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError, setting

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Recurrences in a start's own cells that make a new attractor (Attractors.jl: 100).
RECURRENCES = 40
#: Iterations in a row in an attractor's cells that label a start with it (Attractors.jl: 2).
HITS = 3
#: Iterations in a row in cells of an attractor's basin that label a start with it
#: (Attractors.jl: 10; 5 here, where a basin cell is one only that attractor's starts
#: passed: at 5 and at 10 the driven pendulum's labels are those of its map iterated
#: 300 periods, see basins_numba).
BASIN_HITS = 5
#: The cells of a start's last iterations that become its attractor's basin when labelled.
TRAIL = 32
#: Iterations in a row outside the box that label a start -1 (Attractors.jl: 20).
LOST = 20
#: Iterations after which a start that found nothing is labelled -1.
MAX_ITERATIONS = 2000
#: Iterations kept on a new attractor: its cells and its points.
LOCATE = 200
#: The most cells along a variable (coarser than a fine grid of starts).
CELLS = 250
#: Rk4 steps per iteration of the map.
STEPS = 100
#: Iterations integrated between labellings (one: no iteration is integrated after a
#: start is labelled, and every iteration steps the same times, so the map is one map).
CHUNK = 1
#: Starts integrated together at most, and in the first pool.
POOL, FIRST_POOL = 65_536, 256
#: The attractors a map may have; a start finding one more is labelled -1.
CAPACITY = 256
#: The longest period looked for.
MAX_PERIOD = 64
#: Where the starts are integrated (the labeller runs on numba, on the host, for both).
BACKENDS = ("numba", "jax")


@dataclass(frozen=True)
class Attractor:
    """One attractor: its ``label``, ``kind``, ``period`` (None: none found), its
    representative ``points`` (m, K) (the K points of a periodic orbit, else one point),
    its ``cells`` and the ``starts`` labelled with it."""

    label: int
    kind: str
    period: int | None
    points: np.ndarray
    cells: int
    starts: int


@dataclass(frozen=True)
class BasinMap:
    """``labels`` (shape of the grid): each start's attractor (-1: none reached)."""

    names: tuple[str, ...]
    axes: tuple[np.ndarray, ...]
    labels: np.ndarray
    attractors: tuple[Attractor, ...]
    state_names: tuple[str, ...]
    settings: Mapping[str, object] = field(default_factory=dict)
    name: str = ""

    def counts(self) -> dict[int, int]:
        """Starts per label, -1 included (0 when none)."""
        found = {a.label: a.starts for a in self.attractors}
        return {-1: int(np.count_nonzero(self.labels < 0)), **found}

    def table(self) -> np.ndarray:
        """(starts, len(names) + 1): the grid's values and the label, one row per start."""
        mesh = np.meshgrid(*self.axes, indexing="ij")
        return np.column_stack([*(m.ravel() for m in mesh), self.labels.ravel()])

    def to_csv(self, path: str | os.PathLike) -> Path:
        """The grid's columns and an integer ``attractor`` column, atomically."""
        from ..files import write_atomically

        table = self.table()

        def write(target: Path) -> None:
            with open(target, "w", encoding="utf-8") as stream:
                stream.write(",".join([*self.names, "attractor"]) + "\n")
                for *values, label in table:
                    stream.write(",".join([*(f"{v:.17g}" for v in values), str(int(label))]))
                    stream.write("\n")

        return write_atomically(path, write)

    def to_netcdf(self, path: str | os.PathLike) -> Path:
        """The labels as a NetCDF variable ``attractor`` over the grid's names, atomically;
        the attractors' kinds and periods as attributes."""
        import xarray as xr

        from ..files import write_atomically

        dataset = xr.Dataset(
            {"attractor": (self.names, self.labels.astype(np.int32))},
            coords={name: values for name, values in zip(self.names, self.axes, strict=True)},
            attrs={
                "model": self.name,
                "kinds": ",".join(a.kind for a in self.attractors),
                "periods": ",".join(str(a.period or 0) for a in self.attractors),
            },
        )
        return write_atomically(path, lambda target: dataset.to_netcdf(target))

    def point(self, point: np.ndarray) -> dict[str, float]:
        return {name: float(v) for name, v in zip(self.state_names, point, strict=True)}


def basins_of_attraction(
    compiled: CompiledSystem,
    *,
    grid: Mapping[str, object],
    period: float | None = None,
    phase: float | None = None,
    interval: float | None = None,
    params: Mapping[str, float] | None = None,
    steps: int = STEPS,
    cells: int = CELLS,
    max_iterations: int = MAX_ITERATIONS,
    basin_hits: int = BASIN_HITS,
    progress: Callable[[float], None] | None = None,
    backend: str = "numba",
) -> BasinMap:
    """The basins of the starts of ``grid`` ({state variable: (low, high, count)} or
    GridAxis values, covering the state) under the strobe map of ``period`` (at
    ``phase``) or the flow sampled every ``interval``; see the module docstring.
    ``basin_hits``: iterations in a row in cells of one attractor's basin (cells that only
    starts labelled with it passed) that label a start with it (fewer can be faster).
    ``backend``: where the starts are integrated, ``"numba"`` or ``"jax"`` (the same rk4
    steps on JAX's device, a GPU where JAX has one; :mod:`.basins_jax`)."""
    from ..integrate.orbits import _angles
    from ..integrate.strobe import Strobe

    state_names = (*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names))
    axes = _axes(grid, state_names)
    if compiled.has_constraints:
        raise ModelError("basins of constrained systems are not supported")
    for name, number in (
        ("steps", steps), ("cells", cells), ("max_iterations", max_iterations),
        ("basin_hits", basin_hits),
    ):  # fmt: skip
        if isinstance(number, bool) or int(number) != number or number < 1:
            raise ModelError(f"{name} must be a whole number >= 1, not {number!r}")
    if backend not in BACKENDS:
        raise ModelError(f"basins run on backend numba or jax, not {backend!r}")
    if (period is None) == (interval is None):
        raise ModelError("give a strobe period or, for an autonomous system, an interval")
    p = _parameters(compiled, params or {})
    names = tuple(axes)
    which = np.array([state_names.index(name) for name in names], dtype=np.int64)
    sizes = np.array([len(values) for values in axes.values()], dtype=np.int64)
    _check_memory(sizes, cells)
    lows = np.array([values[0] for values in axes.values()])
    highs = np.array([values[-1] for values in axes.values()])
    reduced = np.minimum(sizes, cells)
    widths = (highs - lows) / (reduced - 1)
    middle = np.column_stack([(lows + highs) / 2])
    start = np.zeros((len(state_names), 1))
    start[which] = middle
    angles = set(_angles(compiled, start, p).tolist())
    is_angle = np.array([int(i) in angles for i in which], dtype=np.bool_)
    if period is not None:
        clock = Strobe.of(period, phase)
        _check_periodic(compiled, clock.period, clock.phase, start, p)
        t0, span = clock.phase, clock.period
    else:
        if phase is not None:
            raise ModelError("a phase goes with a strobe period")
        from ..integrate.base import positive_setting

        span, t0 = positive_setting("interval", interval), 0.0
        _check_autonomous(compiled, span, start, p)
    walk = _Walk(
        compiled, p, t0, span, int(steps), which, lows, widths, reduced, is_angle,
        (lows + highs) / 2, int(max_iterations), int(basin_hits), backend,
    )  # fmt: skip
    labels, kept, found, alias = walk.run(axes, progress)
    attractors, labels = _attractors(walk, labels, kept, found, alias, period is not None)
    settings = {
        **({"period": clock.period, "phase": clock.phase} if period is not None else {}),
        **({"interval": span} if period is None else {}),
        "steps": int(steps), "dt": span / int(steps), "method": "rk4", "backend": backend,
        "cells": [int(c) for c in reduced],
        "angles": [name for name, angle in zip(names, is_angle, strict=True) if angle],
        "max_iterations": int(max_iterations), "recurrences": RECURRENCES, "hits": HITS,
        "lost": LOST, "locate": LOCATE, "basin_hits": int(basin_hits),
        "iterations": walk.iterations,
    }  # fmt: skip
    system = getattr(compiled.equations, "system", None)
    return BasinMap(
        names, tuple(axes.values()), labels, attractors, state_names, settings,
        getattr(system, "name", ""),
    )  # fmt: skip


def _parameters(compiled, params: Mapping[str, float]) -> np.ndarray:
    """The parameter vector with ``params`` (one number each) put in, checked."""
    for name, value in params.items():
        if name not in compiled.parameter_names:
            known = ", ".join(compiled.parameter_names) or "none"
            raise ModelError(f"unknown parameter '{name}' (parameters: {known})")
        if np.ndim(value) != 0:
            raise ModelError(f"basins take one value of each parameter, not several of '{name}'")
    compiled.check_parameters({name: np.asarray(v, dtype=float) for name, v in params.items()})
    return np.asarray(compiled.parameter_vector(dict(params)), dtype=float)


def _axes(grid: Mapping[str, object], state_names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The grid's values per variable, checked: state variables, covering the state,
    at least two values each."""
    axes = {}
    for name, spec in grid.items():
        if name not in state_names:
            known = ", ".join(state_names)
            raise ModelError(
                f"{setting('grid')} '{name}' is not a coordinate or velocity ({known})"
            )
        low, high, count = (
            (spec.low, spec.high, spec.count) if hasattr(spec, "low") else tuple(spec)  # type: ignore[attr-defined]
        )
        if int(count) != count or count < 2:
            raise ModelError(f"{setting('grid')} '{name}' needs at least 2 values, not {count!r}")
        if not (math.isfinite(low) and math.isfinite(high) and high > low):
            raise ModelError(
                f"{setting('grid')} '{name}' needs a range LO < HI, not {low:g} to {high:g}"
            )
        axes[name] = np.linspace(float(low), float(high), int(count))
    missing = [name for name in state_names if name not in axes]
    if missing:
        raise ModelError(
            "the grid must cover the whole state (" + ", ".join(state_names) + "): give "
            + " and ".join(f"{setting('grid')} {name}=LO:HI:N" for name in missing)
        )  # fmt: skip
    return axes


def _check_memory(sizes: np.ndarray, cells: int) -> None:
    """One line when the starts' labels and states would not fit in memory."""
    from ..integrate.memory import check_fits, count_text

    starts = math.prod(int(size) for size in sizes)  # Python ints: no overflow
    kept = math.prod(min(int(size), cells) for size in sizes)
    check_fits(
        8.0 * (3.0 * starts + kept) + 2.0 * kept + 8.0 * POOL * (len(sizes) * (CHUNK + 12) + TRAIL),
        f"a basin map of {count_text(starts)} starts",
        f"use fewer points per {setting('grid')}",
    )


def _check_periodic(compiled, period: float, phase: float, state, p) -> None:
    """ModelError unless the equations repeat with the period (one map every period)."""
    for t in phase + period * np.array([0.0, 0.37, 0.71]):
        now = np.asarray(compiled.rhs(t, state, p), dtype=float)
        later = np.asarray(compiled.rhs(t + period, state, p), dtype=float)
        if not np.all(np.abs(later - now) <= 1e-9 * (1.0 + np.abs(now))):
            raise ModelError(
                f"the equations are not periodic in t with the strobe period {period:g}: "
                f"give the drive's period as {setting('strobe')}"
            )


def _check_autonomous(compiled, interval: float, state, p) -> None:
    """ModelError when the equations depend on t (the sampled flow is then no one map)."""
    now = np.asarray(compiled.rhs(0.0, state, p), dtype=float)
    for t in (0.37 * interval, 1.3, 7.1):
        later = np.asarray(compiled.rhs(t, state, p), dtype=float)
        if not np.all(np.abs(later - now) <= 1e-12 * (1.0 + np.abs(now))):
            raise ModelError(
                f"the equations depend on t: give the drive's period as {setting('strobe')}"
            )


class _NumbaIterations:
    """``iterations(states)``: the states (B, m) after each of the CHUNK iterations of
    ``steps`` rk4 steps on ``grid``, (B, m, CHUNK), on the tabulated rk4 loop (numba); the
    same call as :class:`.basins_jax.JaxIterations`."""

    def __init__(self, compiled, p: np.ndarray, grid: np.ndarray, steps: int):
        from .numba_backend import tabulated_kernel

        self.p, self.grid, self.steps, self.m = p, grid, steps, 2 * compiled.n
        self.loop = tabulated_kernel(compiled, range(p.size))  # every member has p
        self.table = self.loop.table(grid, p)  # every chunk steps this same grid

    def __call__(self, states: np.ndarray) -> np.ndarray:
        count = states.shape[0]
        paths = np.empty((count, self.m, CHUNK + 1))
        final = np.empty_like(states)
        per_member = np.repeat(self.p[None, :], count, axis=0)
        self.loop.run(states, per_member, self.grid, self.table, self.steps, final, paths)
        return np.ascontiguousarray(paths[:, :, 1:])


class _Walk:
    """The pool of starts iterated and labelled (see the module docstring)."""

    def __init__(
        self, compiled, p, t0, span, steps, which, lows, widths, sizes, angles, centres, limit,
        basin_hits, backend="numba",
    ):  # fmt: skip
        from ..codegen.cache import load_text, package_text

        self.m = 2 * compiled.n
        grid = t0 + span * (np.arange(CHUNK * steps + 1) / steps)
        if backend == "jax":  # the same steps on the same grid, on JAX's device
            from .basins_jax import JaxIterations

            self.iterate = JaxIterations(compiled, p, grid, steps, FIRST_POOL)
        else:
            self.iterate = _NumbaIterations(compiled, p, grid, steps)
        self.labeller = load_text(*package_text(Path(__file__).with_name("basins_numba.py")))
        self.which, self.lows, self.widths = which, lows, widths
        self.sizes, self.angles, self.centres = sizes, angles, centres
        self.settings = np.array(
            [RECURRENCES, HITS, LOST, limit, LOCATE, basin_hits], dtype=np.int64
        )
        self.cells = np.full(int(np.prod(sizes)), -1, dtype=np.int64)
        self.seen = np.full(self.cells.size, -1, dtype=np.int16)  # UNSEEN (CAPACITY < 2**15)
        self.angle_rows = which[angles]
        self.iterations = 0

    def advance(self, states: np.ndarray) -> np.ndarray:
        """The states (B, m) after each of CHUNK iterations: (B, m, CHUNK)."""
        self.iterations += CHUNK * states.shape[0]
        return self.iterate(states)

    def run(self, axes, progress):
        """(labels of every start, the attractors' located points, how many were found)."""
        shape = tuple(len(v) for v in axes.values())
        total = int(np.prod(shape))
        order = np.argsort((np.arange(total) * 0.6180339887498949) % 1.0, kind="stable")
        # each start's label by its place in ``order`` (-2: not done); the labeller marks
        # cells with that place, so that the start taken first keeps its marks (see label)
        done_in_order = np.full(total, -2, dtype=np.int64)
        kept = np.zeros((CAPACITY, LOCATE, self.m))
        found = np.zeros(1, dtype=np.int64)
        alias = np.arange(CAPACITY, dtype=np.int64)
        ranks = np.empty(0, dtype=np.int64)
        states = np.empty((0, self.m))
        status = np.empty(0, dtype=np.int64)
        counters = np.empty((0, 8), dtype=np.int64)
        trail = np.empty((0, TRAIL), dtype=np.int64)
        values = list(axes.values())
        taken, done, pool = 0, 0, FIRST_POOL
        while taken < total or ranks.size:
            new = order[taken : taken + max(0, pool - ranks.size)]
            taken += new.size
            if new.size:
                index = np.unravel_index(new, shape)
                fresh = np.zeros((new.size, self.m))
                for d, row in enumerate(self.which):
                    fresh[:, row] = values[d][index[d]]
                ranks = np.concatenate([ranks, np.arange(taken - new.size, taken)])
                states = np.concatenate([states, fresh])
                status = np.concatenate([status, np.full(new.size, -2, dtype=np.int64)])
                counters = np.concatenate([counters, np.zeros((new.size, 8), dtype=np.int64)])
                trail = np.concatenate([trail, np.empty((new.size, TRAIL), dtype=np.int64)])
            points = self.advance(np.ascontiguousarray(states))
            self.labeller.label(
                points, ranks, status, counters, self.cells, self.which, self.lows, self.widths,
                self.sizes, self.angles, self.centres, self.settings, found, kept, alias,
                done_in_order, self.seen, trail,
            )  # fmt: skip
            states = points[:, :, -1].copy()
            if self.angle_rows.size:  # the map is the same a turn on: keep angles small
                states[:, self.angle_rows] = np.mod(states[:, self.angle_rows] + np.pi, 2 * np.pi)
                states[:, self.angle_rows] -= np.pi
            over = status >= -1
            done_in_order[ranks[over]] = status[over]
            finished = status[over]
            done += int(np.count_nonzero(over))
            keep = ~over
            ranks, states = ranks[keep], states[keep]
            status, counters, trail = status[keep], counters[keep], trail[keep]
            if np.any(finished >= 0):  # more starts once some have marked basins
                pool = min(POOL, 4 * pool)
            if progress is not None:
                progress(done / total)
        labels = np.empty(total, dtype=np.int64)
        labels[order] = done_in_order
        return labels.reshape(shape), kept, int(found[0]), alias

    def cell(self, point: np.ndarray) -> int:
        return int(
            self.labeller.cell_of(
                np.ascontiguousarray(point, dtype=float), self.which, self.lows, self.widths,
                self.sizes, self.angles, self.centres,
            )
        )  # fmt: skip

    def difference(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """a - b per grid variable, in cells (angles' differences modulo 2π)."""
        d = (a - b)[self.which]
        d[self.angles] = (d[self.angles] + np.pi) % (2 * np.pi) - np.pi
        return d / self.widths


def _attractors(walk: _Walk, labels, kept, found: int, alias, strobe: bool):
    """The attractors found (duplicates merged: one whose points lie in another's cells
    is that one, ``alias``) and the labels renumbered 0, 1, ... in the order found."""
    target = [int(walk.labeller.root(alias, k)) for k in range(found)]
    distinct = sorted(set(target))
    number = {old: new for new, old in enumerate(distinct)}
    mapping = np.array([number[target[k]] for k in range(found)] + [-1], dtype=np.int64)
    labels = mapping[labels]  # -1 indexes the last entry: -1
    attractors = []
    for new, old in enumerate(distinct):
        points = kept[old]
        period = _period(walk, points)
        cells = int(
            np.count_nonzero(np.isin(walk.cells, [k for k in range(found) if target[k] == old]))
        )
        shown = points[LOCATE - (period or 1) :].T.copy()
        shown[walk.which[walk.angles]] = (shown[walk.which[walk.angles]] + np.pi) % (
            2 * np.pi
        ) - np.pi
        kind = _kind(period, points, walk, strobe)
        starts = int(np.count_nonzero(labels == new))
        attractors.append(Attractor(new, kind, period, shown, cells, starts))
    return tuple(attractors), labels


def _period(walk: _Walk, points: np.ndarray) -> int | None:
    """The least K <= MAX_PERIOD with the later half of ``points`` repeating every K
    iterations to a quarter of a cell, or None."""
    later = points[LOCATE // 2 :]
    for k in range(1, min(MAX_PERIOD, later.shape[0] // 2) + 1):
        if all(
            np.max(np.abs(walk.difference(later[j + k], later[j]))) <= 0.25
            for j in range(later.shape[0] - k)
        ):
            return k
    return None


def _kind(period: int | None, points: np.ndarray, walk: _Walk, strobe: bool) -> str:
    if period == 1:
        return "fixed point"
    if period is not None:
        return "periodic"
    distinct = {walk.cell(point) for point in points}
    return "chaotic" if strobe and len(distinct) > LOCATE // 4 else "aperiodic"

"""Issue 35 item 4: how right the basin map's labels are, and why not all agree with a peer.

The driven damped pendulum's basin map (``basins_of_attraction``, as benchmarks/basins.py
runs it) is made once (or read from ``--labels FILE`` when that exists; written there
otherwise), then a random sample of its starts is run long, each as it would be labelled
by where it ends (the nearest attractor point within 0.05 after ``--periods`` periods):

- ``same bits``: the map the labeller iterates, bit for bit (the tabulated rk4 loop over
  the same grid of times, chunk after chunk, angles taken modulo 2π between chunks as the
  walk takes them).  Where the labeller's label differs from this, the labeller is wrong:
  that is its own error.
- ``t + one period``: the same loop with every time one drive period later (the drive's
  value differs by rounding only); ``h + 1 ulp``: the step one ulp longer; ``peer``: the
  hand-written rk4 kernel of benchmarks/basins.py (other arithmetic).  Where these differ
  from ``same bits``, rounding alone changes the attractor: the system's noise floor on
  this fractal boundary, which no labeller can beat against a peer of other arithmetic.

CPU seconds, one thread for the long runs.

    python benchmarks/basins_labeller.py [--size 1000] [--drive 1.073] [--samples 20000]
        [--periods 300] [--labels FILE]
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

import numba
import numpy as np

from lagrangian.budget import cpu_seconds
from lagrangian.derive import derive
from lagrangian.ensemble import basins
from lagrangian.ensemble.numba_backend import tabulated_kernel
from lagrangian.facade import load
from lagrangian.numeric import compile_equations

PERIOD = 3 * math.pi  # the drive's, omega = 2/3
STEPS = 100


def _basin_map(compiled, size, drive, path, basin_hits):
    """Labels (size, size) and the attractors' points [(2, K)] of the basin map, from
    ``path`` when it holds them."""
    if path and Path(path).exists():
        saved = np.load(path)
        points = [saved[f"points{k}"] for k in range(int(saved["count"]))]
        return saved["labels"], points, None
    grid = {"theta": (-math.pi, math.pi, size), "theta_dot": (-3.0, 3.0, size)}
    small = {"theta": (-math.pi, math.pi, 8), "theta_dot": (-3.0, 3.0, 8)}
    basins.basins_of_attraction(compiled, grid=small, period=PERIOD, params={"A": drive})
    cpu, wall = cpu_seconds(), time.perf_counter()
    found = basins.basins_of_attraction(
        compiled, grid=grid, period=PERIOD, params={"A": drive}, basin_hits=basin_hits
    )
    cpu, wall = cpu_seconds() - cpu, time.perf_counter() - wall
    per_start = found.settings["iterations"] / found.labels.size
    print(f"basin map {size} x {size}: {cpu:.1f} s CPU, {wall:.1f} s wall, "
          f"{per_start:.2f} iterations per start, counts {found.counts()}")  # fmt: skip
    points = [a.points for a in found.attractors]
    if path:
        arrays = {f"points{k}": p for k, p in enumerate(points)}
        np.savez(path, labels=found.labels, count=len(points), **arrays)
    return found.labels, points, found


def _long_run(compiled, drive, starts, periods, t0=0.0, stretch=0.0):
    """The states after ``periods`` iterations of the labeller's map (chunks of
    basins.CHUNK over the same grid of times, angles wrapped between chunks); ``t0``
    shifts the times, ``stretch`` ulps lengthen the step."""
    loop = tabulated_kernel(compiled, range(len(compiled.parameter_names)))
    p = np.asarray(compiled.parameter_vector({"A": drive}), dtype=float)
    chunk = basins.CHUNK
    grid = t0 + PERIOD * (np.arange(chunk * STEPS + 1) / STEPS)
    if stretch:
        h = np.nextafter(PERIOD / STEPS, np.inf)  # one ulp longer
        grid = t0 + h * np.arange(chunk * STEPS + 1)
    table = loop.table(grid, p)
    states = np.ascontiguousarray(starts.copy())
    per_member = np.repeat(p[None, :], len(states), axis=0)
    final = np.empty_like(states)
    for _ in range(periods // chunk):
        loop.run(states, per_member, grid, table, 0, final, np.empty((1, 1, 1)))
        states = final.copy()
        states[:, 0] = np.mod(states[:, 0] + np.pi, 2 * np.pi) - np.pi
    return states


def _nearest(finals, points, within=0.05):
    labels = np.full(len(finals), -1)
    best = np.full(len(finals), np.inf)
    for label, orbit in enumerate(points):
        for x, v in orbit.T:
            d = np.hypot(np.angle(np.exp(1j * (finals[:, 0] - x))), finals[:, 1] - v)
            closer = (d < best) & (d < within)
            labels[closer], best[closer] = label, d[closer]
    return labels


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=int, default=1000)
    parser.add_argument("--drive", type=float, default=1.073)
    parser.add_argument("--samples", type=int, default=20000)
    parser.add_argument("--periods", type=int, default=300)
    parser.add_argument("--labels", default="")
    parser.add_argument("--variants", default="same,shift,ulp,peer")
    parser.add_argument("--reference", default="", help="long runs saved by an earlier run")
    parser.add_argument("--basin-hits", type=int, default=basins.BASIN_HITS)
    args = parser.parse_args()
    compiled = compile_equations(derive(load("driven_damped_pendulum")))
    labels, points, _ = _basin_map(compiled, args.size, args.drive, args.labels, args.basin_hits)
    total = labels.size
    chosen = np.sort(np.random.default_rng(35).choice(total, args.samples, replace=False))
    axis_t = np.linspace(-math.pi, math.pi, args.size)
    axis_v = np.linspace(-3.0, 3.0, args.size)
    i, j = np.unravel_index(chosen, labels.shape)
    starts = np.column_stack([axis_t[i], axis_v[j]])
    ours = labels.ravel()[chosen]
    numba.set_num_threads(1)
    runs = {}
    if args.reference:  # the long runs of an earlier run, for the same sample
        saved = np.load(args.reference)
        assert np.array_equal(saved["chosen"], chosen)
        for name in saved.files:
            if name not in ("chosen", "ours"):
                runs[name] = saved[name]
                print(f"{name} (saved): labeller equal on {100 * np.mean(runs[name] == ours):.2f} %"
                      f" ({np.count_nonzero(runs[name] != ours)} differ)")  # fmt: skip
        before = saved["ours"]
        print(f"labels equal to the saved map's: {100 * np.mean(before == ours):.2f} %")
    for name in filter(None, args.variants.split(",")):
        cpu = cpu_seconds()
        if name == "same":
            finals = _long_run(compiled, args.drive, starts, args.periods)
        elif name == "shift":
            finals = _long_run(compiled, args.drive, starts, args.periods, t0=PERIOD)
        elif name == "ulp":
            finals = _long_run(compiled, args.drive, starts, args.periods, stretch=1.0)
        elif name == "peer":
            from basins import _peer  # benchmarks/basins.py

            finals = np.empty_like(starts)
            _peer(starts, args.drive, 0.5, 2 / 3, PERIOD, STEPS, args.periods, finals)
        else:
            raise SystemExit(f"unknown variant {name}")
        runs[name] = _nearest(finals, points)
        unsettled = np.count_nonzero(runs[name] < 0)
        print(f"{name}: {cpu_seconds() - cpu:.1f} s CPU; labeller equal on "
              f"{100 * np.mean(runs[name] == ours):.2f} % ({np.count_nonzero(runs[name] != ours)}"
              f" differ; not within 0.05 of an attractor: {unsettled})")  # fmt: skip
    if "same" in runs:
        for name, found in runs.items():
            if name != "same":
                differ = np.count_nonzero(found != runs["same"])
                print(f"{name} vs same bits: {100 * differ / args.samples:.2f} % differ ({differ})")
    if {"same", "shift", "peer"} <= runs.keys():
        # where rounding alone does not move a start (its attractor the same one period
        # later), the outcome is decided: there the map is checked against the peer
        decided = runs["same"] == runs["shift"]
        print(f"decided (same bits = t + one period): {100 * np.mean(decided):.2f} % of the "
              f"starts; there the labeller equals the peer on "
              f"{100 * np.mean(ours[decided] == runs['peer'][decided]):.2f} %")  # fmt: skip
    if args.labels and not args.reference:
        out = Path(args.labels).with_suffix(".runs.npz")
        np.savez(out, chosen=chosen, ours=ours, **runs)


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_NUM_THREADS", "2")
    main()

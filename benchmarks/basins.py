"""Issue 35 item 4: the basins of the driven damped pendulum on a 1000 x 1000 grid.

Ours: ``basins_of_attraction`` (the numba ensemble's rk4 loop, labelled between chunks by
recurrence on a grid of cells), CPU and wall seconds, compile excluded (a first run on a
small grid compiles).  The peer: a hand-written numba kernel of the same map (rk4, the
same steps per period) that integrates each start for ``--peer-periods`` periods and
labels it by the nearest point of the attractors ours found (within 0.05, else -1): run
on every k-th start (``--peer-starts`` of them) and its CPU time per start scaled up to
the whole grid; the labels of both compared on those starts.

    python benchmarks/basins.py [--size 1000] [--drive 1.073] [--steps 100]
        [--basin-hits 5] [--peer-periods 100] [--peer-starts 20000]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from numba import njit, prange

from lagrangian.budget import cpu_seconds
from lagrangian.derive import derive
from lagrangian.ensemble.basins import BASIN_HITS, basins_of_attraction
from lagrangian.facade import load
from lagrangian.numeric import compile_equations

PERIOD = 3 * math.pi  # the drive's, omega = 2/3


@njit(parallel=True, cache=True)
def _peer(starts, drive, damping, omega, period, steps, periods, out):  # pragma: no cover
    h = period / steps
    for i in prange(starts.shape[0]):
        x, v = starts[i, 0], starts[i, 1]
        for _ in range(periods):
            for s in range(steps):
                t = s * h
                a1 = -math.sin(x) - damping * v + drive * math.cos(omega * t)
                x2, v2 = x + 0.5 * h * v, v + 0.5 * h * a1
                a2 = -math.sin(x2) - damping * v2 + drive * math.cos(omega * (t + 0.5 * h))
                x3, v3 = x + 0.5 * h * v2, v + 0.5 * h * a2
                a3 = -math.sin(x3) - damping * v3 + drive * math.cos(omega * (t + 0.5 * h))
                x4, v4 = x + h * v3, v + h * a3
                a4 = -math.sin(x4) - damping * v4 + drive * math.cos(omega * (t + h))
                x += h / 6 * (v + 2 * v2 + 2 * v3 + v4)
                v += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
            x = (x + math.pi) % (2 * math.pi) - math.pi
        out[i, 0], out[i, 1] = x, v


def _nearest(finals, attractors):
    """The label of the nearest attractor point (within 0.05), else -1."""
    labels = np.full(len(finals), -1)
    best = np.full(len(finals), np.inf)
    for a in attractors:
        for x, v in a.points.T:
            dx = np.angle(np.exp(1j * (finals[:, 0] - x)))
            d = np.hypot(dx, finals[:, 1] - v)
            closer = (d < best) & (d < 0.05)
            labels[closer], best[closer] = a.label, d[closer]
    return labels


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=int, default=1000)
    parser.add_argument("--drive", type=float, default=1.073)
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--basin-hits", type=int, default=BASIN_HITS)
    parser.add_argument("--peer-periods", type=int, default=100)
    parser.add_argument("--peer-starts", type=int, default=20000)
    args = parser.parse_args()
    compiled = compile_equations(derive(load("driven_damped_pendulum")))
    params = {"A": args.drive}

    def grid(n):
        return {"theta": (-math.pi, math.pi, n), "theta_dot": (-3.0, 3.0, n)}

    basins_of_attraction(compiled, grid=grid(8), period=PERIOD, params=params, steps=args.steps)
    cpu, wall = cpu_seconds(), time.perf_counter()
    ours = basins_of_attraction(
        compiled, grid=grid(args.size), period=PERIOD, params=params, steps=args.steps,
        basin_hits=args.basin_hits,
    )  # fmt: skip
    cpu, wall = cpu_seconds() - cpu, time.perf_counter() - wall
    total = ours.labels.size
    print(f"driven damped pendulum A = {args.drive}, b = 0.5, omega = 2/3, {args.steps} rk4 "
          f"steps per period, basin hits {args.basin_hits}, "
          f"{args.size} x {args.size} starts")  # fmt: skip
    for a in ours.attractors:
        print(f"  attractor {a.label}: {a.kind}, period {a.period}, {a.starts} starts, at "
              f"{np.round(a.points[:, 0], 4).tolist()}")  # fmt: skip
    print(f"  none: {ours.counts()[-1]}")
    per_start = ours.settings["iterations"] / total
    print(f"ours: {cpu:.1f} s CPU, {wall:.1f} s wall, {per_start:.1f} map iterations per start")
    every = max(1, total // args.peer_starts)
    chosen = np.arange(0, total, every)
    mesh = np.meshgrid(*ours.axes, indexing="ij")
    starts = np.column_stack([mesh[0].ravel()[chosen], mesh[1].ravel()[chosen]])
    out = np.empty_like(starts)
    _peer(starts[:2].copy(), args.drive, 0.5, 2 / 3, PERIOD, args.steps, 1, out[:2])  # compile
    peer_cpu = cpu_seconds()
    _peer(starts, args.drive, 0.5, 2 / 3, PERIOD, args.steps, args.peer_periods, out)
    peer_cpu = cpu_seconds() - peer_cpu
    scaled = peer_cpu * total / len(chosen)
    labels = _nearest(out, ours.attractors)
    agree = np.mean(labels == ours.labels.ravel()[chosen])
    print(f"peer (hand-written numba rk4, {args.peer_periods} periods, nearest attractor): "
          f"{peer_cpu:.1f} s CPU for {len(chosen)} starts, {scaled:.0f} s CPU for the grid; "
          f"ours / peer {cpu / scaled:.2f}; labels agree on {100 * agree:.2f} % "
          f"(peer -1: {np.count_nonzero(labels < 0)})")  # fmt: skip


if __name__ == "__main__":
    main()

"""Seconds of the continuation of periodic orbits (issue 35 item 3) beside the brute-force
bifurcation diagram of the same range at the same parameter resolution.

    python benchmarks/continuation.py [--repeat 3] [--values 35] [--low 1.05] [--high 1.084]
                                      [--max-doublings 3] [--backend numba]

- Continuation: the driven damped pendulum's period-1 orbit found at A = ``--low`` (3
  strobe points after 50 periods as starts) followed to ``--high``, steps of at most
  (high - low) / (values - 1), with its period doublings and doubled branches (to
  ``--max-doublings``), each located to 1e-10 along the branch.
- Brute force: ``bifurcation`` over ``--values`` drives from low to high, 300 periods of
  transient and 40 strobe samples, rk4 with 200 steps per period, on ``--backend``: it
  shows the attractor at each drive, so it brackets each doubling between two of its
  values, (high - low) / (values - 1) apart.

Each runs once untimed first (numba compiles the loops, or loads them from the code
cache).  Printed: medians over the runs, wall-clock and this process's CPU seconds (the
machine may be shared), the map integrations and points of the continuation, and the
doublings it found.  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np

import lagrangian as lg

DRIVE_PERIOD = 3 * math.pi


def timed(function, repeat: int) -> tuple[float, float, object]:
    """(median wall seconds, median CPU seconds, the last result) of ``repeat`` runs."""
    walls, cpus, result = [], [], None
    for _ in range(repeat):
        start, cpu = time.perf_counter(), time.process_time()
        result = function()
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - cpu)
    return statistics.median(walls), statistics.median(cpus), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--values", type=int, default=35)
    parser.add_argument("--low", type=float, default=1.05)
    parser.add_argument("--high", type=float, default=1.084)
    parser.add_argument("--max-doublings", type=int, default=3)
    parser.add_argument("--backend", default="numba")
    args = parser.parse_args()
    system = lg.load("driven_damped_pendulum")

    def continuation():
        return system.continuation(
            vary={"A": (args.low, args.high, args.values)}, strobe=DRIVE_PERIOD, attractor=3,
            max_doublings=args.max_doublings, timeout=None,
        )  # fmt: skip

    def diagram():
        return system.bifurcation(
            vary={"A": np.linspace(args.low, args.high, args.values)}, variable="theta_dot",
            period=DRIVE_PERIOD, transient=300 * DRIVE_PERIOD, samples=40,
            backend=args.backend, timeout=None,
        )  # fmt: skip

    continuation(), diagram()  # compiled, or loaded from the code cache
    wall, cpu, result = timed(continuation, args.repeat)
    points = sum(len(branch.points) for branch in result.branches)
    doublings = sorted(
        b.value for branch in result.branches for b in branch.bifurcations
        if b.kind == "period doubling"
    )  # fmt: skip
    print(
        f"continuation, A = {args.low:g} to {args.high:g}, N = {args.values}: {wall:.2f} s "
        f"(CPU {cpu:.2f} s); {len(result.branches)} branches, {points} points, "
        f"{result.settings['map_runs']} map integrations; doublings at "
        + ", ".join(f"{value:.10f}" for value in doublings),
        flush=True,
    )
    wall, cpu, _ = timed(diagram, args.repeat)
    print(
        f"brute force, {args.values} values on {args.backend}: {wall:.2f} s (CPU {cpu:.2f} s); "
        f"each doubling bracketed to {(args.high - args.low) / (args.values - 1):.3g}",
        flush=True,
    )


if __name__ == "__main__":
    main()

"""Issue 35 item 4: the cost of a basin map's step.  The generated rk4 step of the driven
damped pendulum called through the typed-list function pointer that the ensemble's loop
uses (numba_stepping.run) against the same step called directly (numba specialises on
the dispatcher, so LLVM may inline it), and the two whole loops over members, the
ensemble's plain one and the tabulated one the basin map runs (codegen/time_terms.py: the
drive and M^-1 read from a table, the step over scalars), one thread, CPU ns per step;
the final states must be bitwise equal (the pendulum's m = l = g = 1 make the
tabulated step's regrouping exact).

    python benchmarks/basins_step.py [--members 2000] [--steps 1000] [--repeats 3]
"""

from __future__ import annotations

import argparse
import math
import statistics

import numba
import numpy as np
from numba import njit

from lagrangian.budget import cpu_seconds
from lagrangian.derive import derive
from lagrangian.ensemble.numba_backend import kernel, tabulated_kernel
from lagrangian.facade import load
from lagrangian.numeric import compile_equations


@njit
def _members(step, y0, p, size, stack, rows, columns, steps, h, out):  # pragma: no cover
    counts = np.zeros(3, dtype=np.int64)
    work = (np.empty(size), np.empty((stack, rows, columns)))
    for b in range(y0.shape[0]):
        y = y0[b].copy()
        for s in range(steps):
            step(s * h, h, y, p, work, 0.0, 0.0, 0, counts)
        out[b] = y


@njit
def _members_by_pointer(
    steppers, y0, p, size, stack, rows, columns, steps, h, out
):  # pragma: no cover
    _members(steppers[0], y0, p, size, stack, rows, columns, steps, h, out)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--members", type=int, default=2000)
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    compiled = compile_equations(derive(load("driven_damped_pendulum")))
    loop = kernel(compiled, "rk4")
    p = np.asarray(compiled.parameter_vector({"A": 1.073}), dtype=float)
    y0 = np.random.default_rng(1).uniform(-2.0, 2.0, (args.members, 2))
    h = 3 * math.pi / 100
    ways = {
        "direct": (_members, loop.system.step),
        "pointer": (_members_by_pointer, loop._steppers),
    }
    finals = {}
    for name, (run, step) in ways.items():
        out = np.empty_like(y0)
        run(step, y0[:2], p, *loop._sizes, 2, h, out[:2])  # compile
        times = []
        for _ in range(args.repeats):
            cpu = cpu_seconds()
            run(step, y0, p, *loop._sizes, args.steps, h, out)
            times.append(cpu_seconds() - cpu)
        finals[name] = out
        per_step = statistics.median(times) / (args.members * args.steps) * 1e9
        print(f"{name}: {per_step:.1f} ns CPU per step (median of {args.repeats})")
    print("final states bitwise equal:", np.array_equal(finals["direct"], finals["pointer"]))
    grid = h * np.arange(args.steps + 1)
    tabulated = tabulated_kernel(compiled, range(p.size))
    table = tabulated.table(grid, p)
    count = args.members
    loops = {
        "ensemble loop (plain step)": lambda out: loop.run(
            y0, np.repeat(p[None, :], count, axis=0), grid, False, False, 0, 0.0, 0.0, 0, out,
            np.empty(count), np.empty(count, dtype=np.int64), np.empty((1, 1, 1)),
            np.empty(count),
        ),
        "basins' loop (tabulated step)": lambda out: tabulated.run(
            y0, np.repeat(p[None, :], count, axis=0), grid, table, 0, out, np.empty((1, 1, 1))
        ),
    }  # fmt: skip
    numba.set_num_threads(1)
    for name, run in loops.items():
        out = np.empty_like(y0)
        times = []
        for _ in range(args.repeats):
            cpu = cpu_seconds()
            run(out)
            times.append(cpu_seconds() - cpu)
        finals[name] = out
        per_step = statistics.median(times) / (args.members * args.steps) * 1e9
        print(f"{name}: {per_step:.1f} ns CPU per step (median of {args.repeats})")
    print(
        "tabulated and plain final states bitwise equal:",
        np.array_equal(*list(finals.values())[2:]),
    )


if __name__ == "__main__":
    main()

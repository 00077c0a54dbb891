"""Issue 35 item 5: a regular/chaotic map of Hénon–Heiles starts at E = 1/8 from SALI
(and GALI_3) against the map from the largest Lyapunov exponent.

The starts: a grid on the section plane x = 0 (y, p_y = y'), x' > 0 solved from the energy
1/8 (the starts the energy does not allow left out).  The Lyapunov map: the ``lyapunov``
observable at ``--lyapunov-t`` (chaotic where the exponent exceeds ``--above``, 0.01: a
regular orbit's estimate falls like log(t)/t, below 0.005 at t = 2000, while the chaotic
sea's is about 0.045).  The indicators' map: ``sali`` and ``gali3`` at ``--sali-t``
(chaotic below 1e-8).  Both on the same ensemble backend (numpy, rk4, dt 0.05); CPU seconds
of each, and the share of starts both call the same.

    python benchmarks/indicators.py [--size 30] [--lyapunov-t 2000] [--sali-t 300]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from lagrangian.budget import cpu_seconds
from lagrangian.derive import derive
from lagrangian.ensemble import run_ensemble
from lagrangian.facade import load
from lagrangian.numeric import compile_equations

ENERGY = 0.125


def starts(size: int) -> dict[str, np.ndarray]:
    y, py = np.meshgrid(np.linspace(-0.45, 0.7, size), np.linspace(-0.5, 0.5, size))
    kinetic = 2 * (ENERGY - (y**2 / 2 - y**3 / 3)) - py**2
    inside = kinetic > 1e-6
    y, py = y[inside], py[inside]
    return {"x": 0 * y, "y": y, "x_dot": np.sqrt(kinetic[inside]), "y_dot": py}


def timed(compiled, initial, t_end, observables):
    cpu, wall = cpu_seconds(), time.perf_counter()
    result = run_ensemble(compiled, initial=initial, t_end=t_end, dt=0.05, observables=observables)
    return result.dataset, cpu_seconds() - cpu, time.perf_counter() - wall


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=int, default=30)
    parser.add_argument("--lyapunov-t", type=float, default=2000.0)
    parser.add_argument("--sali-t", type=float, default=300.0)
    parser.add_argument("--above", type=float, default=0.01)
    args = parser.parse_args()
    compiled = compile_equations(derive(load("henon_heiles")))
    initial = starts(args.size)
    count = len(initial["y"])
    timed(compiled, {k: v[:2] for k, v in initial.items()}, 1.0, ("sali", "lyapunov"))  # warm
    lyapunov, lyapunov_cpu, lyapunov_wall = timed(compiled, initial, args.lyapunov_t, ("lyapunov",))
    chaotic = lyapunov["lyapunov"].values > args.above
    print(f"Hénon–Heiles E = 1/8, {count} starts on x = 0 ({args.size} x {args.size} grid)")
    share = f"{np.mean(chaotic):.1%} chaotic (> {args.above:g})"
    print(f"lyapunov at t = {args.lyapunov_t:g}: {lyapunov_cpu:.1f} s CPU "
          f"({lyapunov_wall:.1f} s wall), {share}")  # fmt: skip
    for name in ("sali", "gali3"):
        result, cpu, wall = timed(compiled, initial, args.sali_t, (name,))
        called = result[f"{name}_chaotic"].values
        print(f"{name} at t = {args.sali_t:g}: {cpu:.1f} s CPU ({wall:.1f} s wall), "
              f"{np.mean(called):.1%} chaotic; cost / lyapunov's {cpu / lyapunov_cpu:.2f}; "
              f"agree on {np.mean(called == chaotic):.1%}")  # fmt: skip


if __name__ == "__main__":
    main()

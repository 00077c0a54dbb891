"""Issue 35 item 5: a regular/chaotic map of Hénon–Heiles starts at E = 1/8 from SALI
(and GALI_3) against the map from the largest Lyapunov exponent.

The starts: a grid on the section plane x = 0 (y, p_y = y'), x' > 0 solved from the energy
1/8 (the starts the energy does not allow left out).  The Lyapunov map: the ``lyapunov``
observable at ``--lyapunov-t`` (chaotic where the exponent exceeds ``--above``, 0.01: a
regular orbit's estimate falls like log(t)/t, below 0.005 at t = 2000, while the chaotic
sea's is about 0.045); with ``--long-t``, a second one over a longer run, to see how far
the reference itself moves.  The indicators' maps: ``sali`` asked alone at ``--sali-t``
(chaotic where SALI fell below 1e-4 at some step; each member stops there) and ``gali3``
at ``--gali-t`` (chaotic below 1e-8 at t_end).  All on one ensemble backend (``--backend``,
rk4, dt 0.05); CPU seconds of each after an untimed warm-up run (numba: the compile), and
the share of starts each calls as the Lyapunov map does.

    python benchmarks/indicators.py [--size 16] [--lyapunov-t 4000] [--sali-t 750]
        [--gali-t 700] [--long-t 10000] [--backend numpy]
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


def timed(compiled, initial, t_end, observables, backend):
    cpu, wall = cpu_seconds(), time.perf_counter()
    result = run_ensemble(
        compiled, initial=initial, t_end=t_end, dt=0.05, observables=observables, backend=backend
    )
    return result.dataset, cpu_seconds() - cpu, time.perf_counter() - wall


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=int, default=16)
    parser.add_argument("--lyapunov-t", type=float, default=4000.0)
    parser.add_argument("--sali-t", type=float, default=750.0)
    parser.add_argument("--gali-t", type=float, default=700.0)
    parser.add_argument("--long-t", type=float, default=0.0)
    parser.add_argument("--above", type=float, default=0.01)
    parser.add_argument("--backend", default="numpy")
    args = parser.parse_args()
    compiled = compile_equations(derive(load("henon_heiles")))
    initial = starts(args.size)
    count = len(initial["y"])
    two = {k: v[:2] for k, v in initial.items()}
    for names in (("lyapunov",), ("sali",), ("gali3",)):  # warm: numba compiles each loop
        timed(compiled, two, 1.0, names, args.backend)
    print(f"Hénon–Heiles E = 1/8, {count} starts on x = 0 ({args.size} x {args.size} grid), "
          f"backend {args.backend}")  # fmt: skip
    references = {}
    for t_end in (args.lyapunov_t, args.long_t) if args.long_t else (args.lyapunov_t,):
        lyapunov, cpu, wall = timed(compiled, initial, t_end, ("lyapunov",), args.backend)
        references[t_end] = (lyapunov["lyapunov"].values > args.above, cpu)
        print(f"lyapunov at t = {t_end:g}: {cpu:.1f} s CPU ({wall:.1f} s wall), "
              f"{np.mean(references[t_end][0]):.1%} chaotic (> {args.above:g})")  # fmt: skip
    if args.long_t:
        short, long = references[args.lyapunov_t][0], references[args.long_t][0]
        print(f"the two Lyapunov maps agree on {np.mean(short == long):.1%}")
    lyapunov_cpu = references[args.lyapunov_t][1]
    for name, t_end in (("sali", args.sali_t), ("gali3", args.gali_t)):
        result, cpu, wall = timed(compiled, initial, t_end, (name,), args.backend)
        called = result[f"{name}_chaotic"].values
        agree = "; ".join(f"agree with t = {t:g}'s on {np.mean(called == r):.1%}"
                          for t, (r, _) in references.items())  # fmt: skip
        print(f"{name} at t = {t_end:g}: {cpu:.1f} s CPU ({wall:.1f} s wall), "
              f"{np.mean(called):.1%} chaotic; cost / lyapunov's {cpu / lyapunov_cpu:.2f}; "
              f"{agree}")  # fmt: skip


if __name__ == "__main__":
    main()

"""Issue 34: the bouncing ball to rest (hundreds of impacts) in CPU seconds.

Runs, each ``--repeat`` times (medians; CPU = user + sys, never wall clock):

1. in this process, ``simulate_system`` of the ``bouncing_ball`` example to t_end (the
   ball at rest on the floor from t = 8.58 on), on the llvm backend (SciPy's DOP853 loop
   between impacts) and on numba (the compiled DOP853 loop; its machine code cached);
2. the same by hand: ``solve_ivp`` (DOP853, same tolerances) with the floor as a terminal
   event, restarted after each bounce with y' = -e y', stopped at the same impact count
   (the peer a user would write; it has no held contact, so it stops there);
3. ``lagrangian simulate bouncing_ball --json`` as a process, beside the start-up cost of
   ``lagrangian simulate harmonic_oscillator --json`` measured just before (the CLI's
   imports, derivation and compilation, which every run pays).

    python benchmarks/impacts.py [--repeat 3] [--t-end 20]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys


def cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def in_process(backend: str, t_end: float) -> tuple[float, int]:
    import lagrangian as lg
    from lagrangian.simulation import simulate_system

    system = lg.load("bouncing_ball")
    start = cpu()
    trajectory = simulate_system(system, t_end=t_end, backend=backend)
    return cpu() - start, len(trajectory.impacts)


def by_hand(count: int, t_end: float) -> float:
    import numpy as np
    from scipy.integrate import solve_ivp

    g, e = 9.81, 0.9

    def rhs(t, y):
        return np.array([y[2], y[3], 0.0, -g])

    def floor(t, y):
        return y[1]

    floor.terminal, floor.direction = True, -1
    start = cpu()
    t, y, impacts = 0.0, np.array([0.0, 1.0, 0.3, 0.0]), 0
    while impacts < count and t < t_end:
        solution = solve_ivp(rhs, (t, t_end), y, method="DOP853", rtol=1e-10, atol=1e-12,
                             events=floor)  # fmt: skip
        if solution.status != 1:
            break
        t, y = float(solution.t_events[0][0]), solution.y_events[0][0].copy()
        y[1], y[3] = 0.0, -e * y[3]
        impacts += 1
    return cpu() - start


def process(model: str, t_end: float, backend: str | None) -> float:
    command = [sys.executable, "-m", "lagrangian", "simulate", model, "--json",
               "--t-end", str(t_end)]  # fmt: skip
    if backend:
        command += ["--backend", backend]
    start = children_cpu()
    subprocess.run(command, check=True, capture_output=True, env=os.environ.copy())
    return children_cpu() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--t-end", type=float, default=20.0)
    args = parser.parse_args()
    in_process("numba", 1.0)  # the compiled loop's machine code built or loaded once
    for backend in ("llvm", "numba"):
        runs = [in_process(backend, args.t_end) for _ in range(args.repeat)]
        seconds = statistics.median(r[0] for r in runs)
        print(f"in process, {backend:5s}: {seconds:.3f} s CPU, {runs[0][1]} impacts")
    count = runs[0][1]
    hand = statistics.median(by_hand(count, args.t_end) for _ in range(args.repeat))
    print(f"solve_ivp by hand, {count} impacts: {hand:.3f} s CPU")
    for backend in (None, "numba"):
        pairs = []
        for _ in range(args.repeat):
            base = process("harmonic_oscillator", args.t_end, backend)
            ball = process("bouncing_ball", args.t_end, backend)
            pairs.append((base, ball))
        base = statistics.median(p[0] for p in pairs)
        ball = statistics.median(p[1] for p in pairs)
        name = backend or "default"
        print(f"CLI, backend {name}: ball {ball:.2f} s CPU, start-up (harmonic oscillator) "
              f"{base:.2f} s, the ball's run above it {ball - base:.2f} s")  # fmt: skip


if __name__ == "__main__":
    main()

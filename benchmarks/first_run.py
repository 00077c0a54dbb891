"""Seconds of a typical first run on each backend: compile the equations, then integrate.

    python benchmarks/first_run.py [--repeat 3] [--links 10]

Each measurement runs in a fresh process (the compiled functions and numba's
machine code live per process and in the code cache): the double pendulum for its
model's 20 s and the ``--links`` chain for 10 s, DOP853 at the default tolerances,
from the equations of motion (derived before the clock starts) to the end of the
integration (``Integrator.solve``; building the Trajectory, which is the same for
every backend, is not counted).  Backends: ``numpy`` (lambdify), ``llvm``
(SymEngine's LLVM Lambdify), ``numba`` cold (an empty code cache: generate and
compile) and ``numba`` cached (a second process on that cache).  Printed: medians
over ``--repeat`` processes of compile seconds, integrate seconds, their sum, and
the sum relative to the fastest.  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

CHILD = """
import json, sys, time
sys.path.insert(0, {folder!r})
import lagrangian as lg
from lagrangian.integrate.registry import method_class
from lagrangian.numeric import compile_equations
from rhs import chain_pendulum
links, backend = {links}, {backend!r}
system = lg.load("double_pendulum") if links == 2 else chain_pendulum(links)
t_end = 20.0 if links == 2 else 10.0
initial = {{"theta1": 2.0, "theta2": 0.5}} if links == 2 else {{"theta1": 0.5}}
eom = system.equations_of_motion()
start = time.perf_counter()
compiled = compile_equations(eom, backend=backend)
y0, params = compiled.state_vector(initial), compiled.parameter_vector()
compiled.rhs(0.0, y0, params)  # the first call makes the code
made = time.perf_counter()
integrator = method_class("dop853").configure(t_span=(0.0, t_end))
result = integrator.solve(compiled, (0.0, t_end), y0, params)
done = time.perf_counter()
print(json.dumps([made - start, done - made, result.rhs_evaluations]))
"""


def child(links: int, backend: str, cache: str) -> tuple[float, float, int]:
    code = CHILD.format(folder=str(Path(__file__).resolve().parent), links=links, backend=backend)
    environment = dict(os.environ, LAGRANGIAN_CACHE=cache)
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=environment, check=True
    )
    return tuple(json.loads(done.stdout.strip().splitlines()[-1]))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--links", type=int, default=10)
    args = parser.parse_args(argv)
    print(
        f"{'system':>16} {'backend':>14} {'compile s':>10} {'integrate s':>12} {'total s':>8} "
        f"{'rhs calls':>10} {'/ fastest':>10}"
    )
    for links in (2, args.links):
        label = "double pendulum" if links == 2 else f"{links}-link chain"
        backends = ("numpy", "llvm", "numba cold", "numba cached")
        runs: dict[str, list] = {backend: [] for backend in backends}
        for _ in range(args.repeat):  # interleaved, so that each backend sees the same load
            for backend in backends:
                with tempfile.TemporaryDirectory() as cache:
                    name = backend.split()[0]
                    if backend == "numba cached":
                        child(links, name, cache)  # fills the cache
                    runs[backend].append(child(links, name, cache))
        rows = {b: [statistics.median(r[i] for r in runs[b]) for i in range(3)] for b in backends}
        fastest = min(compile + run for compile, run, _ in rows.values())
        for backend, (compile, run, calls) in rows.items():
            print(
                f"{label:>16} {backend:>14} {compile:>10.3f} {run:>12.3f} {compile + run:>8.3f} "
                f"{calls:>10.0f} {(compile + run) / fastest:>10.2f}",
                flush=True,
            )
    print("total: compile + integrate in a fresh process (median); / fastest: same system")


if __name__ == "__main__":
    main()

"""Issue 34, item 3: constrained runs in the compiled loop against SciPy's loop.

A four-bar linkage written by hand (three rod angles, two loop-closure constraints; the
model of tests/integrate/test_constrained_compiled.py, started on its loop):

1. ``lagrangian simulate FOUR_BAR.toml --t-end 10 --json`` as a process, in CPU seconds
   (user + sys, the start-up included), three ways: the default (the run's choice), the
   compiled loop (``--backend numba``) and SciPy's loop (``--backend llvm``), each with an
   empty code cache (a first run: derive, compile, run) and with the cache it left;
2. in this process, after a warm-up, the run alone to t = 1000 (every step kept): CPU
   seconds, steps, and the largest constraint residual |c(q)| over the steps, for the
   compiled loop (projected every step) and SciPy's loop (Baumgarte's damping only);
3. the numba ensemble of the Cartesian pendulum against the numpy backend (rk4, projected
   every step), CPU seconds.

    python benchmarks/constrained.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

FOUR_BAR = """
name = "Four-bar linkage (by hand)"
coordinates = ["th1", "th2", "th3"]
kinetic = "m1*a^2*th1_dot^2/6 + m2*(a^2*th1_dot^2 + b^2*th2_dot^2/4 + a*b*th1_dot*th2_dot*cos(th1 - th2))/2 + m2*b^2*th2_dot^2/24 + m3*c^2*th3_dot^2/6"
potential = "g*(m1*a*sin(th1)/2 + m2*(a*sin(th1) + b*sin(th2)/2) + m3*c*sin(th3)/2)"
constraints = ["a*cos(th1) + b*cos(th2) - c*cos(th3) - d", "a*sin(th1) + b*sin(th2) - c*sin(th3)"]

[parameters]
m1 = 1.0
m2 = 2.0
m3 = 1.5
a = 1.0
b = 3.0
c = 2.5
d = 3.0
g = 9.81

[initial]
th1 = 1.2
th2 = 0.5494695839183232
th3 = 1.6024965614242583
th1_dot = 3.0
th2_dot = -0.4508058092298827
th3_dot = 0.8363552307291638
"""  # noqa: E501  (a state on the loop: tests/integrate/test_constrained_compiled.py)

WAYS = {"default": [], "compiled loop": ["--backend", "numba"], "SciPy loop": ["--backend", "llvm"]}


def process_cpu(argv: list[str], env: dict[str, str]) -> float:
    """CPU seconds (user + sys) of one run of ``argv`` as a child process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(argv, env=env, check=True, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def command_line(model: Path, repeat: int) -> None:
    command = [sys.executable, "-m", "lagrangian", "simulate", str(model), "--t-end", "10"]
    for way, options in WAYS.items():
        cold, warm = [], []
        for _ in range(repeat):
            with tempfile.TemporaryDirectory() as cache:
                env = os.environ | {"LAGRANGIAN_CACHE": cache}
                argv = [*command, *options, "--json"]
                cold.append(process_cpu(argv, env))
                warm.append(process_cpu(argv, env))
        print(
            f"four-bar simulate --t-end 10, {way}: CPU median of {repeat}: "
            f"{statistics.median(cold):.2f} s with an empty cache "
            f"(range {min(cold):.2f}-{max(cold):.2f}), {statistics.median(warm):.2f} s with "
            f"the cache it left (range {min(warm):.2f}-{max(warm):.2f})"
        )


def long_runs(text: str) -> None:
    import lagrangian as lg
    from lagrangian.integrate import simulate
    from lagrangian.integrate.simulate import along
    from lagrangian.numeric import compile_equations

    eom = lg.loads(text).equations_of_motion()
    for way, backend in (("compiled loop", "numba"), ("SciPy loop", "llvm")):
        compiled = compile_equations(eom, backend=backend)
        simulate(compiled, t_end=1.0)  # compiled, kernels made
        start = time.process_time()
        run = simulate(compiled, t_end=1000.0)
        seconds = time.process_time() - start
        states = np.stack([run[name] for name in (*run.coordinates, *run.velocities)])
        params = compiled.parameter_vector({})
        residual = np.abs(along(compiled.constraint_residual, run.t, states, params)).max()
        energy = np.abs(run["energy"] - run["energy"][0]).max() / np.abs(run["energy"]).max()
        print(
            f"four-bar t = 1000 in this process, {way}: {seconds:.2f} s CPU, "
            f"{run.dataset.attrs['steps']} steps, largest |c(q)| {residual:.1e}, "
            f"energy drift {energy:.1e} (relative)"
        )


def ensembles() -> None:
    import lagrangian as lg
    from lagrangian.ensemble import run_ensemble
    from lagrangian.numeric import compile_equations

    compiled = compile_equations(lg.load("cartesian_pendulum").equations_of_motion())
    angle = np.linspace(0.2, 2.5, 256)
    initial = {"x": np.sin(angle), "y": -np.cos(angle)}
    for backend in ("numba", "numpy"):
        options = {"initial": initial, "t_end": 10.0, "dt": 0.002, "backend": backend}
        run_ensemble(compiled, **(options | {"t_end": 0.01}))  # compiled, kernels made
        start = time.process_time()
        run_ensemble(compiled, **options)
        seconds = time.process_time() - start
        print(
            f"Cartesian pendulum ensemble, 256 members, rk4 dt 0.002 to t = 10, {backend}: "
            f"{seconds:.2f} s CPU"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    options = parser.parse_args()
    warnings.simplefilter("ignore")
    with tempfile.TemporaryDirectory() as folder:
        model = Path(folder) / "four_bar_by_hand.toml"
        model.write_text(FOUR_BAR, encoding="utf-8")
        command_line(model, options.repeat)
        os.environ["LAGRANGIAN_CACHE"] = str(Path(folder) / "cache")
        long_runs(FOUR_BAR)
        ensembles()


if __name__ == "__main__":
    main()

"""CPU seconds of a new system's first long run: compile the equations, then integrate.

    python benchmarks/first_run.py [--repeat 3] [--links 10 | 0] [--skip-cli]

Each measurement runs in a fresh process (the compiled functions and numba's machine
code live per process and in the code cache, ``$LAGRANGIAN_CACHE``, a new temporary
folder for each measurement), in CPU seconds (user + system: the machine is shared),
medians over ``--repeat`` processes.

Part 1, in-process (``Integrator.solve``): the double pendulum from (2.0, 0.5) to
t = 1000 and the ``--links`` chain from theta1 = 0.5 to t = 100, DOP853 at the default
tolerances, from the equations of motion (derived before the clock starts) to the end of
the integration: "compile" is ``compile_equations``, the first y' and the integrator's
``prepare`` where it has one (the loop made or loaded), "integrate" the rest.  Ways:

- ``llvm, SciPy's loop``: SymEngine's LLVM y' in SciPy's DOP853 (no cache);
- ``numba``: the system's own compiled loop, three states of the code cache: ``empty``
  (the first run on a machine), ``new system`` (the cache holds another system's run, a
  3-link chain: the method shared by every system is there) and ``cached`` (this
  system ran before);
- ``linked`` (where the code has it, ``Dop853(linked=True)``): the same loop over the llvm
  backend's code of M and f, ``empty`` and ``new system``.

Part 2 (without ``--skip-cli``), the command a user types, ``lagrangian simulate MODEL
--t-end 1000 --method dop853`` (the default's method without heyoka), CPU of the child
process: an empty code cache, after another system's run (``simulate spherical_pendulum
--t-end 1000 --method dop853`` first), and the same command again; ``lagrangian
--version`` (the start-up) beside them.  Nothing is asserted.  Run it on two trees (say
``PYTHONPATH=/path/to/tree/src``) for a before and an after.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

CHILD = """
import dataclasses, json, sys, time
sys.path.insert(0, {folder!r})
import lagrangian as lg
from lagrangian.integrate.registry import method_class
from lagrangian.numeric import compile_equations
from rhs import chain_pendulum
links, way = {links}, {way!r}
system = lg.load("double_pendulum") if links == 2 else chain_pendulum(links)
t_end = 1000.0 if links == 2 else 100.0
initial = {{"theta1": 2.0, "theta2": 0.5}} if links == 2 else {{"theta1": 0.5}}
eom = system.equations_of_motion()
integrator = method_class("dop853").configure(t_span=(0.0, t_end))
if way == "linked":
    if "linked" not in {{f.name for f in dataclasses.fields(integrator)}}:
        print(json.dumps(None))
        raise SystemExit
    integrator = dataclasses.replace(integrator, linked=True)
start = time.process_time()
compiled = compile_equations(eom, backend="numba" if way == "numba" else "llvm")
y0, params = compiled.state_vector(initial), compiled.parameter_vector()
compiled.rhs(0.0, y0, params)  # the first call makes the code
if hasattr(integrator, "prepare"):
    integrator.prepare(compiled, y0, params)
made = time.process_time()
result = integrator.solve(compiled, (0.0, t_end), y0, params)
done = time.process_time()
print(json.dumps([made - start, done - made, result.steps]))
"""
FOLDER = str(Path(__file__).resolve().parent)


def child(links: int, way: str, cache: str) -> list[float] | None:
    code = CHILD.format(folder=FOLDER, links=links, way=way)
    environment = dict(os.environ, LAGRANGIAN_CACHE=cache)
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=environment, check=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def in_process(links: int, way: str, state: str) -> list[float] | None:
    """[compile s, integrate s, steps] of one fresh process with the code cache in ``state``."""
    with tempfile.TemporaryDirectory() as cache:
        if state == "new system":
            child(3, way if way != "llvm" else "numba", cache)
        elif state == "cached":
            child(links, way, cache)
        return child(links, way, cache)


def cli_seconds(arguments: list[str], cache: str) -> float:
    """CPU seconds (user + system) of ``lagrangian ARGUMENTS`` as a child process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    environment = dict(os.environ, LAGRANGIAN_CACHE=cache)
    subprocess.run(
        [sys.executable, "-m", "lagrangian", *arguments],
        capture_output=True, env=environment, check=True,
    )  # fmt: skip
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def cli_runs(model: str) -> dict[str, float]:
    run = ["simulate", model, "--t-end", "1000", "--method", "dop853"]
    other = ["simulate", "spherical_pendulum", "--t-end", "1000", "--method", "dop853"]
    seconds = {}
    with tempfile.TemporaryDirectory() as cache:
        seconds["start-up (--version)"] = cli_seconds(["--version"], cache)
        seconds["empty cache"] = cli_seconds(run, cache)
    with tempfile.TemporaryDirectory() as cache:
        cli_seconds(other, cache)
        seconds["new system"] = cli_seconds(run, cache)
        seconds["same system again"] = cli_seconds(run, cache)
    return seconds


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--links", type=int, default=10, help="the chain's links (0: none)")
    parser.add_argument("--skip-cli", action="store_true")
    args = parser.parse_args(argv)
    cases = [
        ("llvm", "no cache"),
        ("numba", "empty"), ("numba", "new system"), ("numba", "cached"),
        ("linked", "empty"), ("linked", "new system"),
    ]  # fmt: skip
    print(
        f"{'system':>16} {'way':>8} {'code cache':>11} {'compile s':>10} {'integrate s':>12} "
        f"{'total s':>8} {'steps':>7}"
    )
    for links in (2, args.links) if args.links else (2,):
        label = "double pendulum" if links == 2 else f"{links}-link chain"
        runs: dict[tuple[str, str], list] = {case: [] for case in cases}
        for _ in range(args.repeat):  # interleaved, so that each way sees the same load
            for way, state in cases:
                runs[way, state].append(in_process(links, way, state))
        for (way, state), results in runs.items():
            if any(r is None for r in results):
                print(f"{label:>16} {way:>8} {state:>11}  (not in this tree)")
                continue
            compile_s, run_s, steps = (statistics.median(r[i] for r in results) for i in range(3))
            print(
                f"{label:>16} {way:>8} {state:>11} {compile_s:>10.3f} {run_s:>12.3f} "
                f"{compile_s + run_s:>8.3f} {steps:>7.0f}",
                flush=True,
            )
    if args.skip_cli:
        return
    print(
        "\n`lagrangian simulate double_pendulum --t-end 1000 --method dop853`, CPU s of the process"
    )
    runs = [cli_runs("double_pendulum") for _ in range(args.repeat)]
    for key in runs[0]:
        print(f"{key:>22} {statistics.median(r[key] for r in runs):>8.2f}", flush=True)


if __name__ == "__main__":
    main()

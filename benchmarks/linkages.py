"""Issue 34, item 2: what a linkage costs through the command line.  The four-bar linkage
(free, and driven at constant speed) and the slider-crank: `lagrangian simulate EXAMPLE
--t-end 10 --json` as a process, in CPU seconds (user + sys of the process and its
children, the start-up included), with an empty code cache (a first run: derive, compile,
run) and with the cache it left (a second run), beside `lagrangian --version` (the
start-up every command pays), and the parts in this process: build (links -> bodies and
constraints, reactions), derive, the 10 s run.

    python benchmarks/linkages.py [--repeat 3] [--examples four_bar,four_bar_driven,slider_crank]
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


def process_cpu(argv: list[str], env: dict[str, str]) -> float:
    """CPU seconds (user + sys) of one run of ``argv`` as a child process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(argv, env=env, check=True, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def in_process(name: str) -> dict[str, float]:
    """CPU seconds of the stages of one example in this process (caches left as they are)."""
    import lagrangian as lg

    times = {}
    start = time.process_time()
    system = lg.load(name)
    times["build"] = time.process_time() - start
    start = time.process_time()
    system.equations_of_motion()
    times["derive"] = time.process_time() - start
    start = time.process_time()
    run = system.simulate(t_end=10.0)
    times["simulate 10 s"] = time.process_time() - start
    times["steps"] = float(run.dataset.attrs.get("steps", 0))
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--examples", default="four_bar,four_bar_driven,slider_crank")
    options = parser.parse_args()
    command = [sys.executable, "-m", "lagrangian", "simulate"]
    # the start-up every command pays, measured in the same run as the examples
    baseline = [process_cpu([sys.executable, "-m", "lagrangian", "--version"], dict(os.environ))
                for _ in range(options.repeat)]  # fmt: skip
    print(
        f"lagrangian --version as a process, CPU median of {options.repeat}: "
        f"{statistics.median(baseline):.2f} s (range {min(baseline):.2f}-{max(baseline):.2f})"
    )
    for name in options.examples.split(","):
        cold, warm = [], []
        for _ in range(options.repeat):
            with tempfile.TemporaryDirectory() as cache:
                env = os.environ | {"LAGRANGIAN_CACHE": cache}
                argv = [*command, name, "--t-end", "10", "--json"]
                cold.append(process_cpu(argv, env))
                warm.append(process_cpu(argv, env))
        print(
            f"{name}: simulate --t-end 10 as a process, CPU median of {options.repeat}: "
            f"{statistics.median(cold):.2f} s with an empty cache "
            f"(range {min(cold):.2f}-{max(cold):.2f}), {statistics.median(warm):.2f} s with "
            f"the cache it left (range {min(warm):.2f}-{max(warm):.2f})"
        )
        with tempfile.TemporaryDirectory() as cache:
            os.environ["LAGRANGIAN_CACHE"] = cache
            stages = in_process(name)
        print("  in process: " + ", ".join(f"{k} {v:.3g}" for k, v in stages.items()))


if __name__ == "__main__":
    main()

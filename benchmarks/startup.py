"""CPU seconds (user + sys) of short ``lagrangian`` commands as processes, for one or more
source trees in the same run: the fixed cost a ``simulate`` pays (issue 36 item 3).

    python benchmarks/startup.py [--repeat 5] [--tree before=/path/src] [--tree after=src]

Each command runs ``--repeat`` times per tree, the trees taking turns (a shared machine's
load falls on all of them alike), with ``PYTHONPATH`` set to the tree; printed are the
medians.  The code cache is the caller's (run each command once first, so that no tree
pays a compile the other does not).  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys

COMMANDS = {
    "--version": ["--version"],
    "simulate harmonic_oscillator --json": ["simulate", "harmonic_oscillator", "--json"],
    "simulate four_bar --t-end 10 --json": ["simulate", "four_bar", "--t-end", "10", "--json"],
    "derive double_pendulum": ["derive", "double_pendulum"],
}


def cpu_seconds(arguments: list[str], source: str) -> float:
    """The CPU seconds of one ``python -m lagrangian ARGUMENTS`` with ``source`` first."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    environment = {**os.environ, "PYTHONPATH": source}
    subprocess.run(
        [sys.executable, "-m", "lagrangian", *arguments],
        env=environment, check=True, stdout=subprocess.DEVNULL,
    )  # fmt: skip
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument(
        "--tree", action="append", default=[], help="NAME=SRC (default: this checkout's src)"
    )
    options = parser.parse_args()
    here = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src")
    trees = dict(t.split("=", 1) for t in options.tree) or {"this": here}
    print("| command | " + " | ".join(trees) + " |")
    print("|---|" + "---|" * len(trees))
    for label, arguments in COMMANDS.items():
        for source in trees.values():  # warm the code cache and the file cache
            cpu_seconds(arguments, source)
        times: dict[str, list[float]] = {name: [] for name in trees}
        for _ in range(options.repeat):
            for name, source in trees.items():
                times[name].append(cpu_seconds(arguments, source))
        medians = " | ".join(f"{statistics.median(times[n]):.2f} s" for n in trees)
        print(f"| `lagrangian {label}` | {medians} |", flush=True)


if __name__ == "__main__":
    main()

"""The same verdicts on a busy machine: the examples, README and tutorial commands run quiet
and beside busy processes, their outputs compared (issue 22).

    python benchmarks/load.py [--busy 4] [-k NAME]     verdicts quiet vs busy, CPU and wall
    python benchmarks/load.py --stages [-k NAME]       CPU seconds of each budgeted stage

Every budget is CPU time of the process (:mod:`lagrangian.budget`), so a command's
verdict must not change when ``--busy`` processes spinning on the CPU beside it
make it wait: each command runs as a ``lagrangian`` process once on a quiet machine
and once with the busy ones, and the outputs are compared (wall and CPU times
and file names taken out).  ``--stages`` runs ``derive`` and ``analyze`` of each
example in a fresh process and prints the CPU seconds of each budgeted stage
against its budget, which is how the defaults are sized (each well within).
Exits 1 when an output differs or a stage used over a third of its budget.
Not a test: wall clock never enters the suite (tests/test_load.py runs a
cheap version without timing).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import multiprocessing
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: Commands of the README and the tutorial whose verdicts a budget could change.
DOCUMENTED = [
    "analyze spherical_pendulum --momentum p_phi=1",
    "analyze cart_pole --state-space --at theta=0",
    "analyze cart_pole --state-space --at theta=pi --output tip=x+l*sin(theta) --json",
    "simulate cart_pole --set F=0.5 --json",
    "simulate heavy_top --json",
    "simulate rotating_wire_bead --set omega=2 --set r_dot=0.1 --json",
    "derive double_pendulum --steps",
]

#: Output that legitimately differs between runs: times and temporary names.
VOLATILE = re.compile(r'("wall_time": )[0-9.e+-]+|(done in )[0-9.]+ s|/tmp/[^\s"]+')


def examples() -> list[str]:
    from lagrangian.examples import example_names

    return list(example_names())


def commands(pattern: str) -> list[str]:
    every = [f"analyze {name} --json" for name in examples()]
    every += [f"derive {name} --json" for name in examples()]
    return [c for c in every + DOCUMENTED if _chosen(c, pattern)]


def _chosen(text: str, pattern: str) -> bool:
    """Whether ``text`` holds one of the comma-separated parts of ``pattern`` (all: "")."""
    return any(part in text for part in pattern.split(","))


def run(command: str) -> tuple[str, float, float]:
    """(normalized output, CPU seconds, wall seconds) of ``lagrangian COMMAND``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "lagrangian", *command.split()],
        capture_output=True, text=True, stdin=subprocess.DEVNULL, cwd=tempfile.gettempdir(),
    )  # fmt: skip
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    output = f"exit {done.returncode}\n{done.stdout}\n{done.stderr}"
    return VOLATILE.sub(lambda m: (m.group(1) or m.group(2) or "") + "*", output), cpu, wall


def _spin() -> None:
    while True:
        pass


@contextlib.contextmanager
def busy(count: int):
    """``count`` processes spinning on the CPU while inside."""
    spinners = [multiprocessing.Process(target=_spin, daemon=True) for _ in range(count)]
    for spinner in spinners:
        spinner.start()
    try:
        yield
    finally:
        for spinner in spinners:
            spinner.kill()
            spinner.join()


def verdicts(args) -> int:
    rows, differing = [], []
    for command in commands(args.pattern):
        quiet, cpu, wall = run(command)
        with busy(args.busy):
            loaded, cpu_busy, wall_busy = run(command)
        same = quiet == loaded
        rows.append((command, cpu, wall, cpu_busy, wall_busy, same))
        print(
            f"{command[:70]:70s} cpu {cpu:6.2f} / {cpu_busy:6.2f} s  wall {wall:6.2f} / "
            f"{wall_busy:6.2f} s  {'same' if same else 'DIFFERENT'}",
            flush=True,
        )
        if not same:
            differing.append((command, quiet, loaded))
    for command, quiet, loaded in differing:
        print(f"\n--- {command} quiet:\n{quiet}\n--- busy:\n{loaded}")
    slow = max(rows, key=lambda row: row[4])
    print(
        f"\n{len(rows)} commands, {len(differing)} with different output; "
        f"slowest beside {args.busy} busy processes: {slow[0]} ({slow[4]:.1f} s wall, "
        f"{slow[3]:.1f} s CPU)"
    )
    return 1 if differing else 0


_STAGE_PROBE = """
import json, sys
import lagrangian as lg
from lagrangian import budget
from lagrangian.analysis import report

used = {}
attempt = report.attempt

def timed(stage, seconds, work):
    start = budget.cpu_seconds()
    try:
        return attempt(stage, seconds, work)
    finally:
        used[stage] = used.get(stage, 0.0) + budget.cpu_seconds() - start

report.attempt = timed
system = lg.load(sys.argv[1])
start = budget.cpu_seconds()
eom = system.without_inputs().equations_of_motion()
used["derive"] = budget.cpu_seconds() - start
analysis = report.analyze(eom)
print(json.dumps({"used": used, "undecided": [str(u) for u in analysis.undecided]}))
"""


def stages(args) -> int:
    from lagrangian.budget import STAGE_SECONDS

    worst = 0.0
    for name in examples():
        if not _chosen(name, args.pattern):
            continue
        done = subprocess.run(
            [sys.executable, "-c", _STAGE_PROBE, name], capture_output=True, text=True
        )
        if done.returncode != 0:
            print(f"{name}: failed\n{done.stderr}")
            return 1
        result = json.loads(done.stdout.splitlines()[-1])
        used = result["used"]
        shown = "  ".join(f"{stage} {seconds:.2f}" for stage, seconds in used.items())
        print(f"{name:30s} {shown}  {'; '.join(result['undecided'])}", flush=True)
        worst = max([worst] + [s for stage, s in used.items() if stage != "derive"])
    print(f"\nlongest analyze stage: {worst:.2f} s of CPU (budget {STAGE_SECONDS:g} s each)")
    return 1 if worst > STAGE_SECONDS / 3 else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--busy", type=int, default=4, help="busy processes beside the runs")
    parser.add_argument("--stages", action="store_true", help="CPU seconds of each stage")
    parser.add_argument(
        "-k", dest="pattern", default="", help="only commands holding one of these (a,b,...)"
    )
    args = parser.parse_args()
    if shutil.which("lagrangian") is None and not os.environ.get("PYTHONPATH"):
        print("install the package (pip install .) or set PYTHONPATH=src")
        return 1
    return stages(args) if args.stages else verdicts(args)


if __name__ == "__main__":
    sys.exit(main())

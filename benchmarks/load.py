"""The same verdicts on a busy machine: the examples, README and tutorial commands run quiet
and beside busy processes, their outputs compared (issue 22).

    python benchmarks/load.py [--busy 4] [-k NAME]     verdicts quiet vs busy, CPU and wall
    python benchmarks/load.py --stages [-k NAME]       CPU seconds of each budgeted stage

Every budget is CPU time of the process (:mod:`lagrangian.budget`), so a command's
verdict must not change when ``--busy`` processes spinning on the CPU beside it
make it wait: each command runs as a ``lagrangian`` process once on a quiet machine
and once with the busy ones, and the outputs are compared (wall and CPU times
and file names taken out).  ``--stages`` runs ``derive`` and ``analyze`` of each
example and README model in a fresh process and prints the CPU seconds of each
budgeted stage (the longest call of it) against its budget, which is how the
defaults are sized (each well within).  Exits 1 when an output differs, or a
stage used over a third of its budget or was cut.
Not a test: wall clock never enters the suite (tests/test_load.py runs a
cheap version without timing).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import multiprocessing
import os
import re
import resource
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: Output that legitimately differs between runs: durations, rates and temporary names.
VOLATILE = re.compile(
    r'("wall_time": )[0-9.e+-]+|\b[0-9][0-9.,]*(e[+-]?[0-9]+)? (s\b|trajectory-steps/s)'
    r'|/tmp/[^\s"]+'
)


@dataclasses.dataclass(frozen=True)
class Command:
    """One ``lagrangian`` command line, and the folder group it runs in (files it reads)."""

    text: str
    group: str

    @property
    def argv(self) -> list[str]:
        return shlex.split(self.text, comments=True)

    @property
    def line(self) -> str:
        """The command as typed, without its comment."""
        return shlex.join(self.argv)


def examples() -> list[str]:
    from lagrangian.examples import example_names

    return list(example_names())


def _docs():
    """tests/test_docs.py, which reads the README's and the tutorial's command lines."""
    sys.path.insert(0, str(ROOT / "tests"))
    import test_docs

    return test_docs


def documented() -> list[Command]:
    """The README's and the tutorial's commands, as tests/test_docs.py runs them (the same
    lines left out and the same heavy ones made smaller), grouped by code block."""
    docs = _docs()
    found = []
    for kind, body, where in docs.BLOCKS:
        if kind not in ("sh", "console") or "architecture" in where:
            continue
        for line in docs._commands(body):
            if any(key in line for key in docs.SKIPPED) or docs.SYNOPSIS.search(line):
                continue
            if line.startswith("lagrangian "):
                found.append(Command(docs._smaller(line).removeprefix("lagrangian "), where))
    return found


def commands(pattern: str) -> list[Command]:
    """Every example through derive, analyze and simulate, then the documented commands;
    each line once."""
    every = [Command(f"{verb} {name}", "examples") for name in examples()
             for verb in ("derive", "analyze", "simulate")]  # fmt: skip
    seen, chosen = set(), []
    for command in every + documented():
        key = " ".join(command.argv)
        if key not in seen and _chosen(command.text, pattern):
            seen.add(key)
            chosen.append(command)
    return chosen


def _chosen(text: str, pattern: str) -> bool:
    """Whether ``text`` holds one of the comma-separated parts of ``pattern`` (all: "")."""
    return any(part in text for part in pattern.split(","))


def _folder(root: Path, group: str) -> Path:
    """The folder of a group of commands, where the README's model file is my_model.toml."""
    folder = root / re.sub(r"\W", "_", group)
    if not folder.exists():
        folder.mkdir()
        _docs()._readme_model(folder)
    return folder


def _lagrangian(argv: list[str], folder: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "lagrangian", *argv],
        capture_output=True, text=True, stdin=subprocess.DEVNULL, cwd=folder,
        env=os.environ | {"MPLBACKEND": "Agg"},
    )  # fmt: skip


def run(command: Command, root: Path) -> tuple[str, float, float]:
    """(normalized output, CPU seconds, wall seconds) of ``lagrangian COMMAND``."""
    folder = _folder(root, command.group)
    if "run.csv" in command.argv and not (folder / "run.csv").exists():
        # the tutorial's synopsis plots "a trajectory saved by simulate --out"
        _lagrangian(["simulate", "simple_pendulum", "--out", "run.csv"], folder)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = _lagrangian(command.argv, folder)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    output = f"exit {done.returncode}\n{done.stdout}\n{done.stderr}"
    return VOLATILE.sub(_masked, output).replace(str(folder), "<folder>"), cpu, wall


def _masked(match: re.Match) -> str:
    if match.group(1):
        return match.group(1) + "*"
    if match.group(3):
        return "* " + match.group(3)
    return "<tmp>"


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
    chosen = commands(args.pattern)
    if args.list:
        print("\n".join(f"{c.group:16s} lagrangian {c.line}" for c in chosen))
        return 0
    rows, differing = [], []
    with tempfile.TemporaryDirectory() as root:
        quiet_root, busy_root = Path(root, "quiet"), Path(root, "busy")
        quiet_root.mkdir(), busy_root.mkdir()
        for command in chosen:
            quiet, cpu, wall = run(command, quiet_root)
            with busy(args.busy):
                loaded, cpu_busy, wall_busy = run(command, busy_root)
            verdict = "same"
            if quiet != loaded:
                # the first run may have filled the code cache (a compiled loop then says
                # it loads instead of compiling): a second quiet run tells which
                again, _, _ = run(command, quiet_root)
                verdict = "same (2nd quiet run)" if again == loaded else "DIFFERENT"
            rows.append((command.line, cpu, wall, cpu_busy, wall_busy, verdict))
            print(
                f"| `{command.line}` | {cpu:.2f} / {cpu_busy:.2f} | {wall:.1f} / "
                f"{wall_busy:.1f} | {verdict} |",
                flush=True,
            )
            if verdict == "DIFFERENT":
                differing.append((command.line, quiet, loaded))
    for command, quiet, loaded in differing:
        print(f"\n--- {command} quiet:\n{quiet}\n--- busy:\n{loaded}")
    slow = max(rows, key=lambda row: row[4])
    print(
        f"\n{len(rows)} commands, {len(differing)} with different output; "
        f"CPU {sum(r[1] for r in rows):.0f} s quiet, {sum(r[3] for r in rows):.0f} s busy; "
        f"wall {sum(r[2] for r in rows):.0f} s quiet, {sum(r[4] for r in rows):.0f} s busy; "
        f"slowest beside {args.busy} busy processes: {slow[0]} ({slow[4]:.1f} s wall, "
        f"{slow[3]:.1f} s CPU); load average at the end {os.getloadavg()}"
    )
    return 1 if differing else 0


_STAGE_PROBE = """
import json, sys
import lagrangian as lg
from lagrangian import budget
from lagrangian.analysis import report

# every budgeted piece of work goes through budget.attempt (within calls it too): time
# each, in this module and in every module that imported it by name
original, used = budget.attempt, []

def timed(stage, seconds, work):
    start = budget.cpu_seconds()
    result, undecided = original(stage, seconds, work)
    used.append((stage, seconds, budget.cpu_seconds() - start, undecided is None))
    return result, undecided

budget.attempt = timed
import lagrangian.derive.euler_lagrange, lagrangian.analysis.conserved, lagrangian.model.build
for module in list(sys.modules.values()):
    if getattr(module, "__name__", "").startswith("lagrangian") and (
        getattr(module, "attempt", None) is original
    ):
        module.attempt = timed
target = sys.argv[1]
if target.startswith("lagrangian="):
    system = lg.System.from_lagrangian(target.split("=", 1)[1], coordinates=sys.argv[2:])
else:
    system = lg.load(target)
system.equations_of_motion()
analysis = report.analyze(system.without_inputs().equations_of_motion())
print(json.dumps({"used": used, "undecided": [str(u) for u in analysis.undecided]}))
"""
#: Models of the README besides the examples: its model file and its --lagrangian line.
README_MODELS = (
    ["my_model.toml"],
    ["lagrangian=m*l**2*theta_dot**2/2 + m*g*l*cos(theta)", "theta"],
)


def stages(args) -> int:
    """CPU seconds of every budgeted stage (derive's and analyze's) of every example and
    README model, each in a fresh process, against its budget; exit 1 when one took more
    than a third of its budget or was cut."""
    targets = [[name] for name in examples()] + list(README_MODELS)
    worst, cut = 0.0, []
    with tempfile.TemporaryDirectory() as folder:
        _docs()._readme_model(Path(folder))
        for target in targets:
            if not _chosen(target[0], args.pattern):
                continue
            done = subprocess.run(
                [sys.executable, "-c", _STAGE_PROBE, *target], capture_output=True, text=True,
                cwd=folder,
            )  # fmt: skip
            if done.returncode != 0:
                print(f"{target[0]}: failed\n{done.stderr}")
                return 1
            result = json.loads(done.stdout.splitlines()[-1])
            longest: dict[str, tuple[float, float]] = {}
            for stage, seconds, spent, decided in result["used"]:
                if not decided:
                    cut.append(f"{target[0]}: {stage}")
                shown = longest.get(stage, (0.0, seconds))[0]
                longest[stage] = (max(shown, spent), seconds)
                worst = max(worst, spent / seconds if seconds else 0.0)
            row = "  ".join(f"{stage} {s:.2f}/{b:g}" for stage, (s, b) in longest.items())
            print(f"{target[0][:30]:30s} {row}", flush=True)
    print(f"\nlongest stage against its budget: {100 * worst:.0f} %; cut: {cut or 'none'}")
    return 1 if worst > 1 / 3 or cut else 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--busy", type=int, default=4, help="busy processes beside the runs")
    parser.add_argument("--stages", action="store_true", help="CPU seconds of each stage")
    parser.add_argument("--list", action="store_true", help="only list the commands")
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

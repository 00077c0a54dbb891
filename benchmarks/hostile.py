"""Wall time of every hostile CLI case (tests/hostile) as a real ``lagrangian`` process.

    python benchmarks/hostile.py [--repeat 1] [--limit 5]

Runs each case of ``tests/hostile/cases_*.py`` as ``lagrangian ARGV`` in a
fresh folder, checks its outcome as the test suite does, and prints the
slowest cases, the median and the worst wall time (start-up included, which
is what a user waits for).  Exits 1 when a case fails its check or takes
longer than ``--limit`` seconds.  Not a test: the suite runs the same cases
in-process without timing them.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from hostile.case import all_cases


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1, help="runs per case (the median counts)")
    parser.add_argument("--limit", type=float, default=5.0, help="seconds allowed per case")
    parser.add_argument("-k", dest="pattern", default="", help="only cases whose name holds this")
    args = parser.parse_args()
    command = shutil.which("lagrangian")
    command = command and str(Path(command).resolve())
    if command is None:
        print("no 'lagrangian' on the path: pip install . first")
        return 1
    # each case runs in its own folder: a relative PYTHONPATH (src) would name nothing there
    environment = dict(os.environ)
    if environment.get("PYTHONPATH"):
        paths = environment["PYTHONPATH"].split(os.pathsep)
        environment["PYTHONPATH"] = os.pathsep.join(str(Path(p).resolve()) for p in paths if p)
    times: dict[str, float] = {}
    failed = []
    for case in all_cases():
        if args.pattern not in case.name:
            continue
        runs = []
        for _ in range(args.repeat):
            with tempfile.TemporaryDirectory() as folder:
                argv = case.prepare(Path(folder))
                start = time.perf_counter()
                try:
                    done = subprocess.run(
                        [command, *argv], capture_output=True, text=True, stdin=subprocess.DEVNULL,
                        timeout=max(60.0, 4 * args.limit), cwd=folder,
                        env={**environment, **case.environment(Path(folder))},
                    )  # fmt: skip
                except subprocess.TimeoutExpired:
                    runs.append(float("inf"))
                    failed.append(f"{case.name}: hung")
                    break
                runs.append(time.perf_counter() - start)
                try:
                    case.check(done.returncode, done.stdout, done.stderr)
                except AssertionError as error:
                    failed.append(str(error).splitlines()[0])
        times[case.name] = statistics.median(runs)
    ranked = sorted(times.items(), key=lambda item: -item[1])
    print(f"{len(times)} hostile cases as processes ({args.repeat} run(s) each, median)")
    for name, seconds in ranked[:10]:
        print(f"  {seconds:7.2f} s  {name}")
    if times:
        values = list(times.values())
        print(f"median {statistics.median(values):.2f} s, worst {max(values):.2f} s "
              f"({ranked[0][0]}), limit {args.limit:.1f} s")  # fmt: skip
    over = [name for name, seconds in ranked if seconds > args.limit]
    for line in failed:
        print(f"FAILED {line}")
    for name in over:
        print(f"OVER LIMIT {name}: {times[name]:.2f} s")
    return 1 if failed or over else 0


if __name__ == "__main__":
    sys.exit(main())

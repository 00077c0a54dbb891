"""The test suite's two tiers, timed: is each test on the right side of the line?

    python benchmarks/suite_tiers.py [--tier quick|slow|all] [--line 1.5] [--workers auto]

Runs the suite as the README does (``pytest``: the quick tier; ``--tier slow``:
``pytest -m slow``; ``--tier all``: ``pytest --slow``) from this checkout, with an
empty code cache (the first run on a machine, as CI's), and times every test (its wall
and CPU seconds, in the pytest worker that ran it).  Prints the tier's wall and CPU time,
the slowest tests, and the tests on the wrong side of the line: unmarked tests that
took more than ``--line`` seconds (candidates for ``@pytest.mark.slow``) and slow-tier
tests that took less than a third of it (candidates to come back).  A test's seconds
include what it was first in its worker to pay for (an import, a numba compile of the
shared loops), so judge a candidate by its own work, not by this number alone.  Not a
test: the suite asserts no timings.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: The pytest plugin that records (node id, wall, CPU, slow?) of every test, one file per worker.
PLUGIN = """
import json, os, resource, time
import pytest

_rows = []

@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    wall, own = time.perf_counter(), time.process_time()
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    yield
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    spent = after.ru_utime + after.ru_stime - children.ru_utime - children.ru_stime
    slow = item.get_closest_marker("slow") is not None
    _rows.append((item.nodeid, time.perf_counter() - wall, time.process_time() - own + spent, slow))

def pytest_unconfigure(config):
    name = os.environ.get("PYTEST_XDIST_WORKER", "main")
    with open(os.path.join(os.environ["TIERS_OUT"], name + ".json"), "w") as f:
        json.dump(_rows, f)
"""

TIERS = {"quick": [], "slow": ["-m", "slow"], "all": ["--slow"]}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tier", choices=sorted(TIERS), default="quick")
    parser.add_argument("--line", type=float, default=1.5, help="seconds that make a test slow")
    parser.add_argument("--workers", default="auto", help="pytest-xdist's -n")
    parser.add_argument("--top", type=int, default=15, help="how many of the slowest to list")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        out, plugin = Path(scratch, "rows"), Path(scratch, "tiers_plugin.py")
        out.mkdir()
        plugin.write_text(PLUGIN)
        environment = os.environ | {
            "TIERS_OUT": str(out),
            "LAGRANGIAN_CACHE": str(Path(scratch, "cache")),
            "PYTHONPATH": os.pathsep.join([scratch, os.environ.get("PYTHONPATH", "")]),
        }
        command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider"]
        command += ["-p", "tiers_plugin", "-n", args.workers, *TIERS[args.tier]]
        before, started = resource.getrusage(resource.RUSAGE_CHILDREN), time.perf_counter()
        done = subprocess.run(command, cwd=ROOT, env=environment, capture_output=True, text=True)
        wall = time.perf_counter() - started
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        rows = [row for part in sorted(out.glob("*.json")) for row in json.loads(part.read_text())]
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    print(done.stdout.strip().splitlines()[-1] if done.stdout.strip() else done.stderr[-2000:])
    print(f"tier {args.tier}: {wall:.0f} s wall, {cpu:.0f} s CPU (pytest and its children),")
    print(f"  {len(rows)} tests, {sum(r[1] for r in rows):.0f} s of test wall in the workers")
    print(f"\nthe {args.top} slowest (wall, CPU, tier):")
    for nodeid, seconds, used, slow in sorted(rows, key=lambda r: -r[1])[: args.top]:
        print(f"  {seconds:6.2f} {used:6.2f} {'slow ' if slow else 'quick'} {nodeid}")
    over = [r for r in rows if not r[3] and r[1] > args.line]
    under = [r for r in rows if r[3] and r[1] < args.line / 3]
    print(f"\nunmarked, over {args.line:g} s ({len(over)}):")
    for nodeid, seconds, _, _ in sorted(over, key=lambda r: -r[1]):
        print(f"  {seconds:6.2f} {nodeid}")
    print(f"\nmarked slow, under {args.line / 3:g} s ({len(under)}):")
    for nodeid, seconds, _, _ in sorted(under, key=lambda r: r[1]):
        print(f"  {seconds:6.2f} {nodeid}")
    return done.returncode


if __name__ == "__main__":
    sys.exit(main())

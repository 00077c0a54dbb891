"""CPU seconds of ``lagrangian derive FILE`` as a process, against KanesMethod in the same run.

    python benchmarks/cli.py [--repeat 3] [--sizes 5,20,100] [--kane-max 20]

For each n-link pendulum (point masses on massless links, angles from the downward
vertical, written as a model file with particle positions, as benchmarks/derive.py
builds it) the real command runs as a child process: ``derive FILE --json``,
``derive FILE`` (text) and ``derive FILE --latex``.  Process start-up
(``lagrangian --version``: the interpreter, click and the package import) is
measured just before each run of a command and subtracted from it (the machine
may be shared: paired runs see the same load); printed are medians over
``--repeat`` pairs of the command's seconds, of the start-up and of the
difference, the bytes written, and for n up to ``--kane-max`` the seconds of
sympy.physics.mechanics' ``KanesMethod`` for the same chain (one run, in this
process) with the ratio Kane / ours (ours above start-up), and the spread of the
differences (their lower and upper quartiles).  A command that runs past
``--timeout`` seconds is stopped and shown as such.  Nothing is asserted.

The children read the package's bytecode from a cache this script fills (one
unmeasured run of each command first), as an installed package has it: where
``PYTHONDONTWRITEBYTECODE`` is set (this machine sets it) every process would
otherwise compile each module it imports anew, and a command importing more
modules than ``--version`` would be charged their compilation.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from derive import kanes_method

FORMATS = {"json": ["--json"], "text": [], "latex": ["--latex"]}


def chain_model(n: int) -> str:
    """The TOML text of the n-link pendulum built from particles."""
    coordinates = ", ".join(f'"theta{i}"' for i in range(1, n + 1))
    lines = [f'name = "{n}-link pendulum"', f"coordinates = [{coordinates}]", "", "[parameters]"]
    lines += [f"m{i} = 1.0" for i in range(1, n + 1)]
    lines += [f"l{i} = 1.0" for i in range(1, n + 1)]
    lines += ["g = 9.81", ""]
    x, y = "0", "0"
    for i in range(1, n + 1):
        x += f" + l{i}*sin(theta{i})"
        y += f" - l{i}*cos(theta{i})"
        lines += ["[[particles]]", f'name = "bob{i}"', f'mass = "m{i}"']
        lines += [f'position = ["{x}", "{y}"]', ""]
    lines += ["[gravity]", 'g = "g"', "direction = [0, -1]", "", "[initial]", "theta1 = 0.5", ""]
    return "\n".join(lines)


def command() -> list[str]:
    return [sys.executable, "-m", "lagrangian"]


def child_environment(bytecode: Path) -> dict[str, str]:
    """The environment of the measured processes: bytecode kept in ``bytecode``."""
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    environment["PYTHONPYCACHEPREFIX"] = str(bytecode)
    return environment


def timed(arguments: list[str], timeout: float, environment: dict[str, str]) -> tuple[float, int]:
    """CPU seconds (user + system) of one child process and the bytes it printed (inf where
    it timed out)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        done = subprocess.run(
            [*command(), *arguments],
            capture_output=True,
            timeout=timeout,
            check=True,
            env=environment,
        )
    except subprocess.TimeoutExpired:
        return float("inf"), 0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), len(done.stdout)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sizes", default="5,20,100")
    parser.add_argument("--kane-max", type=int, default=20, help="run KanesMethod up to this n")
    parser.add_argument("--timeout", type=float, default=300.0)
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    print(
        f"{'n':>4} {'format':>6} {'process s':>10} {'start-up s':>11} {'above start-up s':>17} "
        f"{'quartiles':>15} {'bytes':>10} {'Kane s':>8} {'Kane / ours':>12}"
    )
    with tempfile.TemporaryDirectory() as folder:
        environment = child_environment(Path(folder) / "bytecode")
        timed(["--version"], 60, environment)
        for n in sizes:
            path = Path(folder) / f"chain{n}.toml"
            path.write_text(chain_model(n))
            kane = kanes_method(n) if n <= args.kane_max else float("nan")
            for name, flags in FORMATS.items():
                timed(["derive", str(path), *flags], args.timeout, environment)
                pairs = []
                for _ in range(args.repeat):
                    startup = timed(["--version"], 60, environment)[0]
                    seconds, size = timed(["derive", str(path), *flags], args.timeout, environment)
                    pairs.append((seconds, startup, size))
                total = statistics.median(p[0] for p in pairs)
                startup = statistics.median(p[1] for p in pairs)
                differences = [p[0] - p[1] for p in pairs]
                above = statistics.median(differences)
                low, high = _quartiles(differences)
                ratio = kane / above if above > 0 else float("nan")
                print(
                    f"{n:>4} {name:>6} {total:>10.3f} {startup:>11.3f} {above:>17.3f} "
                    f"{f'{low:.3f}-{high:.3f}':>15} {pairs[0][2]:>10} {kane:>8.2f} {ratio:>12.1f}",
                    flush=True,
                )
    print("above start-up: median of (command - the start-up run just before it); Kane: one run")


def _quartiles(values: list[float]) -> tuple[float, float]:
    if len(values) < 2:
        return values[0], values[0]
    quartiles = statistics.quantiles(values, n=4)
    return quartiles[0], quartiles[2]


if __name__ == "__main__":
    main()

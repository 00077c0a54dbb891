"""Every ratio of issue 12 in one run: where users feel the speed.

    python benchmarks/user_paths.py [--repeat 3] [--quick]

Runs, one after the other in this process (each part starts its own child
processes where it measures a fresh start):

1. ``cli.py``: ``lagrangian derive FILE --json`` / text / ``--latex`` of the 5-, 20-
   and 100-link chains above process start-up, against KanesMethod (targets: n = 20
   JSON under 0.3 s and at least 50x KanesMethod, n = 100 under 10 s);
2. ``variational.py``: µs per variational step against rk4 at dt = 0.001 on the
   numpy and numba backends (target: within 3x);
3. ``first_run.py``: a first run (compile + integrate) per backend (the default
   should be the fastest);
4. ``taylor_peer.py``: heyoka against our DOP853 and Radau at 1e-10 and 1e-15;
5. ``adaptive.py`` (issue 19): the default single run against heyoka (double
   pendulum t = 1000 at 1e-10, target within 3x at equal or smaller error; 10-link
   chain t = 1000 at 1e-15, within 2x) and the first run of the double pendulum
   against the path before (target: no slower than 0.82 s).

``--quick`` runs smaller sizes (chains of 5 and 20 links, 2,000 steps), skips
the heyoka part (its t = 1000 runs take minutes) and runs ``adaptive.py --quick``.
Nothing is asserted.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import adaptive
import first_run
import taylor_peer
import variational

import cli


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="smaller sizes; no heyoka part")
    args = parser.parse_args(argv)
    repeat = str(args.repeat)
    print("== 1. derive as a process against KanesMethod (benchmarks/cli.py)")
    cli.main(["--repeat", repeat, "--sizes", "5,20" if args.quick else "5,20,100"])
    print("\n== 2. variational step against rk4 (benchmarks/variational.py)")
    variational.main(["--repeat", repeat, "--steps", "2000" if args.quick else "20000"])
    print("\n== 3. first run per backend (benchmarks/first_run.py)")
    first_run.main(["--repeat", repeat])
    if not args.quick:
        print("\n== 4. heyoka at tight tolerances (benchmarks/taylor_peer.py)")
        taylor_peer.main(args.repeat)
    print(
        "\n== 5. the default single run against heyoka and the first run (benchmarks/adaptive.py)"
    )
    adaptive.main(["--repeat", repeat, *(["--quick"] if args.quick else [])])


if __name__ == "__main__":
    main()

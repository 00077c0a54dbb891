"""Issue 36, item 2 where heyoka is not installed: our Taylor method (backend "numba")
against heyoka itself and the compiled DOP853, in CPU time.

    python benchmarks/taylor_numba.py [--repeat 7] [--quick]

In one process, for the double pendulum from (0.3, 0.2) at rest to t = 1000 and the
10-link chain from theta1 = 0.1 to t = 1000 (``--quick`` leaves the chain out), at tol
1e-10 and at the tolerances around it, the CPU seconds (``time.process_time``, median of
``--repeat`` rounds, each round running every row once) of heyoka itself (given the
equations by hand with the parameter values written in, its integrator built before
timing, ``propagate_until``), heyoka on our equations (``Taylor(tol, backend="heyoka")``,
the parameters at run time, as ``method="taylor"`` runs it), ours (``Taylor(tol,
backend="numba").solve``; both to the final state, output time t_end, built before
timing) and the compiled DOP853 down to heyoka's error.  Each row: CPU
seconds, the error of the final state against heyoka in long double at tol 1e-18, the
ratio to heyoka's ``propagate_until`` at 1e-10.

Then the start-up of a new system, each in a fresh process with an empty code cache:
``Taylor(backend="numba").prepare`` (tape, generated module, numba's compile) and the same
in a second process that finds the machine code in the cache.  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rhs import chain_pendulum
from taylor_path import interleaved
from taylor_peer import heyoka_integrator, reference_case

import lagrangian as lg
from lagrangian.integrate.registry import method_class
from lagrangian.integrate.scipy_methods import MIN_RTOL
from lagrangian.integrate.taylor import Taylor
from lagrangian.numeric import compile_equations

_START = """
import sys, time
sys.path.insert(0, {benchmarks!r})
start = time.process_time()
import numpy as np
import lagrangian as lg
from rhs import chain_pendulum
from lagrangian.integrate.taylor import Taylor
from lagrangian.numeric import compile_equations
system = lg.load("double_pendulum") if {links} == 2 else chain_pendulum({links})
compiled = compile_equations(system.equations_of_motion(), backend="llvm")
made = time.process_time()
y0 = np.zeros(2 * compiled.n)
what = Taylor(tol=1e-10, backend="numba").prepare(compiled, y0, compiled.parameter_vector())
print(f"{{made - start:.2f}} {{time.process_time() - made:.2f}} {{what}}")
"""


def _error(final, reference):
    return float(np.max(np.abs(final - reference)))


def case(label, system, angles, t_end, tols, repeat):
    eom, y0, ode, reference = reference_case(system, angles, t_end)
    compiled = compile_equations(eom, backend="llvm")
    params = compiled.parameter_vector()
    works = []
    for tol in tols:
        integrator, _ = heyoka_integrator(ode, y0, tol)

        def until(integrator=integrator):
            integrator.time = 0.0
            integrator.state[:] = y0
            integrator.propagate_until(t_end)
            return np.array(integrator.state)

        theirs = Taylor(tol=tol, backend="heyoka")  # heyoka on our equations (parameters
        theirs.solve(compiled, (0.0, 1.0), y0, params)  # at run time), as method taylor runs

        def heyoka_solve(theirs=theirs):
            return theirs.solve(compiled, (0.0, t_end), y0, params, t_eval=[t_end]).y[:, -1]

        ours = Taylor(tol=tol, backend="numba")
        ours.solve(compiled, (0.0, 1.0), y0, params)  # the loop built, untimed

        def solve(ours=ours):
            return ours.solve(compiled, (0.0, t_end), y0, params, t_eval=[t_end]).y[:, -1]

        works += [(f"heyoka propagate_until, tol {tol:g}", until)]
        works += [(f"heyoka on ours (solve), tol {tol:g}", heyoka_solve)]
        works += [(f"ours (numba, solve), tol {tol:g}", solve)]
    numba = compile_equations(eom, backend="numba")
    for tight in (1e-12, 1e-13):
        dop853 = method_class("dop853").configure(
            t_span=(0.0, t_end), rtol=max(tight, MIN_RTOL), atol=tight
        )
        dop853.solve(numba, (0.0, 1.0), y0, params)

        def run(dop853=dop853):
            return dop853.solve(numba, (0.0, t_end), y0, params).y[:, -1]

        works.append((f"dop853 compiled, tol {tight:g}", run))
    rows = interleaved(works, repeat)
    base = next(s for name, s, _ in rows if name == "heyoka propagate_until, tol 1e-10")
    print(f"\n{label}, t = {t_end:g}")
    print(f"{'run':>40} {'CPU s':>9} {'error':>9} {'/ heyoka 1e-10':>15}")
    for name, seconds, final in rows:
        error = _error(final, reference)
        print(f"{name:>40} {seconds:>9.4f} {error:>9.1e} {seconds / base:>15.2f}")


def start_up(links: int) -> None:
    """A new system's prepare, in a fresh process with an empty cache, then again."""
    benchmarks = str(Path(__file__).resolve().parent)
    code = _START.format(benchmarks=benchmarks, links=links)
    with tempfile.TemporaryDirectory() as cache:
        environment = {**os.environ, "LAGRANGIAN_CACHE": cache}
        for label in ("new system, empty cache", "second process, cached"):
            out = subprocess.run(
                [sys.executable, "-c", code], env=environment, capture_output=True, text=True,
                check=True,
            ).stdout.split(maxsplit=2)  # fmt: skip
            print(f"{links}-coordinate system, {label}: import and compile_equations "
                  f"{out[0]} s, prepare {out[1]} s ({out[2].strip()})")  # fmt: skip


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--quick", action="store_true", help="the double pendulum only")
    args = parser.parse_args(argv)
    import heyoka

    print(f"heyoka {heyoka.__version__}; CPU seconds (process_time), medians of {args.repeat}")
    pendulum = lg.load("double_pendulum")
    case("double pendulum", pendulum, [0.3, 0.2], 1000.0, (1e-10, 3e-11, 1e-12), args.repeat)
    start_up(2)
    if not args.quick:  # ours in the compact mode: 10 s a run
        case("10-link chain", chain_pendulum(10), [0.1], 1000.0, (1e-10,), min(args.repeat, 3))
        start_up(10)


if __name__ == "__main__":
    main()

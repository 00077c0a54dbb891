"""Issue 19's adaptive targets in one run: the default single run against heyoka and against
today's first run.

    python benchmarks/adaptive.py [--repeat 3] [--quick]

1. Double pendulum from (0.3, 0.2) to t = 1000 at tol 1e-10 (rtol = atol = tol): the
   integration's CPU seconds (after compilation, median of ``--repeat``) and the error of
   the final state of our default run (what :func:`lagrangian.integrate.choice.choose_run`
   picks, run as ``simulate`` runs it, by ``RunChoice.integrator``, its path named), of
   DOP853 with its loop compiled at 1e-10 and at the tolerance where its error is no
   larger than heyoka's, and of heyoka at 1e-10; SciPy's loop (the default before) once.
   Target: within 3x of heyoka at equal or smaller error.
2. 10-link chain from theta1 = 0.1 to t = 1000 at 1e-15 (SciPy's and so the compiled
   loop's rtol floor is 2.2e-14, atol 1e-15): the compiled DOP853 and heyoka.
   Target: within 2x of heyoka.
3. The first run of the double pendulum (its model's 20 s from (2.0, 0.5), default
   tolerances) in a fresh process, from the derived equations to the trajectory: the
   default (choice, compile, integrate; CPU seconds of the process) with an empty code
   cache and with a filled one, the path it took named, against the path before
   (compile on llvm, SciPy's DOP853) in the same process.  Target: no slower than
   the path before.

Errors are against heyoka in x87 extended precision at tol 1e-18 (as in
``taylor_peer.py``).  ``--quick`` leaves out the chain and SciPy's t = 1000 run.
Nothing is asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rhs import chain_pendulum
from taylor_peer import heyoka_integrator, reference_case

import lagrangian as lg
from lagrangian.integrate.choice import choose_run
from lagrangian.integrate.registry import method_class
from lagrangian.integrate.scipy_methods import MIN_RTOL
from lagrangian.numeric import compile_equations


def median_run(integrator, compiled, t_end, y0, params, repeat):
    """(median CPU seconds, final state) of ``repeat`` runs after one that compiles."""
    integrator.solve(compiled, (0.0, min(t_end, 1.0)), y0, params)
    seconds, final = [], None
    for _ in range(repeat):
        started = time.process_time()
        result = integrator.solve(compiled, (0.0, t_end), y0, params)
        seconds.append(time.process_time() - started)
        final = result.y[:, -1]
    return statistics.median(seconds), final


def heyoka_run(ode, y0, t_end, tol, repeat):
    """(median CPU seconds, final state, JIT seconds) of heyoka at ``tol``."""
    seconds, final, jit = [], None, 0.0
    for _ in range(repeat):
        integrator, jit = heyoka_integrator(ode, y0, tol)
        started = time.process_time()
        integrator.propagate_until(t_end)
        seconds.append(time.process_time() - started)
        final = np.array(integrator.state)
    return statistics.median(seconds), final, jit


def dop853(rtol, atol, t_end):
    return method_class("dop853").configure(t_span=(0.0, t_end), rtol=rtol, atol=atol)


def path_of(choice) -> str:
    """The way the chosen run goes, in a few words."""
    if choice.method == "taylor":
        return f"taylor (heyoka) on {choice.compiled.backend}"
    if choice.linked:
        return "dop853's compiled loop over llvm's M and f"
    if choice.compiled.backend == "numba":
        return "dop853's compiled loop (numba)"
    return f"dop853 in SciPy's loop on {choice.compiled.backend}"


def against_heyoka(label, system, angles, t_end, tol, repeat, *, scipy_too, tighter):
    eom, y0, ode, reference = reference_case(system, angles, t_end)
    heyoka_s, heyoka_y, jit = heyoka_run(ode, y0, t_end, tol, repeat)
    heyoka_error = float(np.max(np.abs(heyoka_y - reference)))
    names = [c.q.name for c in eom.coordinates]
    initial = dict(zip(names, y0[: len(names)].tolist(), strict=True))
    choice = choose_run(
        eom, t_end=t_end, method=None, backend=None, rtol=max(tol, MIN_RTOL), atol=tol,
        initial=initial, params={},
    )  # fmt: skip
    params = choice.compiled.parameter_vector()
    rows = [(f"default: {path_of(choice)}", choice.integrator(t_end), choice.compiled)]
    numba = compile_equations(eom, backend="numba")
    rows.append((f"dop853 compiled, tol {tol:g}", dop853(max(tol, MIN_RTOL), tol, t_end), numba))
    print(f"\n{label}, t = {t_end:g}, tol {tol:g}; the default's choice: {choice.reason}")
    print(f"{'run':>44} {'CPU s':>9} {'error':>9} {'/ heyoka':>9}")
    for name, integrator, compiled in rows:
        seconds, final = median_run(integrator, compiled, t_end, y0, params, repeat)
        error = float(np.max(np.abs(final - reference)))
        print(f"{name:>44} {seconds:>9.3f} {error:>9.1e} {seconds / heyoka_s:>9.2f}", flush=True)
    if tighter:  # DOP853 at the tolerance where its error is no larger than heyoka's
        for tight in (tol / 3, tol / 10, tol / 30, tol / 100, tol / 300, tol / 1000):
            integrator = dop853(max(tight, MIN_RTOL), tight, t_end)
            seconds, final = median_run(integrator, numba, t_end, y0, params, repeat)
            error = float(np.max(np.abs(final - reference)))
            name = f"dop853 compiled, tol {tight:.1e}"
            ratio = seconds / heyoka_s
            print(f"{name:>44} {seconds:>9.3f} {error:>9.1e} {ratio:>9.2f}", flush=True)
            if error <= heyoka_error:
                break
    if scipy_too:
        llvm = compile_equations(eom, backend="llvm")
        seconds, final = median_run(dop853(max(tol, MIN_RTOL), tol, t_end), llvm, t_end, y0,
                                    params, 1)  # fmt: skip
        error = float(np.max(np.abs(final - reference)))
        name = "dop853 in SciPy's loop (llvm), once"
        print(f"{name:>44} {seconds:>9.3f} {error:>9.1e} {seconds / heyoka_s:>9.2f}", flush=True)
    print(f"{'heyoka, JIT ' + format(jit, '.2f') + ' s':>44} {heyoka_s:>9.3f} {heyoka_error:>9.1e}")


FIRST_RUN = """
import json, sys, time
import lagrangian as lg
from lagrangian.integrate import simulate
from lagrangian.integrate.choice import choose_run
from lagrangian.numeric import compile_equations
system = lg.load("double_pendulum")
eom = system.equations_of_motion()
initial = {"theta1": 2.0, "theta2": 0.5}
start = time.process_time()
if sys.argv[1] == "default":
    choice = choose_run(eom, t_end=20.0, method=None, backend=None, rtol=None, atol=None,
                        initial=initial, params={})
    run = simulate(choice.compiled, t_end=20.0, initial=initial,
                   method=choice.integrator(20.0), choice=choice.reason)
else:
    run = simulate(compile_equations(eom, backend="llvm"), t_end=20.0, initial=initial)
done = time.process_time()
print(json.dumps([done - start, run.dataset.attrs.get("choice", "dop853 on llvm (before)")]))
"""


def first_run(repeat: int) -> None:
    print("\ndouble pendulum, first run (choice + compile + 20 s + trajectory), fresh processes,")
    print("CPU seconds")

    def child(kind: str, cache: str) -> tuple[float, str]:
        environment = dict(os.environ, LAGRANGIAN_CACHE=cache)
        done = subprocess.run(
            [sys.executable, "-c", FIRST_RUN, kind],
            capture_output=True, text=True, env=environment, check=True,
        )  # fmt: skip
        seconds, reason = json.loads(done.stdout.strip().splitlines()[-1])
        return seconds, reason

    results: dict[str, list[float]] = {"before": [], "default, empty cache": [], "default": []}
    reasons: dict[str, str] = {}
    for _ in range(repeat):
        with tempfile.TemporaryDirectory() as cache:
            for label, kind in (
                ("before", "before"), ("default, empty cache", "default"), ("default", "default")
            ):  # fmt: skip
                seconds, reasons[label] = child(kind, cache)
                results[label].append(seconds)
    before = statistics.median(results["before"])
    for label, seconds in results.items():
        median = statistics.median(seconds)
        print(f"{label:>22} {median:>7.3f} s {median / before:>6.2f}x   {reasons[label]}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="no chain, no SciPy t = 1000 run")
    args = parser.parse_args(argv)
    try:
        import heyoka  # noqa: F401
    except ImportError:
        print("heyoka is not installed (pip install heyoka): parts 1 and 2 skipped")
    else:
        against_heyoka(
            "double pendulum", lg.load("double_pendulum"), [0.3, 0.2], 1000.0, 1e-10,
            args.repeat, scipy_too=not args.quick, tighter=True,
        )  # fmt: skip
        if not args.quick:
            against_heyoka(
                "10-link chain", chain_pendulum(10), [0.1], 1000.0, 1e-15, 1,
                scipy_too=False, tighter=False,
            )  # fmt: skip
    first_run(args.repeat)


if __name__ == "__main__":
    main()

"""Issue 36, items 1 and 2: ``method="taylor"`` and the default against heyoka itself, in CPU time.

    python benchmarks/taylor_path.py [--repeat 5] [--quick]

In one process, for the double pendulum from (0.3, 0.2) at rest to t = 1000 at tol 1e-10
and the 10-link chain from theta1 = 0.1 to t = 1000 (tol 1e-10; ``--quick`` leaves the
chain out), the CPU seconds (user + sys of this process, ``time.process_time``; median of
``--repeat`` rounds, each round running every row once) of:

- heyoka itself, given the equations by hand (``taylor_peer.heyoka_ode``, the parameters as
  numbers), its integrator built before timing: ``propagate_until(t_end)`` (final state
  only), ``propagate_until(t_end, c_output=True)`` (every step kept, as our runs without
  output times keep every step) and ``propagate_grid`` of 1001 times;
- ours, ``Taylor(tol).solve`` with every step kept and with the 1001 output times, and
  ``simulate(..., method="taylor")`` as the CLI runs it (every step, a watch called);
- item 2: the default run (``choose_run``'s method) of the same case at the tolerance
  given, and the compiled DOP853 at the tolerance where its final error is no larger
  than heyoka's.

Each row: CPU seconds, the error of the final state against heyoka in x87 long double at
tol 1e-18 and the ratio to heyoka's ``propagate_until``.  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rhs import chain_pendulum
from taylor_peer import heyoka_integrator, reference_case

import lagrangian as lg
from lagrangian.integrate import simulate
from lagrangian.integrate.choice import choose_run
from lagrangian.integrate.registry import method_class
from lagrangian.integrate.scipy_methods import MIN_RTOL
from lagrangian.numeric import compile_equations

OUTPUTS = 1001


def interleaved(works, repeat: int):
    """[(name, median CPU seconds, last result)] of ``works`` [(name, work)], each run once
    per round for ``repeat`` rounds, so that a change of load falls on all alike."""
    seconds = {name: [] for name, _ in works}
    results = {}
    for _ in range(repeat):
        for name, work in works:
            start = time.process_time()
            results[name] = work()
            seconds[name].append(time.process_time() - start)
    return [(name, statistics.median(seconds[name]), results[name]) for name, _ in works]


def heyoka_works(ode, y0, t_end, tol):
    integrator, jit = heyoka_integrator(ode, y0, tol)
    grid = np.linspace(0.0, t_end, OUTPUTS)

    def reset():
        integrator.time = 0.0
        integrator.state[:] = y0

    def until():
        reset()
        integrator.propagate_until(t_end)
        return np.array(integrator.state)

    def until_steps():
        reset()
        output = integrator.propagate_until(t_end, c_output=True)[4]
        return output(output.times)[-1]

    def on_grid():
        reset()
        return integrator.propagate_grid(grid)[-1][-1]

    works = [("heyoka propagate_until", until), ("heyoka propagate_until, c_output", until_steps)]
    works.append((f"heyoka propagate_grid, {OUTPUTS} times", on_grid))
    return works, jit


def our_works(compiled, y0, t_end, tol):
    params = compiled.parameter_vector()
    taylor = method_class("taylor").configure(t_span=(0.0, t_end), rtol=tol, atol=tol)
    taylor.solve(compiled, (0.0, 1.0), y0, params)  # build the integrator once, untimed
    grid = np.linspace(0.0, t_end, OUTPUTS)
    names = [*compiled.coordinate_names, *(f"{c}_dot" for c in compiled.coordinate_names)]
    initial = dict(zip(names, y0.tolist(), strict=True))
    seen = []

    def every_step():
        return taylor.solve(compiled, (0.0, t_end), y0, params).y[:, -1]

    def on_grid():
        return taylor.solve(compiled, (0.0, t_end), y0, params, t_eval=grid).y[:, -1]

    def through_simulate():
        run = simulate(compiled, t_end=t_end, initial=initial, method=taylor, watch=seen.append)
        return np.array(list(run.final_state.values()))

    return [
        ("taylor solve, every step", every_step),
        (f"taylor solve, {OUTPUTS} times", on_grid),
        ("taylor simulate (as the CLI)", through_simulate),
    ]


def _error(final, reference):
    return None if reference is None else float(np.max(np.abs(final - reference)))


def case(label, system, angles, t_end, tol, repeat):
    eom, y0, ode, reference = reference_case(system, angles, t_end)
    compiled = compile_equations(eom, backend="llvm")
    heyoka, jit = heyoka_works(ode, y0, t_end, tol)
    rows = interleaved(heyoka + our_works(compiled, y0, t_end, tol), repeat)
    base = rows[0][1]
    heyoka_error = _error(rows[0][2], reference)
    print(f"\n{label}, t = {t_end:g}, tol {tol:g} (heyoka's JIT {jit:.2f} s, untimed)")
    print(f"{'run':>40} {'CPU s':>9} {'error':>9} {'/ heyoka':>9}")
    for name, seconds, final in rows:
        print(f"{name:>40} {seconds:>9.4f} {_error(final, reference):>9.1e} {seconds / base:>9.2f}")
    for name, seconds, final in _default(eom, y0, t_end, tol, heyoka_error, reference, repeat):
        print(f"{name:>40} {seconds:>9.4f} {_error(final, reference):>9.1e} {seconds / base:>9.2f}")


def _default(eom, y0, t_end, tol, heyoka_error, reference, repeat):
    """Item 2: the default's run, then DOP853 compiled down to heyoka's error."""
    initial = {c.q.name: float(y0[i]) for i, c in enumerate(eom.coordinates)}
    choice = choose_run(
        eom, t_end=t_end, method=None, backend=None, rtol=max(tol, MIN_RTOL), atol=tol,
        initial=initial, params={},
    )  # fmt: skip
    print(f"  the default's choice: {choice.method} on {choice.compiled.backend}: {choice.reason}")
    linked = " (compiled loop on llvm)" if choice.linked else ""
    default = choice.integrator(t_end)  # as simulate_system runs the choice
    yield _timed(f"default: {choice.method}{linked}", default, choice.compiled, y0, t_end, repeat)
    numba = compile_equations(eom, backend="numba")
    for tight in (tol, tol / 10, tol / 100, tol / 1000):
        dop853 = method_class("dop853").configure(
            t_span=(0.0, t_end), rtol=max(tight, MIN_RTOL), atol=tight
        )
        row = _timed(f"dop853 compiled, tol {tight:.0e}", dop853, numba, y0, t_end, repeat)
        yield row
        if _error(row[2], reference) <= heyoka_error:
            break


def _timed(label, integrator, compiled, y0, t_end, repeat):
    params = compiled.parameter_vector()
    integrator.solve(compiled, (0.0, 1.0), y0, params)  # compile or build, untimed
    work = lambda: integrator.solve(compiled, (0.0, t_end), y0, params).y[:, -1]  # noqa: E731
    return interleaved([(label, work)], repeat)[0]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--quick", action="store_true", help="the double pendulum only")
    args = parser.parse_args(argv)
    try:
        import heyoka
    except ImportError:
        print("heyoka is not installed (pip install heyoka): nothing to compare")
        return
    print(f"heyoka {heyoka.__version__}; CPU seconds (process_time), medians of {args.repeat}")
    case("double pendulum", lg.load("double_pendulum"), [0.3, 0.2], 1000.0, 1e-10, args.repeat)
    if not args.quick:
        case("10-link chain", chain_pendulum(10), [0.1], 1000.0, 1e-10, args.repeat)


if __name__ == "__main__":
    main()

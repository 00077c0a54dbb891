"""Fixed-step single runs in compiled code against the numba ensemble's per-member step.

    python benchmarks/compiled_runs.py [--repeat 3] [--steps 1000000] [--long 10000000]

Issue 19's and issue 36's (item 5) targets for rk4 and variational single runs on the
numba backend, double pendulum, dt = 0.001, in one process, in CPU time (user + sys of
every thread of this process, ``time.process_time``; medians of ``--repeat``):

- µs per step of ``RK4(dt).solve`` and ``Variational(dt).solve`` (one state, the whole
  loop in the generated module of ``codegen/loops.py``, the energy balance checked) with
  every state kept and with 1001 output times, and of ``simulate`` with 1001 output
  times (the check of the step against the motion's rate and the trajectory's energy
  included), against µs per member-step of the numba ensemble loop (the same module's
  ``run``, 2,000 members) run with ONE numba thread: "one core of the ensemble" is that
  run's CPU time per member-step; and the ratio (target: within 3x);
- ``--long`` steps of the variational run through ``simulate`` of the compiled system
  (1001 output times):
  the wall time (target: 10^7 steps in under 10 s) and the largest energy error
  max |E - E(0)| over the outputs (bounded: the method is symplectic).

Compilation is done before timing (a first short run).  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from variational import DT

import lagrangian as lg
from lagrangian.ensemble.chunk import Chunk
from lagrangian.ensemble.numba_backend import NumbaBackend
from lagrangian.integrate import simulate
from lagrangian.integrate.registry import method_class
from lagrangian.numeric import compile_equations

MEMBERS = 2000
OUTPUTS = 1001
INITIAL = {"theta1": 2.0, "theta2": 0.5}


def ensemble_member_step(compiled, method: str, steps: int, repeat: int) -> float:
    """Median µs per member-step of the numba ensemble loop, one thread."""
    import numba

    rng = np.random.default_rng(1)
    y0 = np.repeat(compiled.state_vector(INITIAL)[:, None], MEMBERS, axis=1)
    y0[: compiled.n] += rng.uniform(-0.1, 0.1, (compiled.n, MEMBERS))
    params = compiled.parameter_vector()
    integrator = method_class(method)(dt=DT)
    names = ("final_state",)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        backend = NumbaBackend()
        backend.integrate(Chunk(compiled, integrator, y0, params, 20 * DT, names))  # compile, warm
        times = []
        for _ in range(repeat):
            start = time.process_time()
            backend.integrate(Chunk(compiled, integrator, y0, params, steps * DT, names))
            times.append(time.process_time() - start)
    finally:
        numba.set_num_threads(threads)
    return 1e6 * statistics.median(times) / (steps * MEMBERS)


def per_step(compiled, method: str, steps: int, repeat: int, y0, params, **outputs) -> float:
    """Median CPU µs per step of ``method`` over ``steps`` steps of DT (``outputs``: t_eval)."""
    integrator = method_class(method)(dt=DT)
    integrator.solve(compiled, (0.0, 20 * DT), y0, params)  # compile and warm
    times = []
    for _ in range(repeat):
        start = time.process_time()
        result = integrator.solve(compiled, (0.0, steps * DT), y0, params, **outputs)
        times.append(time.process_time() - start)
        assert result.steps == steps, result.message
    return 1e6 * statistics.median(times) / steps


def long_run(compiled, steps: int) -> tuple[float, float, str]:
    """(wall s, max |E - E(0)|, status) of ``steps`` variational steps of ``compiled``
    through ``simulate`` (the step size choice, the energy check and 1001 outputs
    included; the derivation and the compilation, done before, are not)."""
    simulate(compiled, t_end=20 * DT, initial=INITIAL, method="variational", dt=DT)  # warm
    start = time.perf_counter()
    trajectory = simulate(
        compiled, t_end=steps * DT, initial=INITIAL, method="variational", dt=DT, n_out=1001
    )
    wall = time.perf_counter() - start
    energy = np.asarray(trajectory["energy"])
    return wall, float(np.max(np.abs(energy - energy[0]))), trajectory.status


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--steps", type=int, default=1_000_000)
    parser.add_argument("--long", type=int, default=10_000_000)
    args = parser.parse_args(argv)
    system = lg.load("double_pendulum")
    compiled = compile_equations(system.equations_of_motion(), backend="numba")
    y0, params = compiled.state_vector(INITIAL), compiled.parameter_vector()
    grid = {"t_eval": np.linspace(0.0, args.steps * DT, OUTPUTS)}
    print(f"CPU µs per step, {args.steps:,} steps; the ensemble: {MEMBERS:,} members, one thread")
    print(f"{'method':>12} {'run':>34} {'µs/step':>8} {'/ ensemble':>10}")
    for method in ("rk4", "variational"):
        member = ensemble_member_step(compiled, method, max(args.steps // 500, 100), args.repeat)
        rows = [
            ("solve, every step kept", per_step(compiled, method, args.steps, args.repeat, y0,
                                                params)),
            (f"solve, {OUTPUTS} output times", per_step(compiled, method, args.steps,
                                                        args.repeat, y0, params, **grid)),
            (f"simulate, {OUTPUTS} output times", through_simulate(compiled, method, args.steps,
                                                                   args.repeat)),
            ("ensemble member-step (1 thread)", member),
        ]  # fmt: skip
        for name, micro in rows:
            print(f"{method:>12} {name:>34} {micro:>8.3f} {micro / member:>10.2f}", flush=True)
    if args.long:
        wall, error, status = long_run(compiled, args.long)
        print(
            f"{args.long:,} variational steps (simulate, numba, 1001 outputs): {wall:.2f} s, "
            f"max |E - E(0)| = {error:.2e}, status {status}"
        )


def through_simulate(compiled, method: str, steps: int, repeat: int) -> float:
    """Median CPU µs per step of ``simulate`` (the step's check, the energy balance, the
    outputs and the trajectory included) with OUTPUTS output times."""
    simulate(compiled, t_end=20 * DT, initial=INITIAL, method=method, dt=DT)  # warm
    times = []
    for _ in range(repeat):
        start = time.process_time()
        simulate(compiled, t_end=steps * DT, initial=INITIAL, method=method, dt=DT, n_out=OUTPUTS)
        times.append(time.process_time() - start)
    return 1e6 * statistics.median(times) / steps


if __name__ == "__main__":
    main()

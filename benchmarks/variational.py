"""Microseconds per step of the variational integrator against rk4 at the same step.

    python benchmarks/variational.py [--repeat 3] [--steps 20000] [--links 10]

For the double pendulum (the README's ``simulate double_pendulum --method
variational --dt 0.001``: 20,000 steps) and the ``--links`` chain (a tenth of the
steps), on each backend (numpy, numba), one compiled system drives
``Variational(dt).solve`` and ``RK4(dt).solve`` over the same span in the same
run; printed are the medians over ``--repeat`` runs of µs per step and the ratio
variational / rk4 (target: within 3x on every backend).  The ``batch`` rows take
the same variational steps through the NumPy batch step (the path every single
run took before the compiled step of ``integrate/midpoint_step.py``), for
comparison.  Compilation is done before timing (a first short run).  Nothing is
asserted.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rhs import chain_pendulum

import lagrangian as lg
from lagrangian.integrate import variational
from lagrangian.integrate.registry import method_class
from lagrangian.numeric import compile_equations

DT = 0.001


def per_step(compiled, method: str, steps: int, repeat: int, y0, params) -> float:
    """Median µs per step of ``method`` over ``steps`` steps of DT."""
    integrator = method_class(method)(dt=DT)
    integrator.solve(compiled, (0.0, 20 * DT), y0, params)  # compile and warm
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = integrator.solve(compiled, (0.0, steps * DT), y0, params)
        times.append(time.perf_counter() - start)
        assert result.steps == steps, result.message
    return 1e6 * statistics.median(times) / steps


def batch_step(compiled, steps: int, repeat: int, y0, params) -> float:
    """As :func:`per_step` for variational, with the compiled one-state step turned off."""
    saved = variational.midpoint_functions
    variational.midpoint_functions = lambda compiled: None
    try:
        return per_step(compiled, "variational", steps, repeat, y0, params)
    finally:
        variational.midpoint_functions = saved


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--steps", type=int, default=20_000)
    parser.add_argument("--links", type=int, default=10)
    args = parser.parse_args(argv)
    models = [
        ("double pendulum", lg.load("double_pendulum"), {"theta1": 2.0, "theta2": 0.5}, 1),
        (f"{args.links}-link chain", chain_pendulum(args.links), {"theta1": 0.5}, 10),
    ]
    print(
        f"{'system':>16} {'backend':>8} {'steps':>7} {'rk4 µs':>9} {'variational µs':>15} "
        f"{'ratio':>6} {'batch µs':>9} {'batch/rk4':>10}"
    )
    for label, system, initial, fraction in models:
        eom = system.equations_of_motion()
        steps = max(args.steps // fraction, 100)
        for backend in ("numpy", "numba"):
            compiled = compile_equations(eom, backend=backend)
            y0, params = compiled.state_vector(initial), compiled.parameter_vector()
            rk4 = per_step(compiled, "rk4", steps, args.repeat, y0, params)
            ours = per_step(compiled, "variational", steps, args.repeat, y0, params)
            batch = batch_step(compiled, max(steps // 10, 100), args.repeat, y0, params)
            print(
                f"{label:>16} {backend:>8} {steps:>7} {rk4:>9.1f} {ours:>15.1f} "
                f"{ours / rk4:>6.2f} {batch:>9.1f} {batch / rk4:>10.1f}",
                flush=True,
            )
    print("ratio: variational / rk4 per step, same run; batch: the NumPy batch step (before)")


if __name__ == "__main__":
    main()

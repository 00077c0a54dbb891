"""Seconds and accuracy of parameter sensitivities (issue 33) against central differences.

    python benchmarks/sensitivity.py [--repeat 3]

- The driven damped pendulum (A = 0.5, regular motion), d(theta, theta_dot)/d(b, l) at
  1,000 times over 20 s (the size of the issue's fit of the damped pendulum);
- the double pendulum, d(state)/d(m2, l1, g) at 201 times over 10 s (its 3-parameter fit).

Ours: ``System.sensitivities`` (the forward sensitivity equations with the motion, DOP853
at rtol 1e-10, atol 1e-12), in the compiled loop (``backend="numba"``) and in SciPy's
loop.  The peer: central differences of 2k full runs (``System.simulate``, DOP853 at
rtol 1e-12, atol 1e-14, step 1e-4 of each value), what a fit without sensitivities
computes for its Jacobian.  Ours runs once untimed first (the compiled loop is built or
loaded, the kernels compiled).  Printed: median wall-clock and CPU
seconds, the ratio, and the largest difference between the two over each series,
relative to the series' largest size.  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import lagrangian as lg

TIGHT = {"rtol": 1e-12, "atol": 1e-14}


def timed(function, repeat: int) -> tuple[float, float, object]:
    """(median wall seconds, median CPU seconds, the last result) of ``repeat`` runs."""
    walls, cpus, result = [], [], None
    for _ in range(repeat):
        start, cpu = time.perf_counter(), time.process_time()
        result = function()
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - cpu)
    return statistics.median(walls), statistics.median(cpus), result


def differences(system, wrt, t_end, points, params, initial) -> np.ndarray:
    """d state / d w (times, states, wrt) by central differences of full runs."""
    times = np.linspace(0.0, t_end, points)
    names = [*system.coordinate_names, *(f"{q}_dot" for q in system.coordinate_names)]
    result = np.empty((points, len(names), len(wrt)))
    for column, name in enumerate(wrt):
        step = 1e-4 * max(1.0, abs(params[name]))
        runs = []
        for sign in (-1.0, 1.0):
            changed = dict(params, **{name: params[name] + sign * step})
            run = system.simulate(
                t_end=t_end, method="dop853", t_eval=times, params=changed, initial=initial,
                **TIGHT,
            )  # fmt: skip
            runs.append(np.column_stack([run[state] for state in names]))
        result[:, :, column] = (runs[1] - runs[0]) / (2 * step)
    return result


def case(label, system, wrt, t_end, points, params, initial, repeat) -> None:
    def ours(backend):
        return system.sensitivities(
            wrt, t_end=t_end, points=points, params=params, initial=initial, backend=backend
        )

    ours("numba")  # builds (or loads) the compiled loop
    compiled = timed(lambda: ours("numba"), repeat)
    ours(None)  # compiles the kernels
    mine = timed(lambda: ours(None), repeat)
    peer = timed(lambda: differences(system, wrt, t_end, points, params, initial), 1)
    values, reference = mine[2].values, peer[2]
    scale = np.max(np.abs(reference), axis=0)
    worst = float(np.max(np.max(np.abs(values - reference), axis=0) / scale))
    agree = float(np.max(np.abs(compiled[2].values - values)) / np.max(np.abs(values)))
    print(
        f"{label}: compiled loop (numba) {compiled[0]:.2f} s (CPU {compiled[1]:.2f} s, "
        f"{agree:.0e} from SciPy's loop); SciPy's loop "
        f"{mine[0]:.2f} s (CPU {mine[1]:.2f} s), central differences "
        f"{peer[0]:.2f} s (CPU {peer[1]:.2f} s), ratio {mine[1] / peer[1]:.3f} in CPU; "
        f"largest relative difference {worst:.1e}",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    pendulum = lg.load("driven_damped_pendulum")
    params = {p.name: p.default for p in pendulum.parameters} | {"A": 0.5}
    case(
        "driven damped pendulum, d/d(b, l), 1,000 times over 20 s", pendulum, ["b", "l"],
        20.0, 1000, params, {"theta": 0.2}, args.repeat,
    )  # fmt: skip
    double = lg.load("double_pendulum")
    params = {p.name: p.default for p in double.parameters}
    case(
        "double pendulum, d/d(m2, l1, g), 201 times over 10 s", double, ["m2", "l1", "g"],
        10.0, 201, params, {"theta1": 0.5, "theta2": 0.3}, args.repeat,
    )  # fmt: skip


if __name__ == "__main__":
    main()

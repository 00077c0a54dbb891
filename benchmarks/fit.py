"""CPU seconds of a fit (issue 33) with the sensitivity Jacobian, beside the same fit with
finite-difference Jacobians.

    python benchmarks/fit.py [--repeat 3]

- The damped pendulum (b and l from theta), 1,000 samples over 20 s;
- the double pendulum (m2, l1 and g from theta1 and theta2), 201 samples over 10 s.

The data are made without lagrangian: SciPy's solve_ivp (rtol 1e-12) of the hand-written
equations, with Gaussian noise of 1 % of each column's largest size (seed 1); the guesses
are 10-15 % off the truth.

Ours: ``System.fit`` on the numba backend (and, for comparison, on llvm: the sensitivity
equations in SciPy's loop) (the sensitivity equations in the compiled
DOP853 loop, built once per process and loaded from the code cache after that), timed
after a first untimed call, whole: the data checked, the model compiled (found in this
process's caches after the first call), the starts searched.  The peer: the same
residuals, the same ``least_squares`` (trf, x_scale='jac', the same tolerances and
bounds) and the same DOP853 for the motion (rtol 1e-9, atol 1e-11), with
``jac='2-point'``: a Jacobian from k + 1 runs of the motion alone per step; in the
compiled loop (numba) beside ours on numba, and in SciPy's loop (solve_ivp over the llvm
right-hand side) beside ours on llvm.  Printed: median CPU seconds (this process's), the
ratio, the evaluations, and the largest difference of the two fits' values relative to
the standard errors.  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares

import lagrangian as lg
from lagrangian.integrate import fit as fitting
from lagrangian.integrate.compiled_dop853 import compiled_loop
from lagrangian.integrate.compiled_sensitivity import solve_on_grid
from lagrangian.integrate.observation import observation
from lagrangian.numeric import compile_equations

DAMPED = """
name = "Damped pendulum"
coordinates = ["theta"]
kinetic = "m*l^2*theta_dot^2/2"
potential = "-m*g*l*cos(theta)"
dissipation = "b*theta_dot^2/2"
[parameters]
m = 1.0
g = 9.81
l = 1.0
b = 0.1
"""


def cpu_median(function, repeat: int) -> tuple[float, object]:
    """(median CPU seconds, the last result) of ``repeat`` calls."""
    times, result = [], None
    for _ in range(repeat):
        start = time.process_time()
        result = function()
        times.append(time.process_time() - start)
    return statistics.median(times), result


def measured(rhs, y0, t_end, points, columns) -> dict[str, np.ndarray]:
    t = np.linspace(0.0, t_end, points)
    run = solve_ivp(rhs, (0.0, t_end), y0, t_eval=t, rtol=1e-12, atol=1e-12, method="DOP853")
    rng = np.random.default_rng(1)
    data = {"t": t}
    for name, row in columns.items():
        values = run.y[row]
        data[name] = values + 0.01 * np.max(np.abs(values)) * rng.standard_normal(t.size)
    return data


def peer_fit(system, data, guesses, initial, params, backend) -> tuple[np.ndarray, int]:
    """The same fit with jac='2-point' over the motion alone: in the compiled DOP853 loop
    (``backend="numba"``) or SciPy's (``"llvm"``)."""
    compiled = compile_equations(system.equations_of_motion(), backend=backend)
    loop = compiled_loop(compiled) if backend == "numba" else None
    rtol, atol = fitting.DEFAULT_RTOL, fitting.DEFAULT_ATOL

    def motion(y0, p, times):
        if loop is not None:
            return solve_on_grid(loop, y0, p, times, rtol, atol)
        run = solve_ivp(
            lambda t, y: compiled.rhs(t, y, p), (0.0, times[-1]), y0, method="DOP853",
            t_eval=times, rtol=rtol, atol=atol,
        )  # fmt: skip
        return run.y.T

    names = list(guesses)
    p0 = compiled.parameter_vector(params)
    y0 = compiled.state_vector(initial)
    columns = [c for c in data if c != "t"]
    seen = observation(system, columns, {})
    measured_values = np.array([data[c] for c in columns])
    times = data["t"]
    slots = [compiled.parameter_names.index(n) for n in names]
    evaluations = [0]

    def residuals(x):
        p = p0.copy()
        p[slots] = x
        evaluations[0] += 1
        states = motion(y0, p, times)
        h, _, _ = seen.evaluate(times, states, p)
        return (h.T - measured_values).ravel()

    lower = np.zeros(len(names))
    result = least_squares(
        residuals, np.array([guesses[n] for n in names]), jac="2-point", bounds=(lower, np.inf),
        method="trf", x_scale="jac", ftol=fitting.TOLERANCE, xtol=fitting.TOLERANCE,
        gtol=fitting.TOLERANCE,
    )  # fmt: skip
    return result.x, evaluations[0]


def case(label, system, data, guesses, initial, params, repeat) -> None:
    def ours(backend="numba"):
        return system.fit(data, guesses, initial=initial, params=params, backend=backend)

    first, _ = cpu_median(ours, 1)  # derives, builds (or loads) the compiled loop
    whole, result = cpu_median(ours, repeat)
    ours("llvm")  # compiles the kernels of SciPy's loop
    scipy_loop, _ = cpu_median(lambda: ours("llvm"), repeat)
    peer_fit(system, data, guesses, initial, params, "numba")
    peer_seconds, (values, evaluations) = cpu_median(
        lambda: peer_fit(system, data, guesses, initial, params, "numba"), repeat
    )
    peer_fit(system, data, guesses, initial, params, "llvm")
    peer_scipy, _ = cpu_median(
        lambda: peer_fit(system, data, guesses, initial, params, "llvm"), repeat
    )
    gap = np.max(np.abs(values - result.values) / result.stderr)
    fitted = ", ".join(
        f"{n} = {v:.6g} ± {e:.2g}"
        for n, v, e in zip(result.names, result.values, result.stderr, strict=True)
    )
    print(
        f"{label}: compiled loop: ours {whole:.3f} s CPU ({result.evaluations} evaluations, "
        f"{result.iterations} iterations; the first call {first:.2f} s), finite differences "
        f"{peer_seconds:.3f} s ({evaluations} motions), ratio {whole / peer_seconds:.2f}; "
        f"SciPy's loop: ours {scipy_loop:.3f} s, finite differences {peer_scipy:.3f} s, "
        f"ratio {scipy_loop / peer_scipy:.2f}; {fitted}; "
        f"the two fits differ by {gap:.1e} standard errors",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    g, l, b, m = 9.81, 0.75, 0.12, 1.0
    data = measured(
        lambda t, y: [y[1], -g / l * np.sin(y[0]) - b / (m * l * l) * y[1]],
        [0.4, 0.0], 20.0, 1000, {"theta": 0},
    )  # fmt: skip
    case(
        "damped pendulum, b and l, 1,000 samples over 20 s", lg.loads(DAMPED), data,
        {"b": 0.105, "l": 0.85}, {"theta": 0.4}, {}, args.repeat,
    )  # fmt: skip

    m1, m2, l1, l2, g = 1.0, 0.8, 1.1, 1.0, 9.81

    def double(t, y):
        a, c, u, v = y
        delta = a - c
        den = 2 * m1 + m2 - m2 * np.cos(2 * delta)
        ua = (
            -g * (2 * m1 + m2) * np.sin(a) - m2 * g * np.sin(a - 2 * c)
            - 2 * np.sin(delta) * m2 * (v * v * l2 + u * u * l1 * np.cos(delta))
        ) / (l1 * den)  # fmt: skip
        va = (
            2 * np.sin(delta)
            * (u * u * l1 * (m1 + m2) + g * (m1 + m2) * np.cos(a) + v * v * l2 * m2 * np.cos(delta))
        ) / (l2 * den)  # fmt: skip
        return [u, v, ua, va]

    data = measured(double, [0.5, 0.3, 0.0, 0.0], 10.0, 201, {"theta1": 0, "theta2": 1})
    case(
        "double pendulum, m2, l1 and g, 201 samples over 10 s", lg.load("double_pendulum"),
        data, {"m2": 0.9, "l1": 1.0, "g": 9.0}, {"theta1": 0.5, "theta2": 0.3},
        {"m1": m1, "l2": l2}, args.repeat,
    )  # fmt: skip


if __name__ == "__main__":
    main()

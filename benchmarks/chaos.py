"""Seconds of the chaos tools (issue 20) against the same work written by hand with SciPy.

    python benchmarks/chaos.py [--repeat 3] [--orbits 50] [--crossings 2000]
                               [--spectrum-t 10000] [--values 400] [--backend numba]

- Poincaré section: the Hénon–Heiles section x = 0 at E = 1/8, ``--orbits`` orbits
  started on the energy shell, each run until about ``--crossings`` crossings (t_end =
  6.4 per crossing); against ``solve_ivp`` (DOP853, same tolerances) of the hand-written
  equations with a hand-written event, from the same starts.
- Lyapunov spectrum: the full spectrum of the double pendulum to t = ``--spectrum-t``
  (interval 1, rtol 1e-9); against ``solve_ivp`` of the hand-written variational
  equations (the Jacobian by hand) with the same QR every unit of time.
- Bifurcation diagram: the driven damped pendulum, ``--values`` drives from 1.35 to 1.5,
  300 time units of transient and 100 strobe samples, rk4 with 200 steps per period, on
  ``--backend`` (numba: its code is compiled once, before the timing).

Printed: medians over ``--repeat`` runs and the ratios ours / by hand.  Nothing is
asserted; the issue's targets are 10 s, 10 s and 30 s at the default sizes.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.integrate.lyapunov import lyapunov_spectrum
from lagrangian.numeric import compile_equations

RTOL, ATOL = 1e-10, 1e-12
DRIVE_PERIOD = 3 * math.pi


def timed(function, repeat: int) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def henon_heiles_rhs(t, y):
    x, yy, vx, vy = y
    return [vx, vy, -x - 2 * x * yy, -yy - x * x + yy * yy]


def section_by_hand(starts: np.ndarray, t_end: float) -> int:
    def crossing(t, y):
        return y[0]

    crossing.direction = 1
    count = 0
    for k in range(starts.shape[1]):
        solution = solve_ivp(henon_heiles_rhs, (0, t_end), starts[:, k], method="DOP853",
                             rtol=RTOL, atol=ATOL, events=crossing)  # fmt: skip
        count += len(solution.t_events[0])
    return count


def double_pendulum_jacobian(y, g=9.81):
    """rhs and d rhs / dy of the double pendulum with unit masses and rods, by hand."""
    t1, t2, w1, w2 = y
    d = t1 - t2
    c, s = math.cos(d), math.sin(d)
    mass = np.array([[2.0, c], [c, 1.0]])
    force = np.array([-s * w2 * w2 - 2 * g * math.sin(t1), s * w1 * w1 - g * math.sin(t2)])
    accel = np.linalg.solve(mass, force)
    # d(f - M a)/d(t1, t2, w1, w2) at the solved a
    dm_dd = np.array([[0.0, -s], [-s, 0.0]]) @ accel
    df = np.array(
        [
            [-c * w2 * w2 - 2 * g * math.cos(t1), c * w2 * w2, 0.0, -2 * s * w2],
            [c * w1 * w1, -c * w1 * w1 - g * math.cos(t2), 2 * s * w1, 0.0],
        ]
    )
    df[:, 0] -= dm_dd
    df[:, 1] += dm_dd
    lower = np.linalg.solve(mass, df)
    jacobian = np.zeros((4, 4))
    jacobian[0, 2] = jacobian[1, 3] = 1.0
    jacobian[2:] = lower
    return np.array([w1, w2, *accel]), jacobian


def spectrum_by_hand(y0: np.ndarray, t_end: float) -> np.ndarray:
    def rhs(t, z):
        slope, jacobian = double_pendulum_jacobian(z[:4])
        return np.concatenate((slope, (jacobian @ z[4:].reshape(4, 4)).ravel()))

    y, w, sums = y0, np.eye(4), np.zeros(4)
    for k in range(int(t_end)):
        z = solve_ivp(rhs, (k, k + 1), np.concatenate((y, w.ravel())), method="DOP853",
                      rtol=1e-9, atol=1e-11).y[:, -1]  # fmt: skip
        y, (w, r) = z[:4], np.linalg.qr(z[4:].reshape(4, 4))
        sums += np.log(np.abs(np.diag(r)))
    return sums / t_end


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--orbits", type=int, default=50)
    parser.add_argument("--crossings", type=int, default=2000)
    parser.add_argument("--spectrum-t", type=float, default=10_000.0)
    parser.add_argument("--values", type=int, default=400)
    parser.add_argument("--backend", default="numba")
    options = parser.parse_args()

    henon = lg.load("henon_heiles")
    t_end = 6.4 * options.crossings
    compiled = compile_equations(henon.equations_of_motion(), backend="llvm")
    from lagrangian.integrate.poincare import shell_starts
    from lagrangian.integrate.section import parse_section

    starts = shell_starts(compiled, parse_section(compiled, "x = 0"), 1 / 8, options.orbits, "y")
    ours, points = timed(
        lambda: henon.poincare(section="x = 0", axes=("y", "p_y"), energy=1 / 8,
                               orbits=options.orbits, t_end=t_end, timeout=None),
        options.repeat,
    )  # fmt: skip
    hand, count = timed(lambda: section_by_hand(starts, t_end), options.repeat)
    print(f"Henon-Heiles section, {options.orbits} orbits x t = {t_end:g} "
          f"({points.count} / {count} crossings): ours {ours:.2f} s, by hand {hand:.2f} s, "
          f"ratio {ours / hand:.2f}")  # fmt: skip

    pendulum = compile_equations(lg.load("double_pendulum").equations_of_motion(), backend="llvm")
    y0 = pendulum.state_vector()
    ours, spectrum = timed(
        lambda: lyapunov_spectrum(pendulum, t_end=options.spectrum_t), options.repeat
    )
    hand, reference = timed(lambda: spectrum_by_hand(y0, options.spectrum_t), options.repeat)
    print(f"double pendulum spectrum to t = {options.spectrum_t:g}: ours {ours:.2f} s "
          f"{np.round(spectrum.exponents, 3)}, by hand {hand:.2f} s {np.round(reference, 3)}, "
          f"ratio {ours / hand:.2f}")  # fmt: skip

    driven = lg.load("driven_damped_pendulum")

    def diagram(values: int):
        return driven.bifurcation(
            vary={"A": np.linspace(1.35, 1.5, values)}, variable="theta_dot",
            period=DRIVE_PERIOD, transient=300, samples=100, backend=options.backend,
            timeout=None,
        )  # fmt: skip

    diagram(2)  # numba's compile, cached on disk for the timed runs
    ours, result = timed(lambda: diagram(options.values), options.repeat)
    print(f"bifurcation diagram, {options.values} values x {result.points.shape[1]} samples "
          f"({options.backend}): {ours:.2f} s")  # fmt: skip


if __name__ == "__main__":
    main()

"""Seconds of the chaos tools (issue 20) against the same work written by hand with SciPy.

    python benchmarks/chaos.py [--repeat 3] [--peer-repeat 1] [--orbits 50] [--crossings 2000]
                               [--spectrum-t 10000] [--values 400] [--backend numba]
                               [--skip-peer] [--skip-diagram]

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

Ours runs once untimed first (numba compiles the loops, or loads them from the code
cache); the hand-written SciPy peers, minutes long at full size, run ``--peer-repeat``
times.  Printed: medians over the runs, wall-clock seconds and this process's CPU
seconds (the machine may be shared), and the ratios ours / by hand.  Nothing is
asserted; the issue's targets are 10 s, 10 s and 30 s at the default sizes.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numpy as np
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.integrate.lyapunov import lyapunov_spectrum
from lagrangian.numeric import compile_equations

RTOL, ATOL = 1e-10, 1e-12
DRIVE_PERIOD = 3 * math.pi


def timed(function, repeat: int) -> tuple[float, float, object]:
    """(median wall seconds, median CPU seconds, the last result) of ``repeat`` runs."""
    walls, cpus, result = [], [], None
    for _ in range(repeat):
        start, cpu = time.perf_counter(), time.process_time()
        result = function()
        walls.append(time.perf_counter() - start)
        cpus.append(time.process_time() - cpu)
    return statistics.median(walls), statistics.median(cpus), result


def report(label: str, ours: tuple, hand: tuple | None) -> None:
    line = f"{label}: ours {ours[0]:.2f} s (CPU {ours[1]:.2f} s)"
    if hand is not None:
        line += f", by hand {hand[0]:.2f} s (CPU {hand[1]:.2f} s), ratio {ours[0] / hand[0]:.3f}"
        line += f" (CPU {ours[1] / hand[1]:.3f})"
    print(line, flush=True)


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
    parser.add_argument("--peer-repeat", type=int, default=1)
    parser.add_argument("--orbits", type=int, default=50)
    parser.add_argument("--crossings", type=int, default=2000)
    parser.add_argument("--spectrum-t", type=float, default=10_000.0)
    parser.add_argument("--values", type=int, default=400)
    parser.add_argument("--backend", default="numba")
    parser.add_argument("--skip-peer", action="store_true", help="time ours only")
    parser.add_argument("--skip-diagram", action="store_true")
    options = parser.parse_args()
    print(f"load average {os.getloadavg()}", flush=True)

    henon = lg.load("henon_heiles")
    t_end = 6.4 * options.crossings
    compiled = compile_equations(henon.equations_of_motion(), backend="llvm")
    from lagrangian.integrate.poincare import shell_starts
    from lagrangian.integrate.section import parse_section

    starts = shell_starts(compiled, parse_section(compiled, "x = 0"), 1 / 8, options.orbits, "y")

    def section(orbits: int, t: float):
        return henon.poincare(section="x = 0", axes=("y", "p_y"), energy=1 / 8, orbits=orbits,
                              t_end=t, timeout=None)  # fmt: skip

    section(1, 10.0)  # numba's compile, cached on disk for the timed runs
    *ours, points = timed(lambda: section(options.orbits, t_end), options.repeat)
    hand = None
    if not options.skip_peer:
        *hand, count = timed(lambda: section_by_hand(starts, t_end), options.peer_repeat)
        print(f"(by hand: {count} crossings)")
    report(f"Henon-Heiles section, {options.orbits} orbits x t = {t_end:g} "
           f"({points.count} crossings)", ours, hand)  # fmt: skip

    pendulum = compile_equations(lg.load("double_pendulum").equations_of_motion(), backend="llvm")
    y0 = pendulum.state_vector()
    lyapunov_spectrum(pendulum, t_end=2.0)  # numba's compile, as above
    *ours, spectrum = timed(
        lambda: lyapunov_spectrum(pendulum, t_end=options.spectrum_t), options.repeat
    )
    hand = None
    if not options.skip_peer:
        *hand, reference = timed(
            lambda: spectrum_by_hand(y0, options.spectrum_t), options.peer_repeat
        )
        print(f"(by hand: {np.round(reference, 3)})")
    report(f"double pendulum spectrum to t = {options.spectrum_t:g} "
           f"{np.round(spectrum.exponents, 3)}", ours, hand)  # fmt: skip

    if options.skip_diagram:
        return
    driven = lg.load("driven_damped_pendulum")

    def diagram(values: int):
        return driven.bifurcation(
            vary={"A": np.linspace(1.35, 1.5, values)}, variable="theta_dot",
            period=DRIVE_PERIOD, transient=300, samples=100, backend=options.backend,
            timeout=None,
        )  # fmt: skip

    diagram(2)  # numba's compile, cached on disk for the timed runs
    *ours, result = timed(lambda: diagram(options.values), options.repeat)
    report(f"bifurcation diagram, {options.values} values x {result.points.shape[1]} samples "
           f"({options.backend})", ours, None)  # fmt: skip
    print(f"load average {os.getloadavg()}", flush=True)


if __name__ == "__main__":
    main()

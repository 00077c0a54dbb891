"""Solve time of a whole simulation against a hand-written NumPy right-hand side.

    python benchmarks/simulate.py [--links 10] [--t-end 10] [--repeat 3] [--taylor]

For the double pendulum and an N-link pendulum built from particles: µs per
``rhs`` call (ours vs hand-written, same run), and the wall time of a complete
DOP853 run (rtol 1e-10, atol 1e-12) through ``lagrangian``'s ``simulate``
against ``scipy.integrate.solve_ivp`` driving the hand-written rhs with the
same settings; for the N-link pendulum also the numba backend against
``solve_ivp`` driving the hand-written numba kernel (``rhs.chain_by_hand_numba``),
with the first-call (generate + jit) time.  PyDy is timed too when it is installed.  Medians of
``--repeat`` runs; ratios > 1 mean we are slower.  ``--taylor`` adds heyoka
(Taylor's method) against our DOP853 and Radau at tolerances 1e-10 and 1e-15, to
t = 10 and 1000, errors against an extended-precision reference
(:mod:`taylor_peer`; only that part with ``--taylor-only``).  Not a test: nothing
is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parent))
import taylor_peer
from pydy_chain import chain_by_pydy
from rhs import (
    chain_by_hand,
    chain_by_hand_numba,
    chain_pendulum,
    double_pendulum_by_hand,
    microseconds,
)

import lagrangian as lg
from lagrangian.integrate import simulate
from lagrangian.numeric import compile_equations

RTOL, ATOL = 1e-10, 1e-12


def median_seconds(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def compare(label, system, hand_rhs, hand_params, y0, t_end, repeat, backend="numpy") -> None:
    start = time.perf_counter()
    compiled = compile_equations(system.equations_of_motion(), backend=backend)
    params = compiled.parameter_vector()
    compiled.rhs(0.0, y0, params)  # generate the code before timing
    setup = time.perf_counter() - start
    hand_rhs(0.0, y0, hand_params)  # a jitted reference compiles before timing
    ours_call = microseconds(compiled.rhs, 0.0, y0, params, repeat=repeat)
    hand_call = microseconds(hand_rhs, 0.0, y0, hand_params, repeat=repeat)
    names = list(compiled.coordinate_names) + [f"{c}_dot" for c in compiled.coordinate_names]
    initial = dict(zip(names, y0, strict=True))

    def ours():
        return simulate(
            compiled, t_end=t_end, initial=initial, method="dop853", rtol=RTOL, atol=ATOL
        )

    def hand():
        return solve_ivp(
            hand_rhs, (0, t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL, args=(hand_params,)
        )

    ours_solve = median_seconds(ours, repeat)
    hand_solve = median_seconds(hand, repeat)
    final_ours = ours().final_state
    final_hand = hand().y[:, -1]
    difference = max(abs(final_ours[n] - v) for n, v in zip(names, final_hand, strict=True))
    print(f"\n{label}, backend {backend}  (derive + compile + first call {setup:.2f} s)")
    call_ratio, solve_ratio = ours_call / hand_call, ours_solve / hand_solve
    print(
        f"  rhs call      ours {ours_call:9.1f} µs   hand {hand_call:9.1f} µs   {call_ratio:5.2f}x"
    )
    print(
        f"  {t_end:g} s DOP853  ours {ours_solve * 1e3:9.1f} ms   "
        f"hand {hand_solve * 1e3:9.1f} ms   {solve_ratio:5.2f}x"
    )
    print(f"  final states agree to {difference:.1e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--links", type=int, default=10)
    parser.add_argument("--t-end", type=float, default=10.0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--taylor", action="store_true", help="heyoka at tight tolerances too")
    parser.add_argument("--taylor-only", action="store_true", help="only the heyoka comparison")
    args = parser.parse_args()
    if args.taylor_only:
        taylor_peer.main(args.repeat)
        return
    print(f"python {sys.version.split()[0]}, numpy {np.__version__}")
    y0 = np.array([2.0, 0.5, 0.0, 0.0])
    compare(
        "double pendulum",
        lg.load("double_pendulum"),
        double_pendulum_by_hand,
        np.array([1.0, 1.0, 1.0, 1.0, 9.81]),
        y0,
        args.t_end,
        args.repeat,
    )
    n = args.links
    y0 = np.concatenate([np.linspace(0.3, 0.6, n), np.zeros(n)])
    hand = chain_by_hand(n)
    compare(
        f"{n}-link pendulum",
        chain_pendulum(n),
        hand,
        np.concatenate([np.ones(n), np.ones(n), [9.81]]),
        y0,
        args.t_end,
        args.repeat,
    )
    chain_params = np.concatenate([np.ones(n), np.ones(n), [9.81]])
    hand_numba = chain_by_hand_numba(n)
    if hand_numba is None:
        print("\nnumba backend: numba not installed, skipped")
    else:
        compare(
            f"{n}-link pendulum vs hand-written numba",
            chain_pendulum(n),
            hand_numba,
            chain_params,
            y0,
            args.t_end,
            args.repeat,
            backend="numba",
        )
    if args.taylor:
        taylor_peer.main(args.repeat)
    pydy_rhs, pydy_setup = chain_by_pydy(n)
    if pydy_rhs is None:
        print("\nPyDy: not installed, skipped (pip install pydy cython)")
        return
    print(f"\nPyDy: KanesMethod + Cython code generation took {pydy_setup:.1f} s")
    compare(
        f"{n}-link pendulum vs PyDy Cython + solve_ivp",
        chain_pendulum(n),
        pydy_rhs,
        chain_params,
        y0,
        args.t_end,
        args.repeat,
        backend="numba" if hand_numba is not None else "numpy",
    )


if __name__ == "__main__":
    main()

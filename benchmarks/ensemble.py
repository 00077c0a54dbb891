"""Trajectory-steps per second of ensembles of the double pendulum (RK4, fixed step).

    python benchmarks/ensemble.py [--members 20000] [--steps 1000] [--repeat 3]

Backends ``numpy`` and ``numba`` of :func:`lagrangian.ensemble.run_ensemble`
against a hand-written numba kernel: the closed-form double-pendulum
accelerations in the same parallel (prange over members) RK4 loop; the
variational method (midpoint, Newton per step) on both backends; with JAX
installed, the ``jax`` backend (float64 and float32, on JAX's default device)
against a hand-written ``jax.vmap`` RK4 (``gpu.hand_jax``).  Compiled runs
are warmed up first (compile time excluded).  Medians of
``--repeat`` runs; ratio = hand kernel / ours (> 1: we are slower).  Not a
test: nothing is asserted beyond the kernels agreeing.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gpu import hand_jax, median_rate

import lagrangian as lg
from lagrangian.ensemble import run_ensemble
from lagrangian.numeric import compile_equations


def hand_kernel():
    """The double pendulum (point masses, massless rods) by hand, RK4, prange over members."""
    import numba

    @numba.njit(inline="always")
    def derivative(y, p, out):
        m1, m2, l1, l2, g = p[0], p[1], p[2], p[3], p[4]
        t1, t2, w1, w2 = y[0], y[1], y[2], y[3]
        d = t1 - t2
        sd, cd = math.sin(d), math.cos(d)
        den = 2.0 * m1 + m2 - m2 * math.cos(2.0 * d)
        out[0] = w1
        out[1] = w2
        out[2] = (
            -g * (2.0 * m1 + m2) * math.sin(t1)
            - m2 * g * math.sin(t1 - 2.0 * t2)
            - 2.0 * sd * m2 * (w2 * w2 * l2 + w1 * w1 * l1 * cd)
        ) / (l1 * den)
        out[3] = (
            2.0
            * sd
            * (w1 * w1 * l1 * (m1 + m2) + g * (m1 + m2) * math.cos(t1) + w2 * w2 * l2 * m2 * cd)
        ) / (l2 * den)

    @numba.njit(parallel=True)
    def run(y0, p, dt, steps, final):
        for b in numba.prange(y0.shape[0]):
            y = y0[b].copy()
            k1, k2, k3, k4, s = np.empty(4), np.empty(4), np.empty(4), np.empty(4), np.empty(4)
            for _ in range(steps):
                derivative(y, p, k1)
                for i in range(4):
                    s[i] = y[i] + 0.5 * dt * k1[i]
                derivative(s, p, k2)
                for i in range(4):
                    s[i] = y[i] + 0.5 * dt * k2[i]
                derivative(s, p, k3)
                for i in range(4):
                    s[i] = y[i] + dt * k3[i]
                derivative(s, p, k4)
                for i in range(4):
                    y[i] += dt * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) / 6.0
            final[b] = y

    return run


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--members", type=int, default=20_000)
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--numpy-steps", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    import numba

    compiled = compile_equations(lg.load("double_pendulum").equations_of_motion())
    rng = np.random.default_rng(0)
    theta = rng.uniform(-3.0, 3.0, size=(2, args.members))
    dt = 0.01
    initial = {"theta1": theta[0], "theta2": theta[1]}

    def ours(backend: str, steps: int, method: str = "rk4"):
        return run_ensemble(
            compiled, initial=initial, t_end=steps * dt, dt=dt, backend=backend,
            method=method, chunk_size=args.members,
        )  # fmt: skip

    ours("numba", 2)  # compile
    work = args.members * args.steps
    numba_rate = median_rate(lambda: ours("numba", args.steps), work, args.repeat)
    numpy_work = args.members * args.numpy_steps
    numpy_rate = median_rate(lambda: ours("numpy", args.numpy_steps), numpy_work, args.repeat)

    run = hand_kernel()
    y0 = np.ascontiguousarray(np.vstack([theta, np.zeros_like(theta)]).T)
    p = compiled.parameter_vector()
    final = np.empty_like(y0)
    run(y0, p, dt, 2, final)  # compile
    hand_rate = median_rate(lambda: run(y0, p, dt, args.steps, final), work, args.repeat)
    check = ours("numba", args.steps).final_state["theta1"]
    agreement = float(np.max(np.abs(check - final[:, 0])))

    print(
        f"double pendulum, RK4 dt={dt}, {args.members} members, {numba.get_num_threads()} threads"
    )
    print(f"  numpy backend      {numpy_rate:12.3g} trajectory-steps/s ({args.numpy_steps} steps)")
    print(f"  numba backend      {numba_rate:12.3g} trajectory-steps/s ({args.steps} steps)")
    print(f"  hand numba kernel  {hand_rate:12.3g} trajectory-steps/s")
    print(f"  ratio hand / numba backend: {hand_rate / numba_rate:.2f}")
    print(f"  numpy backend / hand: {numpy_rate / hand_rate:.3f}")
    print(f"  max |theta1 ours - hand| at the end: {agreement:.2e}")
    ours("numba", 2, "variational")  # compile
    numba_variational = median_rate(
        lambda: ours("numba", args.steps, "variational"), work, args.repeat
    )
    numpy_variational = median_rate(
        lambda: ours("numpy", args.numpy_steps, "variational"), numpy_work, args.repeat
    )
    print(f"  numba backend, variational (midpoint)  {numba_variational:12.3g} trajectory-steps/s")
    print(f"  numpy backend, variational (midpoint)  {numpy_variational:12.3g} trajectory-steps/s")
    jax_rows(compiled, initial, y0.T.copy(), p, dt, args)


def jax_rows(compiled, initial, y0, p, dt, args) -> None:
    """The jax backend against a hand-written jax.vmap RK4, same members and steps."""
    try:
        import jax
    except ImportError:
        print("  jax: not installed, skipped")
        return
    work = args.members * args.steps
    with jax.enable_x64(True):
        hand = hand_jax(jax, args.steps, dt)
        states, params = jax.numpy.asarray(y0), jax.numpy.asarray(p)
        hand(states, params).block_until_ready()
        hand_rate = median_rate(lambda: hand(states, params).block_until_ready(), work, args.repeat)
    device = jax.devices()[0].platform
    print(f"  hand jax.vmap RK4 (float64, {device}) {hand_rate:10.3g} trajectory-steps/s")
    for precision in ("float64", "float32"):

        def ours(steps, precision=precision):
            return run_ensemble(
                compiled, initial=initial, t_end=steps * dt, dt=dt, backend="jax",
                precision=precision, chunk_size=args.members,
            )  # fmt: skip

        ours(args.steps)  # compile
        rate = median_rate(lambda run=ours: run(args.steps), work, args.repeat)
        print(
            f"  jax backend {precision}      {rate:12.3g} trajectory-steps/s   "
            f"hand jax / ours {hand_rate / rate:.2f}"
        )


if __name__ == "__main__":
    main()

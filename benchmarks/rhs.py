"""Microseconds per call of the compiled right-hand side, against hand-written NumPy.

    python benchmarks/rhs.py [--links 10] [--repeat 7]

Systems: the double pendulum (built-in example) and an N-link pendulum built
from particles.  References, written by hand in the same run: the textbook
double-pendulum rhs (explicit 2x2 formulas), and the N-link closed form
M theta'' = f (mu_ij l_i l_j cos(theta_i - theta_j), vectorised) solved with
``np.linalg.solve``, and the same closed form as a ``numba.njit`` kernel for
the numba backend row (when numba is installed).  Printed: the median over ``--repeat`` timings of
µs/call for one state, per state for a batch of 1000, and the ratio
compiled / hand-written.  This is not a test: nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time
import timeit

import numpy as np

import lagrangian as lg
from lagrangian.numeric import compile_equations

BATCH = 1000


def chain_pendulum(n: int) -> lg.System:
    particles = []
    x_text, y_text = "0", "0"
    for i in range(1, n + 1):
        x_text += f" + l{i}*sin(theta{i})"
        y_text += f" - l{i}*cos(theta{i})"
        particles.append(lg.Particle(f"bob{i}", mass=f"m{i}", position=[x_text, y_text]))
    parameters = {f"m{i}": 1.0 for i in range(1, n + 1)}
    parameters |= {f"l{i}": 1.0 for i in range(1, n + 1)}
    parameters["g"] = 9.81
    return lg.System.from_particles(
        coordinates=[f"theta{i}" for i in range(1, n + 1)],
        particles=particles,
        gravity=lg.Gravity(g="g", direction=(0, -1)),
        parameters=parameters,
    )


def double_pendulum_by_hand(t, y, params):
    """The textbook double pendulum (angles from the downward vertical)."""
    m1, m2, l1, l2, g = params
    th1, th2, w1, w2 = y
    delta = th1 - th2
    s, c = np.sin(delta), np.cos(delta)
    den = 2 * m1 + m2 - m2 * np.cos(2 * delta)
    a1 = (
        -g * (2 * m1 + m2) * np.sin(th1)
        - m2 * g * np.sin(th1 - 2 * th2)
        - 2 * s * m2 * (w2**2 * l2 + w1**2 * l1 * c)
    ) / (l1 * den)
    a2 = (2 * s * (w1**2 * l1 * (m1 + m2) + g * (m1 + m2) * np.cos(th1) + w2**2 * l2 * m2 * c)) / (
        l2 * den
    )
    return np.array([w1, w2, a1, a2])


def chain_by_hand(n: int):
    """The N-link closed form, vectorised: M_ij = mu_ij l_i l_j cos(theta_i - theta_j)."""

    def rhs(t, y, params):
        m, l, g = params[:n], params[n : 2 * n], params[2 * n]
        th, w = y[:n], y[n:]
        tail = np.cumsum(m[::-1])[::-1]  # sum_{k >= i} m_k
        mu = tail[np.maximum.outer(np.arange(n), np.arange(n))]
        diff = th[:, None] - th[None, :]
        ll = np.outer(l, l)
        matrix = mu * ll * np.cos(diff)
        forcing = -(mu * ll * np.sin(diff)) @ (w**2) - tail * g * l * np.sin(th)
        return np.concatenate([w, np.linalg.solve(matrix, forcing)])

    return rhs


def chain_by_hand_numba(n: int):
    """``chain_by_hand(n)`` as a numba kernel (loops, ``np.linalg.solve``); None without numba."""
    try:
        import numba
    except ImportError:
        return None

    @numba.njit
    def rhs(t, y, params):
        m, l, g = params[:n], params[n : 2 * n], params[2 * n]
        th, w = y[:n], y[n:]
        tail = np.empty(n)
        total = 0.0
        for i in range(n - 1, -1, -1):
            total += m[i]
            tail[i] = total
        matrix = np.empty((n, n))
        forcing = np.empty(n)
        for i in range(n):
            forcing[i] = -tail[i] * g * l[i] * np.sin(th[i])
            for j in range(n):
                mu_ll = tail[max(i, j)] * l[i] * l[j]
                matrix[i, j] = mu_ll * np.cos(th[i] - th[j])
                forcing[i] -= mu_ll * np.sin(th[i] - th[j]) * w[j] ** 2
        out = np.empty(2 * n)
        out[:n] = w
        out[n:] = np.linalg.solve(matrix, forcing)
        return out

    return rhs


def numba_row(system, params, y, hand, hand_params, repeat: int, label: str) -> None:
    """µs per call of the numba backend's rhs against a hand-written numba kernel."""
    if hand is None:
        print(f"\nnumba backend, {label}: numba not installed, skipped")
        return
    start = time.perf_counter()
    compiled = compile_equations(system.equations_of_motion(), backend="numba")
    compiled.rhs(0.0, y, params)
    setup = time.perf_counter() - start
    hand(0.0, y, hand_params)  # jit before timing
    error = agreement(compiled, params, hand, hand_params, y)
    ours = microseconds(compiled.rhs, 0.0, y, params, repeat=repeat)
    reference = microseconds(hand, 0.0, y, hand_params, repeat=repeat)
    print(f"\nnumba backend, {label} (derive + generate + jit {setup:.1f} s; agree {error:.1e})")
    print(f"  hand-written numba kernel                {reference:9.2f} µs")
    print(
        f"  numba backend rhs                        {ours:9.2f} µs   ratio {ours / reference:.2f}"
    )


def microseconds(function, *args, repeat: int) -> float:
    """Median over ``repeat`` timings of µs per call."""
    timer = timeit.Timer(lambda: function(*args))
    number, _ = timer.autorange()
    return statistics.median(t / number * 1e6 for t in timer.repeat(repeat, number))


def measure(compiled, params, y, repeat) -> tuple[float, float]:
    """(µs per call for one state, µs per state in a batch of BATCH)."""
    states = np.random.default_rng(1).uniform(-1, 1, (y.size, BATCH))
    single = microseconds(compiled.rhs, 0.0, y, params, repeat=repeat)
    batch = microseconds(compiled.rhs, 0.0, states, params, repeat=repeat) / BATCH
    return single, batch


def agreement(compiled, params, reference, reference_params, y) -> float:
    return agreement_of(compiled.rhs, params, reference, reference_params, y)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, default=10)
    parser.add_argument("--repeat", type=int, default=7)
    options = parser.parse_args()
    rng = np.random.default_rng(0)
    n, repeat = options.links, options.repeat

    start = time.perf_counter()
    double = compile_equations(lg.load("double_pendulum").equations_of_motion())
    double_params = double.parameter_vector({"m1": 1.3, "m2": 0.7, "l1": 1.1, "l2": 0.9})
    double.rhs(0.0, np.zeros(4), double_params)
    print(f"double pendulum: derived and compiled in {time.perf_counter() - start:.1f} s")
    start = time.perf_counter()
    chain = compile_equations(chain_pendulum(n).equations_of_motion())
    chain_params = chain.parameter_vector()
    chain.rhs(0.0, np.zeros(2 * n), chain_params)
    print(f"{n}-link pendulum: derived and compiled in {time.perf_counter() - start:.1f} s")
    values = dict(zip(chain.parameter_names, chain_params, strict=True))
    hand_chain_params = np.array(
        [values[f"m{i}"] for i in range(1, n + 1)]
        + [values[f"l{i}"] for i in range(1, n + 1)]
        + [values["g"]]
    )
    hand_chain = chain_by_hand(n)

    y2, yn = rng.uniform(-1, 1, 4), rng.uniform(-1, 1, 2 * n)
    double_error = agreement(double, double_params, double_pendulum_by_hand, double_params, y2)
    chain_error = agreement(chain, chain_params, hand_chain, hand_chain_params, yn)
    print(
        "agreement with the hand-written rhs (max relative difference): "
        f"double {double_error:.1e}, {n}-link {chain_error:.1e}"
    )
    hand_double = microseconds(double_pendulum_by_hand, 0.0, y2, double_params, repeat=repeat)
    hand_n = microseconds(hand_chain, 0.0, yn, hand_chain_params, repeat=repeat)
    double_single, double_batch = measure(double, double_params, y2, repeat)
    chain_single, chain_batch = measure(chain, chain_params, yn, repeat)

    print(f"\nmedian of {repeat} timings, µs per rhs call (one state)")
    print(f"  hand-written NumPy, double pendulum      {hand_double:9.2f}")
    print(f"  hand-written NumPy, {n}-link closed form  {hand_n:9.2f}")
    print(
        f"  compiled, double pendulum                {double_single:9.2f}   "
        f"ratio to hand-written double: {double_single / hand_double:.2f}"
    )
    print(
        f"  compiled, {n}-link pendulum               {chain_single:9.2f}   "
        f"ratio to hand-written double: {chain_single / hand_double:.2f}, "
        f"to hand-written {n}-link: {chain_single / hand_n:.2f}"
    )
    print(f"\nbatch of {BATCH} states, µs per state")
    print(f"  compiled, double pendulum                {double_batch:9.3f}")
    print(f"  compiled, {n}-link pendulum               {chain_batch:9.3f}")
    numba_row(
        chain_pendulum(n), chain_params, yn, chain_by_hand_numba(n), hand_chain_params, repeat,
        f"{n}-link pendulum",
    )  # fmt: skip
    pydy_row(chain_pendulum(n), chain_params, yn, hand_chain_params, n, repeat)


def pydy_row(system, params, y, pydy_params, n: int, repeat: int) -> None:
    """µs per call of PyDy's Cython rhs against our numba backend (when both are installed)."""
    from pydy_chain import chain_by_pydy

    pydy_rhs, seconds = chain_by_pydy(n)
    if pydy_rhs is None:
        print("\nPyDy: not installed, skipped (pip install pydy cython)")
        return
    error = agreement_of(pydy_rhs, pydy_params, chain_by_hand(n), pydy_params, y)
    peer = microseconds(pydy_rhs, 0.0, y, pydy_params, repeat=repeat)
    print(
        f"\nPyDy Cython, {n}-link pendulum "
        f"(KanesMethod + codegen {seconds:.1f} s; agree {error:.1e})"
    )
    print(f"  PyDy Cython rhs                          {peer:9.2f} µs")
    try:
        compiled = compile_equations(system.equations_of_motion(), backend="numba")
    except Exception as error:  # numba missing
        print(f"  numba backend: {error}")
        return
    compiled.rhs(0.0, y, params)
    ours = microseconds(compiled.rhs, 0.0, y, params, repeat=repeat)
    print(f"  numba backend rhs                        {ours:9.2f} µs   ratio {ours / peer:.2f}")


def agreement_of(function, params, reference, reference_params, y) -> float:
    expected = reference(0.0, y, reference_params)
    got = function(0.0, y, params)
    return float(np.max(np.abs(got - expected)) / np.max(np.abs(expected)))


if __name__ == "__main__":
    main()

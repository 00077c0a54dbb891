"""rk4 of constrained systems in numba, each state projected after every step: the loop
of the numba ensemble's members and of a single rk4 run.

Written into the code cache as it is (:func:`lagrangian.integrate.compiled_loop.
projected_module`), where ``@njit(cache=True)`` keeps its machine code: compiled once on a
machine for every constrained system.  A system's functions come in as the pointers of the
compiled DOP853 loop (:mod:`lagrangian.integrate.numba_dop853`, ``projected_y_prime``): its
generated ``derivative`` (the augmented system [[M, -A^T], [A, 0]] [q''; lambda] = [f; b]
with Baumgarte's b, solved for n + m unknowns) and ``project`` (positions by Gauss-Newton
in the mass metric, velocities exactly: :mod:`lagrangian.integrate.numba_derivative`).

    run(y_prime, size, y0, params, grid, a, b, c, track, stop, save_every, final, flips,
        paths)

steps each member (one per ``prange`` iteration, its own workspace for a solve of
``size``) along ``grid`` with the explicit Runge-Kutta tableau (a, b, c) as the numpy
backend's rk4 takes it (:class:`lagrangian.integrate.explicit_rk.AbstractExplicitRungeKutta`:
the same sums in the same order), then projects the state, as the Python loops project
each step (``compiled.project``).  ``track``/``stop``/``save_every``, ``final``, ``flips``
and ``paths`` are those of the unconstrained loop (:mod:`lagrangian.codegen.numba_stepping`);
a single run is one member whose every step is saved (:class:`~lagrangian.integrate.
compiled_loop.ProjectedLoop`).  This module itself is never run.
"""

import math

import numpy as np
from numba import njit, prange

#: A coordinate beyond this angle has flipped (the flip_time observable).
LIMIT = math.pi


@njit(cache=True)
def workspace(size):  # pragma: no cover - compiled by numba
    """The arrays a constrained system's ``derivative`` and ``project`` work in (the
    workspace type of :mod:`lagrangian.integrate.numba_dop853`, no link)."""
    return (
        np.empty((size, size)), np.empty(size), np.empty((0, 0)), np.empty(0), np.empty(0),
        np.empty(0, dtype=np.int64),
    )  # fmt: skip


@njit(cache=True)
def flipped(y, n):  # pragma: no cover - compiled by numba
    largest = 0.0
    for i in range(n):
        largest = max(largest, abs(y[i]))
    return largest > LIMIT


@njit(parallel=True, cache=True)
def run(
    y_prime, size, y0, params, grid, a, b, c, track, stop, save_every, final, flips, paths
):  # pragma: no cover - compiled by numba  # fmt: skip
    derivative, project = y_prime[0], y_prime[1]
    count, m = y0.shape
    n = m // 2
    stages = b.shape[0]
    steps = grid.shape[0] - 1
    for member in prange(count):
        y = y0[member].copy()
        p = params[member]
        work = workspace(size)
        slopes = np.empty((stages, m))
        stage = np.empty(m)
        flags = np.zeros(1, dtype=np.int64)
        flip = np.nan
        if track and flipped(y, n):
            flip = grid[0]
        if save_every > 0:
            for i in range(m):
                paths[member, i, 0] = y[i]
        if not (stop and flip == flip):
            for s in range(steps):
                t, h = grid[s], grid[s + 1] - grid[s]
                for k in range(stages):
                    for i in range(m):
                        stage[i] = y[i]
                    for j in range(k):
                        if a[k, j] != 0.0:
                            for i in range(m):
                                stage[i] = stage[i] + (h * a[k, j]) * slopes[j, i]
                    derivative(t + c[k] * h, stage, p, work, slopes[k], flags)
                for i in range(m):
                    increment = 0.0
                    for k in range(stages):
                        if b[k] != 0.0:
                            increment += b[k] * slopes[k, i]
                    y[i] = y[i] + h * increment
                project(grid[s + 1], y, p, work, y, flags)
                if save_every > 0 and (s + 1) % save_every == 0:
                    for i in range(m):
                        paths[member, i, (s + 1) // save_every] = y[i]
                if track and flip != flip and flipped(y, n):
                    flip = grid[s + 1]
                    if stop:
                        break
        flips[member] = flip
        for i in range(m):
            final[member, i] = y[i]

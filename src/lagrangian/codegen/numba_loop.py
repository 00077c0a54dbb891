"""The compiled fixed-step loops of the numba target, as the text of a generated module.

numba caches compiled code on disk only for functions defined at the top of a
real module file, not for closures; so the loops live here as module-level
functions over a few globals, and :func:`lagrangian.codegen.loops.numba_loop`
writes, per system and scheme, a copy of this text into the code cache with the
globals filled in (the block between the ``generated`` markers) and the scheme's
functions in place of the placeholder between the ``scheme`` markers.  There
``@njit(cache=True)`` keeps the machine code, so a second process starts the
loop without compiling it.

The globals: ``N`` (coordinates), ``W`` (the entries of a displacement carried with the
state: 2N for the scheme ``rk4-tangent``, else 0) and the generated fillers of the
scheme's expressions (:mod:`lagrangian.codegen.schemes`: ``mass_force`` for
rk4; ``momenta``, ``momenta_force``, ``mass``, ``jacobian`` for midpoint;
``mass`` and ``gradient`` for Stormer-Verlet; ``mass_force`` and ``tangent`` for
rk4-tangent).  With a displacement w, ``run`` renormalises it after every step and
gives each member's largest Lyapunov exponent, the mean of log |w| per unit time (the
numpy backend's ``lyapunov`` observable, :mod:`lagrangian.ensemble.numpy_backend`).
The scheme, for one member's state, is printed from :mod:`lagrangian.codegen.steps`
(the same program the CUDA kernel prints as C):

    workspace()                       the arrays the scheme keeps and works in
    init(t, y, p, work, counts)       the scheme's state at the first step
    step(t, h, y, p, work, tol, floor, iterations, counts) -> int
                                      y (2n,) advanced by h in place; 0, or
                                      not 0 when a Newton iteration did not converge;
                                      counts (3 integers): evaluations of the
                                      right-hand side (or L_q', L_q + Q), of the
                                      Jacobians, and Newton updates

Two loops call it: ``run``, the ensemble's (one member per ``prange`` iteration),
and ``advance``, a stretch of steps of one single run, every state kept.
Linear solves are the printed ``eliminate`` (:func:`lagrangian.codegen.steps.elimination`)
for a constant n.  This module itself is never run.
"""

import math

import numpy as np
from numba import njit, prange

# -- generated: begin (each generated module has its own values here) ----------------
N = 1
W = 0
mass_force = momenta = momenta_force = mass = jacobian = gradient = tangent = None
# -- generated: end ------------------------------------------------------------------

M = 2 * N
LIMIT = math.pi


# -- scheme: begin (each generated module has its scheme, printed by codegen.steps) -------
@njit(cache=True)
def rk4_workspace():  # pragma: no cover - compiled by numba
    return ()


@njit(cache=True)
def rk4_init(t, y, p, work, counts):  # pragma: no cover - compiled by numba
    pass


@njit(cache=True, _nrt=False)
def rk4_step(t, h, y, p, work, tol, floor, iterations, counts):  # pragma: no cover
    return 0


# -- scheme: end ---------------------------------------------------------------------


# -- the loop over members -----------------------------------------------------------
@njit(parallel=True, cache=True)
def run(
    y0, params, grid, track, stop, save_every, tol, floor, iterations,
    final, flips, failures, paths, exponents,
):  # pragma: no cover - compiled by numba  # fmt: skip
    count, m = y0.shape
    steps = grid.shape[0] - 1
    for b in prange(count):
        y = np.empty(m + W)
        for i in range(m):
            y[i] = y0[b, i]
        for i in range(W):
            y[m + i] = 1.0 / math.sqrt(W)
        stretch = 0.0
        p = params[b]
        work = workspace()
        counts = np.zeros(3, dtype=np.int64)
        flip = np.nan
        failure = -1
        if track:
            for i in range(N):
                if abs(y[i]) > LIMIT:
                    flip = grid[0]
        if save_every > 0:
            for i in range(m):
                paths[b, i, 0] = y[i]
        if not (stop and flip == flip):
            init(grid[0], y, p, work, counts)
            for s in range(steps):
                ta = grid[s]
                if step(ta, grid[s + 1] - ta, y, p, work, tol, floor, iterations, counts) != 0:
                    failure = s
                    break
                if W > 0:
                    norm = 0.0
                    for i in range(W):
                        norm += y[m + i] * y[m + i]
                    norm = math.sqrt(norm)
                    stretch += math.log(norm)
                    for i in range(W):
                        y[m + i] /= norm
                if save_every > 0 and (s + 1) % save_every == 0:
                    for i in range(m):
                        paths[b, i, (s + 1) // save_every] = y[i]
                if track and flip != flip:
                    for i in range(N):
                        if abs(y[i]) > LIMIT:
                            flip = grid[s + 1]
                    if stop and flip == flip:
                        break
        flips[b] = flip
        failures[b] = failure
        exponents[b] = stretch / (grid[steps] - grid[0]) if W > 0 else math.nan
        for i in range(m):
            final[b, i] = y[i]


# -- a stretch of one single run ----------------------------------------------------
@njit(cache=True)
def advance(
    y, p, work, grid, start, stop, tol, floor, iterations, states, counts
):  # pragma: no cover - compiled by numba  # fmt: skip
    """Steps start, ..., stop - 1 of ``grid`` from y (advanced in place), the state after
    step s into ``states[s + 1]``.  Returns (the step reached, 0), or (the step that
    failed, its code: 1 or 2 from the scheme's Newton iterations, 3 for a state that is
    not finite)."""
    for s in range(start, stop):
        ta = grid[s]
        failed = step(ta, grid[s + 1] - ta, y, p, work, tol, floor, iterations, counts)
        if failed != 0:
            return s, failed
        for i in range(M):
            value = y[i]
            if value - value != 0:  # inf or NaN
                return s, 3
            states[s + 1, i] = value
    return stop, 0


# -- the scheme (each generated module selects its own) --------------------------------
workspace, init, step = rk4_workspace, rk4_init, rk4_step

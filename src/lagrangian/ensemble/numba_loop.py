"""The numba ensemble loop, as the text of a generated module (a template).

numba caches compiled code on disk only for functions defined at the top of a
real module file, not for closures; so the loop lives here as a module-level
function over a few globals, and :func:`lagrangian.ensemble.numba_backend.kernel`
writes, per system and scheme, a copy of this text into the code cache with the
globals filled in (the block between the ``generated`` markers) and the scheme's
functions in place of the placeholder between the ``scheme`` markers.  There
``@njit(cache=True)`` keeps the machine code, so a second process starts the
loop without compiling it.

The globals: ``N`` (coordinates) and the generated fillers of the scheme's
expressions (:mod:`lagrangian.codegen.schemes`: ``mass_force`` for
rk4; ``momenta``, ``momenta_force``, ``mass``, ``jacobian`` for midpoint;
``mass`` and ``gradient`` for Stormer-Verlet).  The scheme, for one member's
state, is printed from :mod:`lagrangian.codegen.steps` (the same program the
CUDA kernel prints as C):

    workspace()                       the arrays the scheme keeps and works in
    init(t, y, p, work)               the scheme's state at the first step
    step(t, h, y, p, work, tol, floor, iterations) -> int
                                      y (2n,) advanced by h in place; 0, or
                                      not 0 when a Newton iteration did not converge

Linear solves are :func:`lagrangian.numeric.numba_linalg.eliminate` with n a
constant, so that they unroll.  This module itself is never run.
"""

import math

import numpy as np
from numba import njit, prange

from lagrangian.numeric.numba_linalg import eliminate  # noqa: F401 - the schemes call it

# -- generated: begin (each generated module has its own values here) ----------------
N = 1
mass_force = momenta = momenta_force = mass = jacobian = gradient = None
# -- generated: end ------------------------------------------------------------------

M = 2 * N
LIMIT = math.pi


# -- scheme: begin (each generated module has its scheme, printed by codegen.steps) -------
@njit(cache=True)
def rk4_workspace():  # pragma: no cover - compiled by numba
    return ()


@njit(cache=True)
def rk4_init(t, y, p, work):  # pragma: no cover - compiled by numba
    pass


@njit(inline="always", cache=True)
def rk4_step(t, h, y, p, work, tol, floor, iterations):  # pragma: no cover - compiled by numba
    return 0


# -- scheme: end ---------------------------------------------------------------------


# -- the loop over members -----------------------------------------------------------
@njit(parallel=True, cache=True)
def run(
    y0, params, grid, track, stop, save_every, tol, floor, iterations,
    final, flips, failures, paths,
):  # pragma: no cover - compiled by numba  # fmt: skip
    count, m = y0.shape
    steps = grid.shape[0] - 1
    for b in prange(count):
        y = y0[b].copy()
        p = params[b]
        work = workspace()
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
            init(grid[0], y, p, work)
            for s in range(steps):
                ta = grid[s]
                if step(ta, grid[s + 1] - ta, y, p, work, tol, floor, iterations) != 0:
                    failure = s
                    break
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
        for i in range(m):
            final[b, i] = y[i]


# -- the scheme (each generated module selects its own) --------------------------------
workspace, init, step = rk4_workspace, rk4_init, rk4_step

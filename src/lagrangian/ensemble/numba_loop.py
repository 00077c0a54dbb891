"""The numba ensemble loop, as the text of a generated module (a template).

numba caches compiled code on disk only for functions defined at the top of a
real module file, not for closures; so the loop and the three schemes live
here as module-level functions over a few globals, and
:func:`lagrangian.ensemble.numba_backend.kernel` writes, per system and
scheme, a copy of this text with the globals filled in (the block between the
``generated`` markers and the ``scheme`` line) into the code cache.  There
``@njit(cache=True)`` keeps the machine code, so a second process starts the
loop without compiling it.

The globals: ``N`` (coordinates), ``STALL_RATIO`` (of the Newton test), the
generated fillers of the scheme's expressions (:mod:`lagrangian.numeric.scheme_expressions`:
``fill`` for rk4; ``momenta``, ``momenta_force``, ``mass``, ``jacobian`` for
midpoint; ``mass`` and
``gradient`` for Stormer-Verlet) and the RK4 tableau.  The schemes are the
numpy backend's step for step, written for one member's state:

    workspace()                       the arrays the scheme keeps and works in
    init(t, y, p, work)               the scheme's state at the first step
    step(t, h, y, p, work, tol, floor, iterations) -> bool
                                      y (2n,) advanced by h in place; False
                                      when a Newton iteration did not converge

``rk4`` (the tableau of :mod:`lagrangian.integrate.tableaus`, M q'' = f solved
at each stage) and the two of :class:`~lagrangian.integrate.variational.Variational`,
``midpoint`` (Newton on the midpoint velocity, first guess, convergence test
and the velocity from the momenta as there) and ``stormer-verlet``.  Linear
solves are Gaussian elimination with partial pivoting, unrolled for N
(:func:`lagrangian.numeric.numba_linalg.eliminate`), so results equal
numpy's LAPACK solves to rounding.  This module itself is never run.
"""

import math

import numpy as np
from numba import njit, prange

from lagrangian.numeric.numba_linalg import eliminate

# -- generated: begin (each generated module has its own values here) ----------------
N = 1
STALL_RATIO = 0.5
A21 = A32 = A43 = B1 = B2 = B3 = B4 = C2 = C3 = C4 = 0.0
fill = momenta = momenta_force = mass = jacobian = gradient = None
# -- generated: end ------------------------------------------------------------------

M = 2 * N
LIMIT = math.pi


@njit(inline="always", cache=True)
def solve(matrix, force, out, offset):  # pragma: no cover - compiled by numba
    eliminate(matrix, force, out, offset, N)


@njit(inline="always", cache=True)
def larger(a, b):  # pragma: no cover - compiled by numba
    """max(a, b) that keeps a NaN, as numpy's max does, so a NaN never converges."""
    return b if b > a or b != b else a


@njit(inline="always", cache=True)
def converged(size, previous, scale, reach, tol, floor):  # pragma: no cover - compiled by numba
    """variational._converged for one member: small, or stuck at the rounding floor."""
    small = size <= tol * scale or size == 0.0
    return small or (size >= STALL_RATIO * previous and size <= floor * scale * reach)


@njit(inline="always", cache=True)
def extent(y):  # pragma: no cover - compiled by numba
    """variational._extent for one member: max(1, max |q|)."""
    size = 1.0
    for i in range(N):
        size = larger(size, abs(y[i]))
    return size


# -- rk4 -------------------------------------------------------------------------------
@njit(cache=True)
def rk4_workspace():  # pragma: no cover - compiled by numba
    k = (np.empty(M), np.empty(M), np.empty(M), np.empty(M), np.empty(M))
    return (*k, np.empty((N, N)), np.empty(N))


@njit(inline="always", cache=True)
def derivative(t, y, p, matrix, force, out):  # pragma: no cover - compiled by numba
    fill(t, y, p, matrix, force)
    solve(matrix, force, out, N)
    for i in range(N):
        out[i] = y[N + i]


@njit(cache=True)
def rk4_init(t, y, p, work):  # pragma: no cover - compiled by numba
    pass


@njit(inline="always", cache=True)
def rk4_step(t, h, y, p, work, tol, floor, iterations):  # pragma: no cover - compiled by numba
    k1, k2, k3, k4, stage, matrix, force = work
    derivative(t, y, p, matrix, force, k1)
    for i in range(M):
        stage[i] = y[i] + (h * A21) * k1[i]
    derivative(t + C2 * h, stage, p, matrix, force, k2)
    for i in range(M):
        stage[i] = y[i] + (h * A32) * k2[i]
    derivative(t + C3 * h, stage, p, matrix, force, k3)
    for i in range(M):
        stage[i] = y[i] + (h * A43) * k3[i]
    derivative(t + C4 * h, stage, p, matrix, force, k4)
    for i in range(M):
        y[i] = y[i] + h * (B1 * k1[i] + B2 * k2[i] + B3 * k3[i] + B4 * k4[i])
    return True


# -- midpoint (variational) --------------------------------------------------------
@njit(cache=True)
def midpoint_workspace():  # pragma: no cover - compiled by numba
    # kept: p_k, the last midpoint velocity, whether there is one; then scratch
    kept = (np.empty(N), np.empty(N), np.zeros(1, dtype=np.bool_))
    scratch = (np.empty(N), np.empty(2 * N), np.empty(N), np.empty(N), np.empty(N))
    return (*kept, *scratch, np.empty(N), np.empty((N, N)))


@njit(cache=True)
def midpoint_init(t, y, p, work):  # pragma: no cover - compiled by numba
    momenta(t, y, p, work[0])
    work[2][0] = False


@njit(inline="always", cache=True)
def midpoint_step(t, h, y, p, work, tol, floor, iterations):  # pragma: no cover - compiled by numba
    kept, last, started, v, z, momenta_now, force, residual, change, matrix = work
    tm = t + h / 2
    for i in range(N):
        v[i] = 2 * y[N + i] - last[i] if started[0] else y[N + i]  # O(h^2) first guess
    previous = np.inf
    reach = extent(y)
    for iteration in range(iterations + 1):
        for i in range(N):
            z[i] = y[i] + (h / 2) * v[i]
            z[N + i] = v[i]
        momenta_force(tm, z, p, momenta_now, force)
        size = scale = 0.0
        for i in range(N):
            residual[i] = momenta_now[i] - (h / 2) * force[i] - kept[i]
            size = larger(size, abs(residual[i]))
            scale = larger(scale, larger(abs(kept[i]), abs(momenta_now[i])))
        if converged(size, previous, scale, reach, tol, floor):
            break
        if iteration == iterations:
            return False
        previous = size
        jacobian(tm, z, p, h, matrix)
        solve(matrix, residual, change, 0)
        for i in range(N):
            v[i] -= change[i]
    for i in range(N):
        kept[i] = kept[i] + h * force[i]
        y[i] = y[i] + h * v[i]
        last[i] = v[i]
        z[i] = y[i]
        z[N + i] = v[i]
    started[0] = True
    # the velocity from the momenta: L_q'(q, q') = p_{k+1} by Newton with M, from v
    previous = np.inf
    reach = extent(y)
    for iteration in range(iterations + 1):
        momenta(t + h, z, p, momenta_now)
        size = scale = 0.0
        for i in range(N):
            residual[i] = momenta_now[i] - kept[i]
            size = larger(size, abs(residual[i]))
            scale = larger(scale, larger(abs(kept[i]), abs(momenta_now[i])))
        if converged(size, previous, scale, reach, tol, floor):
            for i in range(N):
                y[N + i] = z[N + i]
            return True
        if iteration == iterations:
            return False
        previous = size
        mass(t + h, z, p, matrix)
        solve(matrix, residual, change, 0)
        for i in range(N):
            z[N + i] -= change[i]
    return False


# -- Stormer-Verlet (variational, separable systems) -------------------------------
@njit(inline="always", cache=True)
def apply(matrix, x, out):  # pragma: no cover - compiled by numba
    for i in range(N):
        total = 0.0
        for j in range(N):
            total += matrix[i, j] * x[j]
        out[i] = total


@njit(cache=True)
def verlet_workspace():  # pragma: no cover - compiled by numba
    # kept: p_k, L_q(q_k), M^-1; then scratch
    kept = (np.empty(N), np.empty(N), np.empty((N, N)))
    return (*kept, np.empty(N), np.empty(2 * N), np.empty((N, N)), np.empty((N, N)))


@njit(cache=True)
def verlet_init(t, y, p, work):  # pragma: no cover - compiled by numba
    kept, force, inverse, unit, z, matrix, copy = work
    mass(t, y, p, matrix)
    for j in range(N):  # the inverse column by column
        for i in range(N):
            unit[i] = 1.0 if i == j else 0.0
            for k in range(N):
                copy[i, k] = matrix[i, k]
        solve(copy, unit, z, 0)
        for i in range(N):
            inverse[i, j] = z[i]
    apply(matrix, y[N:], kept)
    gradient(t, y, p, force)


@njit(inline="always", cache=True)
def verlet_step(t, h, y, p, work, tol, floor, iterations):  # pragma: no cover - compiled by numba
    kept, force, inverse, half, z, _, _ = work
    for i in range(N):
        half[i] = kept[i] + (h / 2) * force[i]
    apply(inverse, half, z[N:])
    for i in range(N):
        z[i] = y[i] + h * z[N + i]
    gradient(t + h, z, p, force)
    for i in range(N):
        kept[i] = half[i] + (h / 2) * force[i]
        y[i] = z[i]
    apply(inverse, kept, y[N:])
    return True


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
                if not step(ta, grid[s + 1] - ta, y, p, work, tol, floor, iterations):
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

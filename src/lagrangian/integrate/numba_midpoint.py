"""The midpoint variational step of one state in numba, as the text of a generated module.

numba keeps machine code on disk only for functions at the top of a real module
file, so :func:`lagrangian.integrate.midpoint_step.midpoint_functions` writes, per
system, a copy of this text with the globals between the ``generated`` markers
filled in (N, the Newton test's STALL_RATIO, and the import of the system's
generated fillers: ``momenta_force``, ``jacobian``, ``momenta``, ``mass``) into the
code cache, where ``@njit(cache=True)`` keeps the compiled step.

    step(t, h, y, p, kept, last, started, tol, floor, iterations, y_out, kept_out, last_out,
         counts)

takes the step of ``Variational._midpoint`` (first guess, Newton on the midpoint
velocity with its convergence test, then the velocity from the momenta by Newton
with M) for one state: y (2N,) at t with momenta ``kept`` and the last midpoint
velocity ``last`` (used when ``started``), into the three output arrays.  It
returns 0, or 1 / 2 where the Newton iteration for the midpoint velocity / for the
velocity did not converge; ``counts`` (3 integers) gets the evaluations of the
momenta, of the Jacobians (J and M) and the Newton updates of the midpoint
velocity.  Solves are Gaussian elimination with partial pivoting
(:func:`lagrangian.numeric.numba_linalg.eliminate`).  This module itself is never run.
"""

import numpy as np
from numba import njit

from lagrangian.numeric.numba_linalg import eliminate

# -- generated: begin (each generated module has its own values here) ----------------
N = 1
STALL_RATIO = 0.5
momenta = momenta_force = mass = jacobian = None
# -- generated: end ------------------------------------------------------------------


@njit(inline="always", cache=True)
def larger(a, b):  # pragma: no cover - compiled by numba
    """max(a, b) that keeps a NaN, as numpy's max does, so a NaN never converges."""
    return b if b > a or b != b else a


@njit(inline="always", cache=True)
def converged(size, previous, scale, reach, tol, floor):  # pragma: no cover - compiled by numba
    small = size <= tol * scale or size == 0.0
    return small or (size >= STALL_RATIO * previous and size <= floor * scale * reach)


@njit(cache=True)
def step(
    t, h, y, p, kept, last, started, tol, floor, iterations, y_out, kept_out, last_out, counts
):  # pragma: no cover - compiled by numba
    v = np.empty(N)
    z = np.empty(2 * N)
    momenta_now = np.empty(N)
    force = np.empty(N)
    residual = np.empty(N)
    change = np.empty(N)
    matrix = np.empty((N, N))
    tm = t + h / 2
    reach = 1.0
    for i in range(N):
        v[i] = 2 * y[N + i] - last[i] if started else y[N + i]  # O(h^2) first guess
        reach = larger(reach, abs(y[i]))
    previous = np.inf
    for iteration in range(iterations + 1):
        for i in range(N):
            z[i] = y[i] + (h / 2) * v[i]
            z[N + i] = v[i]
        momenta_force(tm, z, p, momenta_now, force)
        counts[0] += 1
        size = scale = 0.0
        for i in range(N):
            residual[i] = momenta_now[i] - (h / 2) * force[i] - kept[i]
            size = larger(size, abs(residual[i]))
            scale = larger(scale, larger(abs(kept[i]), abs(momenta_now[i])))
        if converged(size, previous, scale, reach, tol, floor):
            break
        if iteration == iterations:
            return 1
        previous = size
        jacobian(tm, z, p, h, matrix)
        counts[1] += 1
        counts[2] += 1
        eliminate(matrix, residual, change, 0, N)
        for i in range(N):
            v[i] -= change[i]
    reach = 1.0
    for i in range(N):
        kept_out[i] = kept[i] + h * force[i]
        y_out[i] = y[i] + h * v[i]
        last_out[i] = v[i]
        z[i] = y_out[i]
        z[N + i] = v[i]
        reach = larger(reach, abs(y_out[i]))
    previous = np.inf
    for iteration in range(iterations + 1):
        momenta(t + h, z, p, momenta_now)
        counts[0] += 1
        size = scale = 0.0
        for i in range(N):
            residual[i] = momenta_now[i] - kept_out[i]
            size = larger(size, abs(residual[i]))
            scale = larger(scale, larger(abs(kept_out[i]), abs(momenta_now[i])))
        if converged(size, previous, scale, reach, tol, floor):
            for i in range(N):
                y_out[N + i] = z[N + i]
            return 0
        if iteration == iterations:
            return 2
        previous = size
        mass(t + h, z, p, matrix)
        counts[1] += 1
        eliminate(matrix, residual, change, 0, N)
        for i in range(N):
            z[N + i] -= change[i]
    return 2

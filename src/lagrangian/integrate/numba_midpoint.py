"""The midpoint variational step of one state in numba, as the text of a generated module.

numba keeps machine code on disk only for functions at the top of a real module
file, so :func:`lagrangian.integrate.midpoint_step.midpoint_functions` writes, per
system, a copy of this text into the code cache with the globals between the
``generated`` markers filled in (N and the import of the system's generated
fillers: ``momenta_force``, ``jacobian``, ``momenta``, ``mass``) and, between the
``scheme`` markers, the midpoint step printed from :mod:`lagrangian.codegen.steps`
(the one the numba ensemble loop and the CUDA kernel print), where
``@njit(cache=True)`` keeps the compiled step.

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

import math  # noqa: F401 - the printed step uses math.inf

import numpy as np
from numba import njit

from lagrangian.numeric.numba_linalg import eliminate  # noqa: F401 - the step calls it

# -- generated: begin (each generated module has its own values here) ----------------
N = 1
momenta = momenta_force = mass = jacobian = None
# -- generated: end ------------------------------------------------------------------


# -- scheme: begin (the midpoint step printed by codegen.steps, counting evaluations) ------
@njit(cache=True)
def midpoint_workspace():  # pragma: no cover - compiled by numba
    return (np.empty(N), np.empty(N), np.empty(1))


@njit(inline="always", cache=True)
def midpoint_step(t, h, y, p, work, tol, floor, iterations, counts):  # pragma: no cover
    return 0


# -- scheme: end ---------------------------------------------------------------------


@njit(cache=True)
def step(
    t, h, y, p, kept, last, started, tol, floor, iterations, y_out, kept_out, last_out, counts
):  # pragma: no cover - compiled by numba
    work = midpoint_workspace()
    momenta_kept, velocity, begun = work[0], work[1], work[2]
    for i in range(N):
        momenta_kept[i] = kept[i]
        velocity[i] = last[i]
    begun[0] = 1.0 if started else 0.0
    for i in range(2 * N):
        y_out[i] = y[i]
    failed = midpoint_step(t, h, y_out, p, work, tol, floor, iterations, counts)
    for i in range(N):
        kept_out[i] = momenta_kept[i]
        last_out[i] = velocity[i]
    return failed

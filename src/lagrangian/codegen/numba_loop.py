"""One system's fixed-step scheme for the numba target, as the text of a generated module.

numba caches compiled code on disk only for functions defined at the top of a
real module file, not for closures; so :func:`lagrangian.codegen.loops.numba_loop`
writes, per system and scheme, a copy of this text into the code cache with the
globals filled in (the block between the ``generated`` markers) and the scheme's
functions in place of the placeholder between the ``scheme`` markers.  There
``@njit(cache=True)`` keeps the machine code, so a second process starts without
compiling it.  The loops that take the steps (:mod:`.numba_stepping`) are compiled
once for every system of a scheme and call these functions through pointers.

The globals: the generated fillers of the scheme's expressions
(:mod:`lagrangian.codegen.schemes`: ``mass_force`` for rk4; ``momenta``,
``momenta_force``, ``mass``, ``jacobian`` for midpoint; ``mass`` and ``gradient`` for
Stormer-Verlet; ``mass_force`` and ``tangent`` for rk4-tangent).  The scheme, for one
member's state, is printed from :mod:`lagrangian.codegen.steps` (the same program the
CUDA kernel prints as C):

    init(t, y, p, work, counts)       the scheme's state at the first step
    step(t, h, y, p, work, tol, floor, iterations, counts) -> int
                                      y (2n,) advanced by h in place; 0, or
                                      not 0 when a Newton iteration did not converge;
                                      counts (3 integers): evaluations of the
                                      right-hand side (or L_q', L_q + Q), of the
                                      Jacobians, and Newton updates

Two loops call it (:mod:`.numba_stepping`): ``run``, the ensemble's (one member per
``prange`` iteration), and ``advance``, a stretch of steps of one single run, every
state kept.
Linear solves are the printed ``eliminate`` for a constant n (imported from the module
of :func:`lagrangian.codegen.numba.linear_module`, one per n).  This module itself is
never run.
"""

import math  # noqa: F401 - the printed steps call it

import numpy as np  # noqa: F401 - the printed workspaces allocate with it
from numba import njit

# -- generated: begin (each generated module has its own values here) ----------------
mass_force = momenta = momenta_force = mass = jacobian = gradient = tangent = None
# -- generated: end ------------------------------------------------------------------


# -- scheme: begin (each generated module has its scheme, printed by codegen.steps) -------
@njit(cache=True)
def rk4_init(t, y, p, work, counts):  # pragma: no cover - compiled by numba
    pass


@njit(cache=True, _nrt=False)
def rk4_step(t, h, y, p, work, tol, floor, iterations, counts):  # pragma: no cover
    return 0


# -- scheme: end ---------------------------------------------------------------------


# -- the scheme (each generated module selects its own) --------------------------------
init, step = rk4_init, rk4_step

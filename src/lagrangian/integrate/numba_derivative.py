"""One system's y' for the compiled DOP853 method, as the text of a generated module.

:mod:`lagrangian.integrate.compiled_dop853` writes, per system, a copy of this text into
the code cache with the globals between the ``generated`` markers filled in (N, TANGENT,
PARAMETERS and the imports of the system's generated ``fill`` of M and f, the printed
``eliminate`` and, with TANGENT, its ``jacobian``, from :mod:`lagrangian.codegen.numba`;
:mod:`.compiled_sensitivity` fills it in for the sensitivities), where
``@njit(cache=True)`` keeps the compiled code.  The method itself
(:mod:`.numba_dop853`) is compiled once for every system and takes ``derivative`` as an
argument (a function pointer):

    derivative(t, y, p, work, out, flags)
        out = y' at (t, y), with the arrays ``work`` of the method's ``workspace(N,
        TANGENT)``; flags[0] = 1 where it is not finite

The vector has any length: with ``TANGENT`` it is the state followed by K columns S (2N x
K, row by row) of the forward sensitivity equations S' = J S + [dF/dp | 0]
(:mod:`lagrangian.integrate.sensitivity`), the first PARAMETERS of them to parameters and
the others to initial values.  The generated ``jacobian`` gives G = d(f - M a)/d(q, q', p)
at a = q'' (N x (2N + PARAMETERS), row by row); the lower rows of each column of S' are
M^-1 (G_y s + G_p e_j), solved column by column: no solved accelerations are
differentiated.  With no parameters (PARAMETERS = 0) these are the variational equations
W' = J W of the displacements W (:mod:`lagrangian.integrate.lyapunov`).  With parameters
the method's workspace is made for a size whose arrays hold the larger G
(:func:`.compiled_sensitivity.workspace_size`): every loop here indexes by N.

With constraints (``SOLVED`` = N + the constraints) ``fill`` is the generated
``augmented`` of :mod:`lagrangian.codegen.numba_constrained`: M and f bordered by the
constraint rows, solved for [q''; lambda] in ``work``'s own arrays (of size SOLVED), and

    project(t, y, p, work, out, flags)
        out = y moved onto the constraint manifold (out may be y): Gauss-Newton steps on
        the positions in the mass metric (the generated ``positions``) until a step is
        below STEP_TOLERANCE (relative to 1 + |q|) or after PROJECTION_STEPS, then the
        velocities exactly (``velocities``), as
        :meth:`lagrangian.numeric.projection.ConstraintFunctions.project`

which the method calls after every accepted step.  This module itself is never run.
"""

import math

from numba import njit

# -- generated: begin (each generated module has its own values here) ----------------
N = 1
SOLVED = 1  # unknowns of the linear solve: N, or N + the constraints (q'' and lambda)
TANGENT = False  # whether the vector integrated carries sensitivities after the state
PARAMETERS = 0  # the columns of S (the first ones) that are parameters (tangent only)
fill = eliminate = jacobian = None  # the system's M and f, the printed solve, G (tangent)
positions = velocities = None  # the projection's systems (constraints only)
HOLONOMIC = False  # whether a constraint has a position level
PROJECTION_STEPS, STEP_TOLERANCE = 50, 1e-13  # the Gauss-Newton steps on the positions
# -- generated: end ------------------------------------------------------------------


# What allocates nothing is compiled lean: not inlined, no reference counts (LEAN of
# lagrangian.codegen.steps, which says why).
@njit(cache=True, _nrt=False)
def derivative(t, y, p, work, out, flags):  # pragma: no cover - compiled by numba
    """out = y' = [q', q''] at (t, y), then S' with TANGENT; flags[0] = 1 where it is not
    finite."""
    mass, force, copy = work[0], work[1], work[2]
    fill(t, y, p, mass, force)
    for i in range(N):
        out[i] = y[N + i]
    if SOLVED > N:  # [q''; lambda] of the augmented system, in place
        eliminate(mass, force, force, 0)
        for i in range(N):
            out[N + i] = force[i]
    else:
        if TANGENT:
            for i in range(N):
                for j in range(N):
                    copy[i, j] = mass[i, j]
        eliminate(mass, force, out, N)
    if TANGENT and y.shape[0] > 2 * N:
        tangent(t, y, p, work, out)
    for i in range(y.shape[0]):
        if not math.isfinite(out[i]):
            flags[0] = 1


@njit(cache=True, _nrt=False)
def tangent(t, y, p, work, out):  # pragma: no cover - compiled by numba
    """out[2N:] = S' = J S + [dF/dp | 0] for S = y[2N:] (2N x K, row by row), with
    J = [[0, I], [M^-1 G_y]] and G = d(f - M a)/d(q, q', p) at a = q'' = out[N:2N]."""
    mass, copy, gradient, column = work[0], work[2], work[3], work[4]
    size = 2 * N
    width = size + PARAMETERS
    count = (y.shape[0] - size) // size
    jacobian(t, y, p, out[N:size], gradient)
    for j in range(count):
        for i in range(N):
            out[size + i * count + j] = y[size + (N + i) * count + j]
            total = gradient[i * width + size + j] if j < PARAMETERS else 0.0
            for k in range(size):
                total += gradient[i * width + k] * y[size + k * count + j]
            column[i] = total
            for k in range(N):
                mass[i, k] = copy[i, k]
        eliminate(mass, column, column, 0)
        for i in range(N):
            out[size + (N + i) * count + j] = column[i]


@njit(cache=True, _nrt=False)
def project(t, y, p, work, out, flags):  # pragma: no cover - compiled by numba
    """out = y moved onto the constraint manifold (see the module docstring)."""
    matrix, vector = work[0], work[1]
    for i in range(2 * N):
        out[i] = y[i]
    if HOLONOMIC:
        for _ in range(PROJECTION_STEPS):
            positions(t, out, p, matrix, vector)
            eliminate(matrix, vector, vector, 0)
            step, largest = 0.0, 0.0
            for i in range(N):
                out[i] += vector[i]
                step = max(step, abs(vector[i]))
                largest = max(largest, abs(out[i]))
            if not step > STEP_TOLERANCE * (1.0 + largest):  # converged, or not finite
                break
    velocities(t, out, p, matrix, vector)
    eliminate(matrix, vector, vector, 0)
    for i in range(N):
        out[N + i] += vector[i]
    for i in range(2 * N):
        if not math.isfinite(out[i]):
            flags[0] = 1

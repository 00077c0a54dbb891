"""One system's y' with its sensitivities, for the compiled DOP853 method, as the text of
a generated module (as :mod:`.numba_derivative` is for the state and the variational
equations; :mod:`.compiled_sensitivity` fills in the globals between the ``generated``
markers and keeps the machine code in the code cache).

The vector is the state followed by the sensitivities S (2N x K, row by row) of the
forward sensitivity equations S' = J S + [dF/dp | 0] (:mod:`lagrangian.integrate.
sensitivity`): the first PARAMETERS columns are parameters, the others initial values.
The generated ``jacobian`` gives G = d(f - M a)/d(q, q', p) at a = q'' (N x (2N +
PARAMETERS), row by row); the lower rows of each column of S' are M^-1 (G_y s + G_p e_j),
solved column by column.  The method's workspace is made for a size whose arrays hold
this G (:func:`.compiled_sensitivity.workspace_size`): every loop here indexes by N.
This module itself is never run.
"""

import math

from numba import njit

# -- generated: begin (each generated module has its own values here) ----------------
N = 1
PARAMETERS = 0  # the columns of S (the first ones) that are parameters
fill = eliminate = jacobian = None  # the system's M and f, the printed solve, G
# -- generated: end ------------------------------------------------------------------


@njit(cache=True, _nrt=False)
def derivative(t, y, p, work, out, flags):  # pragma: no cover - compiled by numba
    """out = [y', S'] at (t, y, S); flags[0] = 1 where it is not finite."""
    mass, force, copy = work[0], work[1], work[2]
    fill(t, y, p, mass, force)
    for i in range(N):
        out[i] = y[N + i]
    for i in range(N):
        for j in range(N):
            copy[i, j] = mass[i, j]
    eliminate(mass, force, out, N)
    if y.shape[0] > 2 * N:
        sensitivities(t, y, p, work, out)
    for i in range(y.shape[0]):
        if not math.isfinite(out[i]):
            flags[0] = 1


@njit(cache=True, _nrt=False)
def sensitivities(t, y, p, work, out):  # pragma: no cover - compiled by numba
    """out[2N:] = J S + [dF/dp | 0] for S = y[2N:] (2N x K, row by row)."""
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

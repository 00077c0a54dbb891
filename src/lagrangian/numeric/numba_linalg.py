"""The in-kernel linear solve of the numba code: M q'' = f by Gaussian elimination.

Shared by the generated right-hand sides (:mod:`lagrangian.codegen.numba`)
and the ensemble loops (:mod:`lagrangian.ensemble.numba_loop`, which call
:func:`eliminate` with n a constant, so that the loops unroll).  Partial pivoting
keeps it stable for any nonsingular M (for unconstrained systems M is symmetric
positive definite, where pivoting changes nothing but costs little at the sizes
of mechanical models).  Importing this module imports numba.
"""

from __future__ import annotations

import numba

from .numba_cache import tolerate_full_disk

tolerate_full_disk()  # every numba module of ours imports this one before it compiles


@numba.njit(inline="always")
def eliminate(matrix, force, out, offset, n):  # pragma: no cover - compiled by numba
    """Gaussian elimination with partial pivoting, then back substitution:
    about n^3 / 3 multiply-adds (G. H. Golub, C. F. Van Loan, Matrix
    Computations, 4th ed., algorithm 3.4.1)."""
    for k in range(n):
        pivot, largest = k, abs(matrix[k, k])
        for i in range(k + 1, n):
            if abs(matrix[i, k]) > largest:
                pivot, largest = i, abs(matrix[i, k])
        if pivot != k:
            for j in range(n):
                matrix[k, j], matrix[pivot, j] = matrix[pivot, j], matrix[k, j]
            force[k], force[pivot] = force[pivot], force[k]
        for i in range(k + 1, n):
            factor = matrix[i, k] / matrix[k, k]
            for j in range(k, n):
                matrix[i, j] -= factor * matrix[k, j]
            force[i] -= factor * force[k]
    for i in range(n - 1, -1, -1):
        total = force[i]
        for j in range(i + 1, n):
            total -= matrix[i, j] * out[offset + j]
        out[offset + i] = total / matrix[i, i]


@numba.njit(cache=True)
def solve_into(matrix, force, out, offset):  # pragma: no cover - compiled by numba
    """``out[offset + i] = x_i`` with ``matrix x = force``; overwrites matrix and force."""
    eliminate(matrix, force, out, offset, force.shape[0])

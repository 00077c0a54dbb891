"""One system's tabulated rk4 for the numba target, as the text of a generated module.

:func:`lagrangian.codegen.time_terms.tabulated_loop` writes, per system and set of
shared parameters, a copy of this text into the code cache (as
:mod:`.numba_loop` is written) with the globals filled in (the block between the
``generated`` markers: the fillers of the time-only terms and of M found by
:func:`~lagrangian.codegen.time_terms.split_time_terms`, the solve for n, and the sizes)
and the step written by :func:`~lagrangian.codegen.time_terms.tabulated_step` between the
``scheme`` markers:

    tabulate(grid, c, p, table)        table[s, k]: the terms at t = grid[s] + c[k] h,
                                       then M^-1 there (where M is free of the state)
    rk4_table_step(t, h, y, p, rows, work, counts) -> 0
                                       y advanced by h in place, stage k reading rows[k]

The loop over members that calls the step is :mod:`.numba_table_stepping`.  This module
itself is never run.
"""

import math  # noqa: F401 - the printed step may call it

import numpy as np
from numba import njit

# -- generated: begin (each generated module has its own values here) ----------------
terms = mass = eliminate = None
N, TERMS, INVERSE = 1, 0, False
# -- generated: end ------------------------------------------------------------------


@njit(cache=True)
def tabulate(grid, c, p, table):  # pragma: no cover - compiled by numba
    """Each row of ``table`` (steps, stages, width), at the time the step's stage has:
    t + c[k] h, computed as the printed step computes it."""
    y = np.zeros(2 * N)  # the fillers of the terms and of M read no state
    matrix = np.empty((N, N))
    for s in range(grid.shape[0] - 1):
        t = grid[s]
        h = grid[s + 1] - t
        for k in range(c.shape[0]):
            time = t + (c[k] * h) if c[k] != 0.0 else t
            row = table[s, k]
            terms(time, y, p, row)
            if INVERSE:
                mass(time, y, p, matrix)
                for j in range(N):  # column j of M^-1: M x = e_j
                    a = matrix.copy()
                    b = np.zeros(N)
                    b[j] = 1.0
                    x = np.empty(N)
                    eliminate(a, b, x, 0)
                    for i in range(N):
                        row[TERMS + i * N + j] = x[i]


# -- scheme: begin (each generated module has its step, written by codegen.time_terms) ----
@njit(cache=True, _nrt=False)
def rk4_table_step(t, h, y, p, rows, work, counts):  # pragma: no cover
    return 0


# -- scheme: end ---------------------------------------------------------------------

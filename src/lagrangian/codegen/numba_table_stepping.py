"""The loop over members of the tabulated rk4 (:mod:`lagrangian.codegen.time_terms`),
shared by every system.

:func:`lagrangian.codegen.time_terms.tabulated_loop` writes a copy of this text into
the code cache, where ``@njit(cache=True)`` keeps the machine code: compiled once on a
machine, it gets a system's step (``rk4_table_step`` of :mod:`.numba_tabulated`) as a
pointer in a typed list of one, as :mod:`.numba_stepping` gets the plain steps.

    run(size, stack, rows, columns, steppers, y0, params, grid, table, every, final, paths)

steps every member of ``y0`` over ``grid`` (one member per ``prange`` iteration, each
with its own workspace and its row of ``params``), step s reading ``table[s]`` (made
with the parameters every member shares).  This module itself is never run.
"""

import numpy as np
from numba import njit, prange, types
from numba.typed import List

_1D = types.float64[::1]
_ROWS = types.float64[:, ::1]
_INTS = types.int64[::1]
WORK = types.Tuple((_1D, types.float64[:, :, ::1]))
#: step(t, h, y, p, rows, work, counts) -> 0: the type the steps are called as.
STEP = types.FunctionType(types.int64(types.float64, types.float64, _1D, _1D, _ROWS, WORK, _INTS))


@njit(types.ListType(STEP)(STEP), cache=True)
def steppers(function):  # pragma: no cover - compiled by numba
    pointers = List.empty_list(STEP)
    pointers.append(function)
    return pointers


@njit(parallel=True, cache=True)
def run(
    size, stack, rows, columns, steppers, y0, params, grid, table, every, final, paths
):  # pragma: no cover - compiled by numba
    step = steppers[0]
    count, m = y0.shape
    steps = grid.shape[0] - 1
    for b in prange(count):
        y = np.empty(m)
        for i in range(m):
            y[i] = y0[b, i]
        p = params[b]
        work = (np.empty(size), np.empty((stack, rows, columns)))
        counts = np.zeros(3, dtype=np.int64)
        if every > 0:
            for i in range(m):
                paths[b, i, 0] = y[i]
        for s in range(steps):
            ta = grid[s]
            step(ta, grid[s + 1] - ta, y, p, table[s], work, counts)
            if every > 0 and (s + 1) % every == 0:
                for i in range(m):
                    paths[b, i, (s + 1) // every] = y[i]
        for i in range(m):
            final[b, i] = y[i]

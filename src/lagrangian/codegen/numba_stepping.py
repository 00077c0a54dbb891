"""The compiled fixed-step loops of the numba target, shared by every system and scheme.

:func:`lagrangian.codegen.loops.stepping_module` writes a copy of this text into the
code cache, where ``@njit(cache=True)`` keeps the machine code: the loops are compiled
once on a machine (every scheme's workspace has one type, ``WORK``:
:class:`lagrangian.codegen.steps.WorkspaceLayout`), and a system's scheme functions
(:mod:`.numba_loop`) come in as function pointers, each in a typed list of one (a
pointer passed from Python is converted at every call, one in a list once).

    workspace(size, stack, rows, columns)

is a workspace of a scheme for a system: ``size`` entries for its vectors, ``stack``
matrices of rows x columns, and

    run(size, stack, rows, columns, inits, steppers, w, y0, params, grid, track, stop,
        save_every, tol, floor, iterations, final, flips, failures, paths, exponents,
        below, crossings)

is the ensemble's loop: one member per ``prange`` iteration, each with its own
workspace.  With ``w`` entries carried after the state (rk4-tangent: k = w / 2n
displacements, their starting values in ``y0`` after the state's, ``y0`` and ``final``
then 2n + w wide), it renormalises each displacement to length 1 after every step and
gives each member's largest Lyapunov exponent, the mean of log |w_1| per unit time (the
numpy backend's ``lyapunov`` observable, :mod:`lagrangian.ensemble.numpy_backend`); the
unit displacements at the end are in ``final`` (the chaos indicators).  With ``below`` > 0
it computes SALI of the first two after every step, min(|w_1 + w_2|, |w_1 - w_2|), and
puts the first step time at which it is below ``below`` into ``crossings`` (NaN: never).
With ``stop``, a member stops once everything looked for has happened: its flip (with
``track``) and its crossing (with ``below``).

    advance(steppers, y, p, work, grid, start, stop, tol, floor, iterations, states, counts)

is a stretch of steps of one single run.  This module itself is never run.
"""

import math

import numpy as np
from numba import njit, prange, types
from numba.typed import List

_1D = types.float64[::1]
_INTS = types.int64[::1]

#: A scheme's workspace (codegen.steps.WorkspaceLayout): its vectors in one buffer, its
#: matrices in one stack, the same type for every scheme.
WORK = types.Tuple((_1D, types.float64[:, :, ::1]))


@njit(cache=True)
def workspace(size, stack, rows, columns):  # pragma: no cover - compiled by numba
    return np.empty(size), np.empty((stack, rows, columns))


#: init(t, y, p, work, counts) and step(t, h, y, p, work, tol, floor, iterations, counts)
#: -> code: the types a scheme's functions are called as.
INIT = types.FunctionType(types.none(types.float64, _1D, _1D, WORK, _INTS))
STEP = types.FunctionType(
    types.int64(
        types.float64, types.float64, _1D, _1D, WORK, types.float64, types.float64,
        types.int64, _INTS,
    )
)  # fmt: skip
#: A coordinate beyond this angle has flipped (the flip_time observable).
LIMIT = math.pi


# Each of a system's functions in a typed list of one, made in compiled code (numba
# compiles a typed list's methods in every process, 0.3-0.5 s for each type of item;
# these functions' machine code is cached): see lagrangian.integrate.numba_dop853.
@njit(types.ListType(INIT)(INIT), cache=True)
def inits(function):  # pragma: no cover - compiled by numba
    pointers = List.empty_list(INIT)
    pointers.append(function)
    return pointers


@njit(types.ListType(STEP)(STEP), cache=True)
def steppers(function):  # pragma: no cover - compiled by numba
    pointers = List.empty_list(STEP)
    pointers.append(function)
    return pointers


# -- the loop over members -----------------------------------------------------------
@njit(parallel=True, cache=True)
def run(
    size, stack, rows, columns, inits, steppers, w, y0, params, grid, track, stop,
    save_every, tol, floor, iterations, final, flips, failures, paths, exponents, below,
    crossings,
):  # pragma: no cover - compiled by numba  # fmt: skip
    init, step = inits[0], steppers[0]
    count, width = y0.shape
    m = width - w
    n = m // 2
    vectors = w // m if w > 0 else 0
    steps = grid.shape[0] - 1
    for b in prange(count):
        y = np.empty(width)
        for i in range(width):
            y[i] = y0[b, i]
        stretch = 0.0
        p = params[b]
        work = workspace(size, stack, rows, columns)
        counts = np.zeros(3, dtype=np.int64)
        flip = np.nan
        crossing = np.nan
        failure = -1
        if track:
            for i in range(n):
                if abs(y[i]) > LIMIT:
                    flip = grid[0]
        if save_every > 0:
            for i in range(m):
                paths[b, i, 0] = y[i]
        if not (stop and flip == flip and below <= 0.0):
            init(grid[0], y, p, work, counts)
            for s in range(steps):
                ta = grid[s]
                if step(ta, grid[s + 1] - ta, y, p, work, tol, floor, iterations, counts) != 0:
                    failure = s
                    break
                for v in range(vectors):
                    start = m * (v + 1)
                    norm = 0.0
                    for i in range(start, start + m):
                        norm += y[i] * y[i]
                    norm = math.sqrt(norm)
                    if v == 0:
                        stretch += math.log(norm)
                    for i in range(start, start + m):
                        y[i] /= norm
                if save_every > 0 and (s + 1) % save_every == 0:
                    for i in range(m):
                        paths[b, i, (s + 1) // save_every] = y[i]
                if track and flip != flip:
                    for i in range(n):
                        if abs(y[i]) > LIMIT:
                            flip = grid[s + 1]
                if below > 0.0 and crossing != crossing:
                    plus = 0.0
                    minus = 0.0
                    for i in range(m, 2 * m):
                        plus += (y[i] + y[i + m]) * (y[i] + y[i + m])
                        minus += (y[i] - y[i + m]) * (y[i] - y[i + m])
                    if min(math.sqrt(plus), math.sqrt(minus)) < below:
                        crossing = grid[s + 1]
                flipped = flip == flip or not track
                crossed = crossing == crossing or below <= 0.0
                if stop and (track or below > 0.0) and flipped and crossed:
                    break
        flips[b] = flip
        if below > 0.0:
            crossings[b] = crossing
        failures[b] = failure
        exponents[b] = stretch / (grid[steps] - grid[0]) if w > 0 else math.nan
        for i in range(width):
            final[b, i] = y[i]


# -- a stretch of one single run ----------------------------------------------------
@njit(cache=True)
def advance(
    steppers, y, p, work, grid, start, stop, tol, floor, iterations, states, counts
):  # pragma: no cover - compiled by numba  # fmt: skip
    """Steps start, ..., stop - 1 of ``grid`` from y (advanced in place), the state after
    step s into ``states[s + 1]``.  Returns (the step reached, 0), or (the step that
    failed, its code: 1 or 2 from the scheme's Newton iterations, 3 for a state that is
    not finite)."""
    step, m = steppers[0], states.shape[1]
    for s in range(start, stop):
        ta = grid[s]
        failed = step(ta, grid[s + 1] - ta, y, p, work, tol, floor, iterations, counts)
        if failed != 0:
            return s, failed
        for i in range(m):
            value = y[i]
            if value - value != 0:  # inf or NaN
                return s, 3
            states[s + 1, i] = value
    return stop, 0

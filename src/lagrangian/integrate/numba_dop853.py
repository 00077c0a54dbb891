"""DOP853's step loop in numba, as the text of a generated module shared by every system.

numba keeps machine code on disk only for functions at the top of a real module file,
so :mod:`lagrangian.integrate.compiled_dop853` writes this text into the code cache as it
is, where ``@njit(cache=True)`` keeps the compiled method: one for every system.  A
system's y' comes in as an argument, ``y_prime`` (a typed list holding the system's
``derivative``, from its own generated module, :mod:`.numba_derivative`; n coordinates,
``tangent`` for the variational equations): ``advance`` is compiled for the type of a
function pointer of that signature (``DERIVATIVE``), not for each system's function, so
a new system compiles only its y' (about a second, where the whole loop took 4-5 s more
for each system and each loop).

    advance(y_prime, n, tangent, link, clock, y, f, p, t_end, rtol, atol, dense, t_eval,
            out, ts, ys, olds, slopes, counts, flags) -> status
    slope(y_prime, n, tangent, link, t, y, p, out, flags)  out = y' at (t, y), for Python

``link`` is empty for a system's generated y'; for ``linked_derivative`` (the y' of any
system, over the machine code SymEngine's LLVM made of its M and f, called by address:
:mod:`lagrangian.integrate.numba_address`) it is (address, user data, parameter count),
and a new system then compiles nothing in numba at all (see
:func:`lagrangian.integrate.compiled_dop853.linked_loop`).

is SciPy's ``DOP853._step_impl`` (scipy/integrate/_ivp/rk.py, BSD-3-Clause) for one
state, repeated: the same coefficients, error norm and step-size control.  It takes
accepted steps from (t, y, f = y') = (``clock[0]``, ``y``, ``f``) with the next step
size ``clock[1]`` until t_end or until ``ts`` is full, keeping everything it works on in
its arguments after every accepted step (so that a ZeroDivisionError, which numba
raises where NumPy would give inf, leaves them at the last accepted step): the
step's end into ``ts``/``ys`` at row ``counts[1]``, with ``dense`` its start and
interpolant into ``olds``/``slopes`` (the rows of F of SciPy's
``Dop853DenseOutput``) and the interpolant at the times ``t_eval[counts[2]:]`` it
covers into ``out``.  ``counts[0]`` adds the right-hand side's evaluations,
``counts[3]`` is 1 while the current step has been rejected; ``flags[0]`` is set to 1
where an evaluation was not finite.  Status: 0 ``ts`` full, 1 t_end reached, 2 the
step size fell below 10 ulp of t (SciPy's "Required step size is less than spacing
between numbers."), 3 an accepted state is not finite.  With a second function in
``y_prime`` (a constrained system's ``project``, :func:`projected_y_prime`) every accepted
state and every output is projected onto the constraint manifold, and y' is evaluated again
at the projected state (one evaluation more per step): the next step starts on the manifold.

The pieces of a step (``step``, ``interpolation``, ``interpolate``, ``accept``) are
functions of their own, so that other loops (the sections of
:mod:`lagrangian.integrate.numba_sections`) take the same steps.  The vector integrated
has any length (the state, or the state and the displacements of the variational
equations).  This module itself is never run.
"""

import math

import numpy as np
from numba import njit, types
from numba.typed import List

from lagrangian.integrate.dop853_tableau import E3, E5, A, B, C, D
from lagrangian.integrate.numba_address import call_address

SAFETY = 0.9  # SciPy's step-size controller (scipy/integrate/_ivp/rk.py)
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
EXPONENT = -1.0 / 8.0  # -1 / (error estimator order + 1)
STAGES = 12

_1D, _2D = types.float64[::1], types.float64[:, ::1]
#: The arrays a system's ``derivative`` works in (``workspace(n, tangent)``, or
#: ``linked_workspace(n, link)`` for ``linked_derivative``); the last holds the link.
WORK = types.Tuple((_2D, _1D, _2D, _1D, _1D, types.int64[::1]))
#: derivative(t, y, p, work, out, flags): the type every system's y' is called as.
DERIVATIVE = types.FunctionType(types.void(types.float64, _1D, _1D, WORK, _1D, types.int64[::1]))


# The loops below take a system's y' in a typed list of one, made here: a function passed
# from Python is converted to a pointer at every call (0.14 ms), one in a list once, and
# the list's type, the same for every system, is what they are compiled for.  Made in
# compiled code because numba compiles a typed list's methods in every process (0.3-0.5 s
# for each type of item); this function's machine code is cached.
@njit(types.ListType(DERIVATIVE)(DERIVATIVE), cache=True)
def y_prime(derivative):  # pragma: no cover - compiled by numba
    """[derivative]: the system's y' as the loops take it."""
    pointers = List.empty_list(DERIVATIVE)
    pointers.append(derivative)
    return pointers


@njit(types.ListType(DERIVATIVE)(DERIVATIVE, DERIVATIVE), cache=True)
def projected_y_prime(derivative, project):  # pragma: no cover - compiled by numba
    """[derivative, project]: the y' of a constrained system and its projection onto the
    constraint manifold (``project(t, y, p, work, out, flags)``, out = y projected), which
    ``advance`` applies to every accepted state and every output."""
    pointers = List.empty_list(DERIVATIVE)
    pointers.append(derivative)
    pointers.append(project)
    return pointers


@njit(cache=True)
def workspace(n, tangent):  # pragma: no cover - compiled by numba
    """(M, f, a copy of M, G row by row, a column, no link): the arrays a system's
    generated ``derivative`` works in, for a linear solve of size n (the coordinates, or
    with constraints the coordinates and the multipliers; the copy, G and the column for
    the variational equations only)."""
    link = np.empty(0, dtype=np.int64)
    if tangent:
        return (
            np.empty((n, n)), np.empty(n), np.empty((n, n)), np.empty(2 * n * n), np.empty(n),
            link,
        )  # fmt: skip
    return np.empty((n, n)), np.empty(n), np.empty((0, 0)), np.empty(0), np.empty(0), link


@njit(cache=True)
def linked_workspace(n, link):  # pragma: no cover - compiled by numba
    """(M, f, nothing, the values [t, y, p], the entries [M row by row, f], the link): the
    arrays ``linked_derivative`` works in, for n coordinates and the ``link`` (address,
    user data, parameter count) of SymEngine's function of M and f."""
    values = np.empty(1 + 2 * n + link[2])
    return np.empty((n, n)), np.empty(n), np.empty((0, 0)), values, np.empty(n * n + n), link


@njit(cache=True, _nrt=False)
def linked_derivative(t, y, p, work, out, flags):  # pragma: no cover - compiled by numba
    """out = y' = [q', q''] at (t, y) from SymEngine's compiled M and f at the address of
    ``work``'s link (:mod:`lagrangian.integrate.numba_address`): the y' of any system,
    compiled once on a machine; flags[0] = 1 where it is not finite."""
    mass, force, values, entries, link = work[0], work[1], work[3], work[4], work[5]
    n = mass.shape[0]
    values[0] = t
    for i in range(2 * n):
        values[1 + i] = y[i]
    for i in range(p.shape[0]):
        values[1 + 2 * n + i] = p[i]
    call_address(link[0], link[1], entries, values)
    for i in range(n):
        for j in range(n):
            mass[i, j] = entries[i * n + j]
        force[i] = entries[n * n + i]
        out[i] = y[n + i]
    eliminate(mass, force, out, n)
    for i in range(y.shape[0]):
        if not math.isfinite(out[i]):
            flags[0] = 1


@njit(cache=True, _nrt=False)
def eliminate(a, b, x, offset):  # pragma: no cover - compiled by numba
    """x[offset:offset + n] with a x = b for an n x n ``a`` of any n: the printed
    ``eliminate`` of :func:`lagrangian.codegen.steps.elimination` (Gaussian elimination with
    partial pivoting, the same operations in the same order), with n read from ``a``."""
    n = a.shape[0]
    singular = 0
    for k in range(n):
        for i in range(k + 1, n):
            if abs(a[i, k]) > abs(a[k, k]):
                for j in range(n):
                    swap = a[k, j]
                    a[k, j] = a[i, j]
                    a[i, j] = swap
                swap = b[k]
                b[k] = b[i]
                b[i] = swap
        pivot = a[k, k]
        if (abs(pivot) == 0.0) or ((pivot - pivot) != 0.0):
            singular = 1
        a[k, k] = 1.0 / pivot
        for i in range(k + 1, n):
            factor = a[i, k] * a[k, k]
            for j in range(k + 1, n):
                a[i, j] = a[i, j] - (factor * a[k, j])
            b[i] = b[i] - (factor * b[k])
    for k in range(n):
        row = n - 1 - k
        total = b[row]
        for j in range(row + 1, n):
            total = total - (a[row, j] * x[offset + j])
        x[offset + row] = total * a[row, row]
    return singular


@njit(cache=True)
def slope(y_prime, n, tangent, link, t, y, p, out, flags):  # pragma: no cover - compiled by numba
    """out = y' at (t, y), for Python (the size of a first step)."""
    y_prime[0](t, y, p, work_for(n, tangent, link), out, flags)


@njit(cache=True)
def work_for(n, tangent, link):  # pragma: no cover - compiled by numba
    """The arrays of the system's y': ``workspace``, or with a link ``linked_workspace``."""
    if link.shape[0]:
        return linked_workspace(n, link)
    return workspace(n, tangent)


@njit(cache=True)
def buffers(size):  # pragma: no cover - compiled by numba
    """(stages, a stage, y_new, the interpolant) of a loop over vectors of ``size``."""
    return np.empty((16, size)), np.empty(size), np.empty(size), np.empty((7, size))


# What allocates nothing is compiled lean: not inlined, no reference counts (LEAN of
# lagrangian.codegen.steps, which says why).
@njit(cache=True, _nrt=False)
def take_stages(
    derivative, first, last, t, h, y, p, stages, stage, work, flags
):  # pragma: no cover - compiled by numba
    """Stages first..last-1 of the step of size h from (t, y), rows of ``stages``."""
    for s in range(first, last):
        for i in range(y.shape[0]):
            total = 0.0
            for j in range(s):
                total += stages[j, i] * A[s, j]
            stage[i] = y[i] + total * h
        derivative(t + C[s] * h, stage, p, work, stages[s], flags)


@njit(cache=True, _nrt=False)
def step(
    derivative, clock, y, f, p, t_end, rtol, atol, stages, stage, y_new, work, counts, flags
):  # pragma: no cover - compiled by numba
    """One step from (t, y, f) = (``clock[0]``, y, f), tried with the size ``clock[1]`` and
    shrunk until its error is within the tolerance: y_new and the stages of the step
    taken.  Returns (t_new, the next step size); t_new = t where the size fell below 10 ulp
    of t.  Rejections update ``clock[1]`` and set ``counts[3]`` (see the module docstring).
    """
    size = y.shape[0]
    t = clock[0]
    h_abs = clock[1]
    min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
    if h_abs < min_step:
        h_abs = min_step
    rejected = counts[3] == 1
    while True:
        if h_abs < min_step:
            return t, h_abs
        t_new = t + h_abs
        if t_new - t_end > 0:
            t_new = t_end
        h = t_new - t
        h_abs = abs(h)
        for i in range(size):
            stages[0, i] = f[i]
        counts[0] += STAGES
        take_stages(derivative, 1, STAGES, t, h, y, p, stages, stage, work, flags)
        for i in range(size):
            total = 0.0
            for j in range(STAGES):
                total += stages[j, i] * B[j]
            y_new[i] = y[i] + h * total
        derivative(t + h, y_new, p, work, stages[STAGES], flags)
        error5 = 0.0
        error3 = 0.0
        for i in range(size):
            scale = atol + max(abs(y[i]), abs(y_new[i])) * rtol
            e5 = 0.0
            e3 = 0.0
            for j in range(STAGES + 1):
                e5 += stages[j, i] * E5[j]
                e3 += stages[j, i] * E3[j]
            error5 += (e5 / scale) ** 2
            error3 += (e3 / scale) ** 2
        if error5 == 0.0 and error3 == 0.0:
            norm = 0.0
        else:
            norm = h_abs * error5 / math.sqrt((error5 + 0.01 * error3) * size)
        if norm < 1.0:
            factor = MAX_FACTOR if norm == 0.0 else min(MAX_FACTOR, SAFETY * norm**EXPONENT)
            if rejected:
                factor = min(1.0, factor)
            return t_new, h_abs * factor
        shrink = SAFETY * norm**EXPONENT
        h_abs *= shrink if shrink > MIN_FACTOR else MIN_FACTOR  # NaN: MIN_FACTOR
        rejected = True
        clock[1] = h_abs
        counts[3] = 1


@njit(cache=True, _nrt=False)
def interpolation(
    derivative, t, h, y, y_new, p, stages, stage, work, interpolant, counts, flags
):  # pragma: no cover - compiled by numba
    """The rows of the step's 7th-order interpolant (SciPy's ``Dop853DenseOutput``) into
    ``interpolant``, after the three stages more it needs."""
    counts[0] += 3
    take_stages(derivative, STAGES + 1, 16, t, h, y, p, stages, stage, work, flags)
    for i in range(y.shape[0]):
        delta = y_new[i] - y[i]
        interpolant[0, i] = delta
        interpolant[1, i] = h * stages[0, i] - delta
        interpolant[2, i] = 2 * delta - h * (stages[STAGES, i] + stages[0, i])
        for r in range(4):
            total = 0.0
            for j in range(16):
                total += D[r, j] * stages[j, i]
            interpolant[3 + r, i] = h * total


@njit(cache=True, _nrt=False)
def interpolate(interpolant, x, y, out):  # pragma: no cover - compiled by numba
    """out = the interpolant at x = (t - t_old) / h of the step from y."""
    for i in range(y.shape[0]):
        value = 0.0
        for r in range(6, -1, -1):
            value += interpolant[r, i]
            if (6 - r) % 2 == 0:
                value *= x
            else:
                value *= 1 - x
        out[i] = value + y[i]


@njit(cache=True, _nrt=False)
def accept(clock, y, f, y_new, stages, t_new, h_next, counts):  # pragma: no cover
    """The step to t_new taken: y, f and the clock moved on; whether y is finite."""
    finite = True
    for i in range(y.shape[0]):
        y[i] = y_new[i]
        f[i] = stages[STAGES, i]
        if not math.isfinite(y_new[i]):
            finite = False
    clock[0] = t_new
    clock[1] = h_next
    counts[3] = 0
    return finite


@njit(cache=True)
def advance(
    y_prime, n, tangent, link, clock, y, f, p, t_end, rtol, atol, dense, t_eval, out, ts, ys, olds,
    slopes, counts, flags,
):  # pragma: no cover - compiled by numba  # fmt: skip
    derivative, work = y_prime[0], work_for(n, tangent, link)
    projected = len(y_prime) > 1
    size = y.shape[0]
    stages, stage, y_new, interpolant = buffers(size)
    capacity = ts.shape[0]
    while counts[1] < capacity:
        t = clock[0]
        if t >= t_end:
            return 1
        t_new, h_next = step(
            derivative, clock, y, f, p, t_end, rtol, atol, stages, stage, y_new, work, counts,
            flags,
        )  # fmt: skip
        if t_new == t:
            return 2
        h = t_new - t
        k = counts[1]
        if dense:
            interpolation(
                derivative, t, h, y, y_new, p, stages, stage, work, interpolant, counts, flags
            )
            for i in range(size):
                olds[k, i] = y[i]
                for r in range(7):
                    slopes[k, r, i] = interpolant[r, i]
            while counts[2] < t_eval.shape[0] and t_eval[counts[2]] <= t_new:
                interpolate(interpolant, (t_eval[counts[2]] - t) / h, y, out[counts[2]])
                if projected:
                    row = out[counts[2]]
                    y_prime[1](t_eval[counts[2]], row, p, work, row, flags)
                counts[2] += 1
        if projected:  # onto the manifold, and y' there (the last stage was off it)
            y_prime[1](t_new, y_new, p, work, y_new, flags)
            counts[0] += 1
            derivative(t_new, y_new, p, work, stages[STAGES], flags)
        finite = accept(clock, y, f, y_new, stages, t_new, h_next, counts)
        for i in range(size):
            ys[k, i] = y_new[i]
        ts[k] = t_new
        counts[1] = k + 1
        if not finite:
            return 3
    return 0

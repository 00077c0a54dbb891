"""Crossings of a surface of section found in DOP853's compiled loop, as a generated module.

:mod:`lagrangian.integrate.compiled_sections` writes a copy of this text into the code
cache with the block between the ``generated`` markers filled in: the import of the
pieces of a step from the DOP853 method's module (:mod:`.numba_dop853`).  Like the
method, it is compiled once for every system and section: the system's ``derivative``
(:mod:`.numba_derivative`) and the section's generated ``section(t, y, p, out)``,
out[0] = g (from :mod:`lagrangian.codegen.numba`), come in as function pointers (each in
a typed list of one, ``y_prime`` and ``g``).

    cross(y_prime, g, n, tangent, clock, y, f, p, t_end, rtol, atol, direction, level,
          budget, found_t, found_y, counts, flags) -> status

takes up to ``budget`` steps of one motion as ``advance`` takes them (the same
arguments: ``clock``, ``y``, ``f``, ``counts[0:4]``, ``flags``; everything kept in them
after every accepted step) and evaluates g at every step's end.  Where g changes sign in
``direction`` between the ends (SciPy's ``find_active_events``: g <= 0 <= g_new
upwards, g >= 0 >= g_new downwards), the step's 7th-order interpolant is built and the
root of g on it found by Brent's method to 4 eps, as SciPy's ``solve_ivp`` locates an
event (``brentq(xtol=4 EPS, rtol=4 EPS)``): the crossing's time into ``found_t`` and the
interpolated state into ``found_y``, at row ``counts[4]``.  ``level`` holds g at the
last step's end, and (t0, g there) of the motion's start, whose g is replaced by the
sign it takes just after t0 when it is 0 (:func:`lagrangian.integrate.events.scipy_event`).
Status: 0 ``budget`` steps taken, 1 t_end reached, 2 and 3 as ``advance``'s, 4
``found_t`` full.  This module itself is never run.
"""

import numpy as np
from numba import njit, types
from numba.typed import List

# -- generated: begin (the generated module imports the method's module) --------------
from lagrangian.integrate.numba_dop853 import (
    accept,
    buffers,
    interpolate,
    interpolation,
    step,
    workspace,
)

# -- generated: end ------------------------------------------------------------------

_1D = types.float64[::1]
#: section(t, y, p, out): out[0] = g, the type every section is called as.
SECTION = types.FunctionType(types.void(types.float64, _1D, _1D, _1D))


@njit(types.ListType(SECTION)(SECTION), cache=True)
def g(section):  # pragma: no cover - compiled by numba
    """[section]: the section's function as ``cross`` takes it (a typed list of one, made
    in compiled code: see the method's ``y_prime``)."""
    pointers = List.empty_list(SECTION)
    pointers.append(section)
    return pointers


TOLERANCE = 4 * np.finfo(np.float64).eps  # SciPy's xtol and rtol of an event's root
ITERATIONS = 100  # brentq's default


@njit(cache=True, _nrt=False)
def crosses(before, after, direction):  # pragma: no cover - compiled by numba
    up = before <= 0 <= after
    down = before >= 0 >= after
    if direction > 0:
        return up
    if direction < 0:
        return down
    return up or down


@njit(cache=True, _nrt=False)
def value(
    section, s, t, h, y, p, interpolant, level, state, out
):  # pragma: no cover - compiled by numba
    """g at time s on the interpolant of the step of width h from (t, y)."""
    if s == level[1]:
        return level[2]
    interpolate(interpolant, (s - t) / h, y, state)
    section(s, state, p, out)
    return out[0]


@njit(cache=True, _nrt=False)
def root(
    section, t, h, y, p, interpolant, level, state, out
):  # pragma: no cover - compiled by numba
    """The root of g on the step (t, t + h), by SciPy's ``brentq`` (scipy/optimize/Zeros/
    brentq.c, BSD-3-Clause: Brent's method, R. P. Brent, *Algorithms for Minimization
    without Derivatives*, 1973, ch. 4)."""
    x_pre, x_cur = t, t + h
    f_pre = value(section, x_pre, t, h, y, p, interpolant, level, state, out)
    f_cur = value(section, x_cur, t, h, y, p, interpolant, level, state, out)
    if f_pre == 0.0:
        return x_pre
    if f_cur == 0.0:
        return x_cur
    x_blk, f_blk, s_pre, s_cur = 0.0, 0.0, 0.0, 0.0
    for _ in range(ITERATIONS):
        if f_pre != 0.0 and f_cur != 0.0 and (f_pre < 0.0) != (f_cur < 0.0):
            x_blk, f_blk = x_pre, f_pre
            s_pre = s_cur = x_cur - x_pre
        if abs(f_blk) < abs(f_cur):
            x_pre, x_cur, x_blk = x_cur, x_blk, x_cur
            f_pre, f_cur, f_blk = f_cur, f_blk, f_cur
        delta = (TOLERANCE + TOLERANCE * abs(x_cur)) / 2
        s_bis = (x_blk - x_cur) / 2
        if f_cur == 0.0 or abs(s_bis) < delta:
            return x_cur
        if abs(s_pre) > delta and abs(f_cur) < abs(f_pre):
            if x_pre == x_blk:  # interpolate
                s_try = -f_cur * (x_cur - x_pre) / (f_cur - f_pre)
            else:  # extrapolate
                d_pre = (f_pre - f_cur) / (x_pre - x_cur)
                d_blk = (f_blk - f_cur) / (x_blk - x_cur)
                s_try = -f_cur * (f_blk * d_blk - f_pre * d_pre) / (d_blk * d_pre * (f_blk - f_pre))
            if 2 * abs(s_try) < min(abs(s_pre), 3 * abs(s_bis) - delta):
                s_pre, s_cur = s_cur, s_try  # a good short step
            else:
                s_pre = s_cur = s_bis
        else:
            s_pre = s_cur = s_bis
        x_pre, f_pre = x_cur, f_cur
        if abs(s_cur) > delta:
            x_cur += s_cur
        else:
            x_cur += delta if s_bis > 0 else -delta
        f_cur = value(section, x_cur, t, h, y, p, interpolant, level, state, out)
    return x_cur


@njit(cache=True)
def cross(
    y_prime, g, n, tangent, clock, y, f, p, t_end, rtol, atol, direction, level, budget,
    found_t, found_y, counts, flags,
):  # pragma: no cover - compiled by numba  # fmt: skip
    derivative, section, work = y_prime[0], g[0], workspace(n, tangent)
    stages, stage, y_new, interpolant = buffers(y.shape[0])
    state, out = np.empty(y.shape[0]), np.empty(1)
    for _ in range(budget):
        t = clock[0]
        if t >= t_end:
            return 1
        if counts[4] >= found_t.shape[0]:
            return 4
        t_new, h_next = step(
            derivative, clock, y, f, p, t_end, rtol, atol, stages, stage, y_new, work, counts,
            flags,
        )  # fmt: skip
        if t_new == t:
            return 2
        h = t_new - t
        section(t_new, y_new, p, out)
        after = out[0]
        if crosses(level[0], after, direction):
            interpolation(
                derivative, t, h, y, y_new, p, stages, stage, work, interpolant, counts, flags
            )
            found = root(section, t, h, y, p, interpolant, level, state, out)
            k = counts[4]
            found_t[k] = found
            interpolate(interpolant, (found - t) / h, y, found_y[k])
            counts[4] = k + 1
        level[0] = after
        counts[1] += 1
        if not accept(clock, y, f, y_new, stages, t_new, h_next, counts):
            return 3
    return 0

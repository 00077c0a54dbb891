"""Taylor's method's step loop in numba, as the text of a generated module.

:mod:`lagrangian.integrate.taylor_compiled` writes a copy of this text into the code cache
with the import of ``coefficients`` between the ``generated`` markers, where
``@njit(cache=True)`` keeps the compiled loop: a small system's own generated coefficients
(:mod:`lagrangian.codegen.taylor_numba`; the loop compiled for each such system), or for a
large one the compact mode's walk of the tape as data (:mod:`.numba_taylor_tape`, the same
text for every system: compiled once per machine), which reads ``program`` and
``exponents`` (empty for the other).  Unlike DOP853's loop (:mod:`.numba_dop853`, one for
every system, calling the system's y' through a function pointer) a small system's loop
is its own: a call through a pointer cost 0.15 us a step, 15% of the double pendulum's.

    advance(size, c, order, t_end, clock, tc, flat, work, t_eval, out, ts, ys, counts,
            limit, keep, program, exponents, kept) -> status

takes steps from (t, y) = (``clock[0]``, ``tc[:size, 0]``) towards ``t_end``, at most
``limit`` of them (``flat``: ``tc``'s memory as a 1-D array, which a printed system's
coefficients index), the step's order ``order`` and size by Jorba and Zou's rule as heyoka
takes it (Biscani and Izzo, MNRAS 504 (2021), section 2.2): with x = max |y_i|,
N_j = max_i |y_i[j]| over the coefficients of orders j = order - 1 and order, and
X = x where x > 1 (the tolerance relative) else 1 (absolute),

    rho = min over j of (X / N_j)^(1/j),    h = rho exp(-0.7 / (order - 1)) / e^2,

cut to end on ``t_end``.  The new state is the Taylor polynomial at h (Horner), and so is
every output time ``t_eval[counts[2]:]`` the step covers (into the columns of ``out``);
with ``keep`` every step's end goes into ``ts``/``ys`` at row ``counts[1]``, and where
``kept`` has rows, the step's Taylor coefficients of the state into ``kept[counts[1]]``
(events are located on them).  ``counts[0]``
adds the steps.  Status: 0 ``limit`` steps taken or ``ts`` full, 1 t_end reached, 2 the step
fell below 10 ulp of t, 3 a coefficient or the new state is not finite (the state in
``tc[:size, 0]`` and ``clock[0]`` are then the last finite ones).  This module itself is
never run.
"""

import math

from numba import njit, uint64

# -- generated: begin (each generated module imports its system's coefficients here) --
coefficients = None  # coefficients(t, c, order, tc, flat, program, exponents): see below
# -- generated: end ------------------------------------------------------------------

#: heyoka's safety factor on rho at order p: exp(-0.7 / (p - 1)) / e^2.
SAFETY = math.exp(-2.0)
#: 10 machine epsilons: 10 ulp of t is at most this times |t|.
TINY_STEP = 10.0 * 2.220446049250313e-16


@njit(cache=True)
def step_size(tc, size, order, safety):  # pragma: no cover - compiled by numba
    """h of Jorba and Zou's rule for the coefficients in ``tc`` (see the module), ``safety``
    its factor at ``order``; inf where the last two orders vanish, NaN where a coefficient
    is not finite."""
    largest, last, before = 0.0, 0.0, 0.0
    top = uint64(order)
    for i in range(size):
        largest = max(largest, abs(tc[i, 0]))
        last = max(last, abs(tc[i, top]))
        before = max(before, abs(tc[i, top - uint64(1)]))
        if not (math.isfinite(tc[i, top]) and math.isfinite(tc[i, top - uint64(1)])):
            return math.nan
    scale = largest if largest > 1.0 else 1.0
    # rho = min((scale / last)^(1/order), (scale / before)^(1/(order - 1))) as one exp of
    # the smaller logarithm: two logs and an exp where two powers took two of each
    exponent = math.inf
    if last > 0.0:
        exponent = math.log(scale / last) / order
    if before > 0.0:
        exponent = min(exponent, math.log(scale / before) / (order - 1))
    return math.exp(exponent) * safety


@njit(cache=True)
def below_ten_ulp(h, t):  # pragma: no cover - compiled by numba
    """Whether |h| <= 10 ulp of t.  10 ulp of t is at most 10 eps |t| (or 10 of the smallest
    subnormal, near 0), so only a step that short asks nextafter (a call each step was a
    few percent of the double pendulum's)."""
    return abs(h) <= TINY_STEP * abs(t) + 5e-323 and abs(h) <= 10.0 * abs(
        math.nextafter(t, math.inf) - t
    )


@njit(cache=True)
def evaluate(tc, size, order, h, into, column):  # pragma: no cover - compiled by numba
    """into[:, column] = the Taylor polynomial of every state row at h (Horner)."""
    top = uint64(order)  # unsigned: indexed without numba's check for negative indices
    for i in range(size):  # a row's sum in a register (through ``into`` it was a store and a
        value = tc[i, top]  # load a term, 9% of the double pendulum's step)
        for k in range(uint64(1), top + uint64(1)):
            value = value * h + tc[i, top - k]
        into[i, column] = value


@njit(cache=True)
def advance(
    size,
    c,
    order,
    t_end,
    clock,
    tc,
    flat,
    work,
    t_eval,
    out,
    ts,
    ys,
    counts,
    limit,
    keep,
    program,
    exponents,
    kept,
):  # pragma: no cover - compiled by numba
    """Steps towards ``t_end`` (see the module docstring)."""
    t = clock[0]
    forward = t_end >= t
    safety = SAFETY * math.exp(-0.7 / (order - 1))
    for _ in range(limit):
        if t == t_end:
            return 1
        if keep and counts[1] >= ts.shape[0]:
            return 0
        coefficients(t, c, order, tc, flat, program, exponents)
        h = step_size(tc, size, order, safety)
        if math.isnan(h):
            return 3
        remaining = t_end - t
        last = h >= abs(remaining)
        if last:
            h = abs(remaining)
        if not forward:
            h = -h
        if not last and below_ten_ulp(h, t):
            return 2
        if keep and kept.shape[0] > 0:  # the step's polynomial, for events located on it
            for i in range(size):
                for k in range(order + 1):
                    kept[counts[1], i, k] = tc[i, k]
        evaluate(tc, size, order, h, work, 0)
        for i in range(size):
            if not math.isfinite(work[i, 0]):
                return 3
        t_next = t_end if last else t + h
        while counts[2] < t_eval.shape[0]:
            te = t_eval[counts[2]]
            if (te > t_next) if forward else (te < t_next):
                break
            evaluate(tc, size, order, te - t, out, counts[2])
            counts[2] += 1
        for i in range(size):
            tc[i, 0] = work[i, 0]
        t = t_next
        clock[0] = t
        counts[0] += 1
        if keep:
            ts[counts[1]] = t
            for i in range(size):
                ys[counts[1], i] = tc[i, 0]
            counts[1] += 1
    return 1 if t == t_end else 0

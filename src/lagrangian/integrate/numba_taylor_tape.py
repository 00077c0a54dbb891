"""Taylor coefficients of any system from its tape as data: the compact mode, one module for
every system.

For a large system the printed coefficients of :mod:`lagrangian.codegen.taylor_numba` are
thousands of lines (a 10-link chain: 1214 operations, 6880 lines), which numba compiles for
minutes.  Here the tape is an array and one loop walks it order by order (as heyoka's
compact mode does): the same recurrences, the operation's kind chosen per operation,
compiled once per machine (this text goes into the code cache as it is).

    coefficients(t, c, order, tc, flat, program, exponents)

``program`` (int64, rows of OPERATION_WIDTH): kind, the row written, the two operands
(a series' row, or -1 - j for the constant c[j]); then one row more per state element
whose rate it names the same way, and a last row (time row, 1 where time is used).
``exponents`` holds ``pow``'s exponent per operation; ``flat`` (the printed modules'
view of ``tc``) is not read here.  This module itself is never run.
"""

import math

from numba import njit, uint64

#: Columns of a row of ``program``.
OPERATION_WIDTH = 4
#: The kinds, in the order of lagrangian.integrate.taylor_compiled.KINDS.
ADD, SUB, MUL, SQUARE, DIV, NEG, SQRT, POW, EXP, LOG, SINCOS, SINHCOSH = range(12)


@njit(cache=True, _nrt=False, error_model="numpy")
def operand(tc, c, where, k):  # pragma: no cover - compiled by numba
    """Coefficient k of an operand: a series' row, or a constant at order 0 only."""
    if where >= 0:
        return tc[where, k]
    return c[-1 - where] if k == 0 else 0.0


@njit(cache=True, _nrt=False, error_model="numpy")
def order_zero(tc, c, kind, w, a, b, exponent):  # pragma: no cover - compiled by numba
    u = operand(tc, c, a, 0)
    if kind == ADD:
        tc[w, 0] = u + operand(tc, c, b, 0)
    elif kind == SUB:
        tc[w, 0] = u - operand(tc, c, b, 0)
    elif kind == MUL:
        tc[w, 0] = u * operand(tc, c, b, 0)
    elif kind == SQUARE:
        tc[w, 0] = u * u
    elif kind == DIV:
        tc[w, 0] = u / operand(tc, c, b, 0)
    elif kind == NEG:
        tc[w, 0] = -u
    elif kind == SQRT:
        tc[w, 0] = math.sqrt(u)
    elif kind == POW:
        tc[w, 0] = u**exponent
    elif kind == EXP:
        tc[w, 0] = math.exp(u)
    elif kind == LOG:
        tc[w, 0] = math.log(u)
    elif kind == SINCOS:
        tc[w, 0] = math.sin(u)
        tc[w + 1, 0] = math.cos(u)
    else:
        tc[w, 0] = math.sinh(u)
        tc[w + 1, 0] = math.cosh(u)


@njit(cache=True, _nrt=False, error_model="numpy")
def order_k(tc, c, kind, w, a, b, exponent, k):  # pragma: no cover - compiled by numba
    """Coefficient k >= 1 of one operation (the recurrences of
    :mod:`lagrangian.codegen.taylor_numba`), unsigned indices as there."""
    one = uint64(1)
    if kind in (ADD, SUB):
        u = tc[a, k] if a >= 0 else 0.0
        v = tc[b, k] if b >= 0 else 0.0
        tc[w, k] = u + v if kind == ADD else u - v
    elif kind == NEG:
        tc[w, k] = -tc[a, k]
    elif kind == MUL:
        if a < 0:
            tc[w, k] = c[-1 - a] * tc[b, k]
        elif b < 0:
            tc[w, k] = c[-1 - b] * tc[a, k]
        else:
            s = 0.0
            for j in range(k + one):
                s += tc[a, j] * tc[b, k - j]
            tc[w, k] = s
    elif kind == SQUARE:
        s = 0.0
        for j in range(k + one):
            s += tc[a, j] * tc[a, k - j]
        tc[w, k] = s
    elif kind == DIV:
        if b < 0:
            tc[w, k] = tc[a, k] / c[-1 - b]
        else:
            s = tc[a, k] if a >= 0 else 0.0
            for j in range(one, k + one):
                s -= tc[b, j] * tc[w, k - j]
            tc[w, k] = s / tc[b, 0]
    elif kind == SQRT:
        s = tc[a, k]
        for j in range(one, k):
            s -= tc[w, j] * tc[w, k - j]
        tc[w, k] = s / (2.0 * tc[w, 0])
    elif kind == POW:
        s = 0.0
        for j in range(k):
            s += (exponent * (k - j) - j) * tc[a, k - j] * tc[w, j]
        tc[w, k] = s / k / tc[a, 0]
    elif kind == EXP:
        s = 0.0
        for j in range(one, k + one):
            s += j * tc[a, j] * tc[w, k - j]
        tc[w, k] = s / k
    elif kind == LOG:
        s = 0.0
        for j in range(one, k):
            s += j * tc[w, j] * tc[a, k - j]
        tc[w, k] = (tc[a, k] - s / k) / tc[a, 0]
    else:  # the sin/cos and sinh/cosh pairs
        s = 0.0
        r = 0.0
        for j in range(one, k + one):
            d = j * tc[a, j]
            s += d * tc[w + 1, k - j]
            r += d * tc[w, k - j]
        tc[w, k] = s / k
        tc[w + 1, k] = (-r if kind == SINCOS else r) / k


@njit(cache=True, _nrt=False, error_model="numpy")
def coefficients(t, c, order, tc, flat, program, exponents):  # pragma: no cover - numba
    """tc[i, 1..order] of the state rows for tc[:, 0] (see the module docstring)."""
    last = program.shape[0] - 1
    time_row, uses_time = program[last, 0], program[last, 1]
    size = program[last, 2]
    count = last - size
    if uses_time:
        tc[time_row, 0] = t
        tc[time_row, 1] = 1.0
        for k in range(2, order + 1):
            tc[time_row, k] = 0.0
    for k in range(uint64(order)):
        if k == 0:
            for m in range(count):
                order_zero(tc, c, program[m, 0], program[m, 1], program[m, 2], program[m, 3],
                           exponents[m])  # fmt: skip
        else:
            for m in range(count):
                order_k(tc, c, program[m, 0], program[m, 1], program[m, 2], program[m, 3],
                        exponents[m], k)  # fmt: skip
        for i in range(size):
            where = program[count + i, 0]
            tc[i, k + uint64(1)] = operand(tc, c, where, k) / (k + uint64(1))

"""The fixed-step schemes of the numba ensemble loop, one member's state at a time.

Each builder returns a :class:`Scheme` of three jitted functions that the
parallel loop of :mod:`.numba_backend` calls for one member:

    workspace()                       a tuple of the arrays the scheme keeps
                                      and works in (allocated once per member)
    init(t, y, p, work)               the scheme's state at the first step
    step(t, h, y, p, work, tol, floor, iterations) -> bool
                                      y (2n,) advanced by h in place; False
                                      when a Newton iteration did not converge

They are the numpy backend's schemes step for step, written for one state:
``rk4`` (the tableau of :mod:`lagrangian.integrate.tableaus`, M q'' = f solved
at each stage) and the two of :class:`~lagrangian.integrate.variational.Variational`,
``midpoint`` (Newton on the midpoint velocity, first guess, convergence test
and the velocity from the momenta as there) and ``stormer-verlet``.  The
linear solves are Gaussian elimination with partial pivoting
(:func:`lagrangian.numeric.numba_linalg.solver`, unrolled for the system's n),
so results equal numpy's LAPACK solves to rounding.  The expressions come from generated fillers
(:mod:`.scheme_expressions`, :func:`lagrangian.numeric.numba_source.load_functions`).
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from ..integrate import tableaus
from ..numeric.numba_linalg import solver


class Scheme(NamedTuple):
    workspace: object
    init: object
    step: object


@numba.njit(inline="always")
def _larger(a, b):  # pragma: no cover - compiled by numba
    """max(a, b) that keeps a NaN, as numpy's max does, so a NaN never converges."""
    return b if b > a or b != b else a


@numba.njit(inline="always")
def _converged(size, previous, scale, tol, floor):  # pragma: no cover - compiled by numba
    """variational._converged for one member: small, or stuck at the rounding floor."""
    small = size <= tol * scale or size == 0.0
    return small or (size >= previous and size <= floor * scale)


def rk4(fill, n: int) -> Scheme:
    """RK4 around ``fill(t, y, p, M, f)`` (the generated M and f of M q'' = f)."""
    solve = solver(n)
    a21, a32, a43 = (float(tableaus.RK4.a[i, i - 1]) for i in (1, 2, 3))
    b1, b2, b3, b4 = (float(b) for b in tableaus.RK4.b)
    c2, c3, c4 = (float(c) for c in tableaus.RK4.c[1:])
    m = 2 * n

    @numba.njit
    def workspace():  # pragma: no cover - compiled by numba
        k = (np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m))
        return (*k, np.empty((n, n)), np.empty(n))

    @numba.njit(inline="always")
    def derivative(t, y, p, matrix, force, out):  # pragma: no cover - compiled by numba
        fill(t, y, p, matrix, force)
        solve(matrix, force, out, n)
        for i in range(n):
            out[i] = y[n + i]

    @numba.njit
    def init(t, y, p, work):  # pragma: no cover - compiled by numba
        pass

    @numba.njit
    def step(t, h, y, p, work, tol, floor, iterations):  # pragma: no cover - compiled by numba
        k1, k2, k3, k4, stage, matrix, force = work
        derivative(t, y, p, matrix, force, k1)
        for i in range(m):
            stage[i] = y[i] + (h * a21) * k1[i]
        derivative(t + c2 * h, stage, p, matrix, force, k2)
        for i in range(m):
            stage[i] = y[i] + (h * a32) * k2[i]
        derivative(t + c3 * h, stage, p, matrix, force, k3)
        for i in range(m):
            stage[i] = y[i] + (h * a43) * k3[i]
        derivative(t + c4 * h, stage, p, matrix, force, k4)
        for i in range(m):
            y[i] = y[i] + h * (b1 * k1[i] + b2 * k2[i] + b3 * k3[i] + b4 * k4[i])
        return True

    return Scheme(workspace, init, step)


def midpoint(functions, n: int) -> Scheme:
    """The midpoint variational step; ``functions`` holds the generated fillers of the scheme."""
    solve = solver(n)
    momenta_of, momenta_force = functions.momenta, functions.momenta_force
    mass, jacobian = functions.mass, functions.jacobian

    @numba.njit
    def workspace():  # pragma: no cover - compiled by numba
        # kept: p_k, the last midpoint velocity, whether there is one; then scratch
        kept = (np.empty(n), np.empty(n), np.zeros(1, dtype=np.bool_))
        scratch = (np.empty(n), np.empty(2 * n), np.empty(n), np.empty(n), np.empty(n))
        return (*kept, *scratch, np.empty(n), np.empty((n, n)))

    @numba.njit
    def init(t, y, p, work):  # pragma: no cover - compiled by numba
        momenta_of(t, y, p, work[0])
        work[2][0] = False

    @numba.njit
    def step(t, h, y, p, work, tol, floor, iterations):  # pragma: no cover - compiled by numba
        kept, last, started, v, z, momenta, force, residual, change, matrix = work
        tm = t + h / 2
        for i in range(n):
            v[i] = 2 * y[n + i] - last[i] if started[0] else y[n + i]  # O(h^2) first guess
        previous = np.inf
        for iteration in range(iterations + 1):
            for i in range(n):
                z[i] = y[i] + (h / 2) * v[i]
                z[n + i] = v[i]
            momenta_force(tm, z, p, momenta, force)
            size = scale = 0.0
            for i in range(n):
                residual[i] = momenta[i] - (h / 2) * force[i] - kept[i]
                size = _larger(size, abs(residual[i]))
                scale = _larger(scale, _larger(abs(kept[i]), abs(momenta[i])))
            if _converged(size, previous, scale, tol, floor):
                break
            if iteration == iterations:
                return False
            previous = size
            jacobian(tm, z, p, h, matrix)
            solve(matrix, residual, change, 0)
            for i in range(n):
                v[i] -= change[i]
        for i in range(n):
            kept[i] = kept[i] + h * force[i]
            y[i] = y[i] + h * v[i]
            last[i] = v[i]
            z[i] = y[i]
            z[n + i] = v[i]
        started[0] = True
        # the velocity from the momenta: L_q'(q, q') = p_{k+1} by Newton with M, from v
        previous = np.inf
        for iteration in range(iterations + 1):
            momenta_of(t + h, z, p, momenta)
            size = scale = 0.0
            for i in range(n):
                residual[i] = momenta[i] - kept[i]
                size = _larger(size, abs(residual[i]))
                scale = _larger(scale, _larger(abs(kept[i]), abs(momenta[i])))
            if _converged(size, previous, scale, tol, floor):
                for i in range(n):
                    y[n + i] = z[n + i]
                return True
            if iteration == iterations:
                return False
            previous = size
            mass(t + h, z, p, matrix)
            solve(matrix, residual, change, 0)
            for i in range(n):
                z[n + i] -= change[i]
        return False

    return Scheme(workspace, init, step)


def stormer_verlet(functions, n: int) -> Scheme:
    """The explicit Stormer-Verlet step of separable systems (M constant: its inverse kept)."""
    solve = solver(n)
    mass, gradient = functions.mass, functions.gradient

    @numba.njit(inline="always")
    def apply(matrix, x, out):  # pragma: no cover - compiled by numba
        for i in range(n):
            total = 0.0
            for j in range(n):
                total += matrix[i, j] * x[j]
            out[i] = total

    @numba.njit
    def workspace():  # pragma: no cover - compiled by numba
        # kept: p_k, L_q(q_k), M^-1; then scratch
        kept = (np.empty(n), np.empty(n), np.empty((n, n)))
        return (*kept, np.empty(n), np.empty(2 * n), np.empty((n, n)), np.empty((n, n)))

    @numba.njit
    def init(t, y, p, work):  # pragma: no cover - compiled by numba
        momenta, force, inverse, unit, z, matrix, copy = work
        mass(t, y, p, matrix)
        for j in range(n):  # the inverse column by column
            for i in range(n):
                unit[i] = 1.0 if i == j else 0.0
                for k in range(n):
                    copy[i, k] = matrix[i, k]
            solve(copy, unit, z, 0)
            for i in range(n):
                inverse[i, j] = z[i]
        apply(matrix, y[n:], momenta)
        gradient(t, y, p, force)

    @numba.njit
    def step(t, h, y, p, work, tol, floor, iterations):  # pragma: no cover - compiled by numba
        momenta, force, inverse, half, z, _, _ = work
        for i in range(n):
            half[i] = momenta[i] + (h / 2) * force[i]
        apply(inverse, half, z[n:])
        for i in range(n):
            z[i] = y[i] + h * z[n + i]
        gradient(t + h, z, p, force)
        for i in range(n):
            momenta[i] = half[i] + (h / 2) * force[i]
            y[i] = z[i]
        apply(inverse, momenta, y[n:])
        return True

    return Scheme(workspace, init, step)


SCHEMES = {"rk4": rk4, "midpoint": midpoint, "stormer-verlet": stormer_verlet}

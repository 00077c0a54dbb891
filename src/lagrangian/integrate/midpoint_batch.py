"""The midpoint variational step over a batch of states, for NumPy and JAX alike.

The two Newton iterations of :mod:`.variational`'s midpoint scheme, written once over an
array namespace ``xp`` and a while loop with the signature of ``jax.lax.while_loop``
(:class:`ArrayNewton`): NumPy runs the loop in Python, stopping as soon as every member
has converged; JAX traces it into one XLA loop (:mod:`lagrangian.ensemble.jax_backend`).
The compiled languages print the same step from :mod:`lagrangian.codegen.steps`.

Per member, Newton stops (its value frozen) when the residual is ``tolerance`` relative
to the momenta, or when an update no longer shrinks it by ``STALL_RATIO`` below
``floor`` times the momenta times max(1, max |q|) (see :mod:`.variational`); members
still iterating after ``iterations`` updates have failed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

#: Below the floor, a Newton update that no longer shrinks the residual by this factor
#: has reached the rounding noise (Newton's iteration, converging, shrinks it far more).
#: Waiting for the noise to stop decreasing instead took up to max_newton updates, and a
#: long enough run of decreasing noise failed the step (float32 ensembles: one member
#: in about 10^9 steps).
STALL_RATIO = 0.5


class ArrayNewton(NamedTuple):
    """How the batched step runs: ``xp`` (numpy or jax.numpy), ``while_loop(condition,
    body, carry)``, ``solve(matrix (n, n, B), rhs (n, B)) -> x (n, B)``, and the Newton
    settings."""

    xp: Any
    while_loop: Callable
    solve: Callable
    tolerance: float
    floor: float
    iterations: int


class Solved(NamedTuple):
    """A Newton iteration's end: x (n, B), what the residual gave beside it (the force of
    the midpoint step), the members that failed, the updates made and the residual size."""

    x: Any
    extra: Any
    failed: Any
    updates: Any
    size: Any


def python_while(condition, body, carry):
    """``jax.lax.while_loop`` in Python (NumPy's: it stops as soon as it may)."""
    while condition(carry):
        carry = body(carry)
    return carry


def newton(settings: ArrayNewton, residual, jacobian, x) -> Solved:
    """Newton's method per member for ``residual(x) -> (r, scale, reach, extra) = 0`` with
    ``jacobian(x)`` (n, n, B), from ``x`` (n, B); see the module."""
    xp, solve = settings.xp, settings.solve
    tolerance, floor, iterations = settings.tolerance, settings.floor, settings.iterations

    def converged(size, previous, scale, reach):
        small = (size <= tolerance * scale) | (size == 0.0)
        return small | ((size >= STALL_RATIO * previous) & (size <= floor * scale * reach))

    r, scale, reach, extra = residual(x)
    size = xp.max(xp.abs(r), axis=0)
    active = ~converged(size, xp.inf, scale, reach)

    def more(carry):
        count, _, active, *_ = carry
        return (count < iterations) & xp.any(active)

    def update(carry):
        count, x, active, r, previous, _ = carry
        x = xp.where(active, x - solve(jacobian(x), r), x)
        r, scale, reach, extra = residual(x)
        size = xp.max(xp.abs(r), axis=0)
        return count + 1, x, active & ~converged(size, previous, scale, reach), r, size, extra

    count, x, active, _, size, extra = settings.while_loop(
        more, update, (0, x, active, r, size, extra)
    )
    return Solved(x, extra, active, count, size)


def midpoint_velocity(system, settings: ArrayNewton, t, h, q, w, p, last, params) -> Solved:
    """The midpoint velocity v of the step from (q, p) at t (L_q'(q_m, v) - (h/2)[L_q + Q]
    = p, q_m = q + (h/2) v), from the first guess 2 q' - ``last`` (``last``: the previous
    step's v; q' at the first step); ``extra``: L_q + Q at the midpoint."""
    xp = settings.xp
    tm = t + h / 2

    def residual(v):
        qm = q + (h / 2) * v
        momenta = system.momenta(tm, qm, v, params)
        force = system.lagrangian_gradient(tm, qm, v, params)
        force = force + system.nonconservative_forces(tm, qm, v, params)
        return momenta - (h / 2) * force - p, scale(xp, momenta, p), extent(xp, q), force

    def jacobian(v):
        """d(residual)/dv, (n, n, B); see :mod:`.variational`."""
        qm = q + (h / 2) * v
        mass = system.mass_matrix(tm, qm, v, params)
        p_q = system.momenta_jacobian_q(tm, qm, v, params)
        l_qq = system.lagrangian_hessian_q(tm, qm, v, params)
        f_q = system.nonconservative_forces_jacobian_q(tm, qm, v, params)
        f_v = system.nonconservative_forces_jacobian_v(tm, qm, v, params)
        skew = p_q - xp.swapaxes(p_q, 0, 1)
        return mass + (h / 2) * skew - (h * h / 4) * (l_qq + f_q) - (h / 2) * f_v

    return newton(settings, residual, jacobian, 2 * w - last)


def legendre_velocity(system, settings: ArrayNewton, t, q, p, guess, params) -> Solved:
    """q' with L_q'(q, q', t) = p, by Newton with M from ``guess`` (one update is exact
    for a quadratic L)."""
    xp = settings.xp

    def residual(u):
        momenta = system.momenta(t, q, u, params)
        return momenta - p, scale(xp, momenta, p), extent(xp, q), None

    return newton(settings, residual, lambda u: system.mass_matrix(t, q, u, params), guess)


def scale(xp, momenta, p):
    """max(max |p|, max |momenta|) per member: the size the residual is measured against."""
    return xp.maximum(xp.max(xp.abs(p), axis=0), xp.max(xp.abs(momenta), axis=0))


def extent(xp, q):
    """max(1, max |q|) per member: how the coordinates' rounding scales."""
    return xp.maximum(1.0, xp.max(xp.abs(q), axis=0))

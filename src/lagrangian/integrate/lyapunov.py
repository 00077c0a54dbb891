"""Lyapunov exponents: the mean exponential rates at which nearby motions separate.

Along a motion y(t) of y' = F(t, y), a small displacement w obeys the variational
equations w' = J(t, y) w, J = dF/dy the Jacobian of the flow.  Here J is
``compiled.rhs_jacobian``: the compiled symbolic derivative of the solved
accelerations (:mod:`lagrangian.numeric.dynamics`), not finite differences.  k
displacements W (2n x k) are integrated with the state by DOP853 (the extended
system [y, W], 2n (k + 1) equations; in its compiled loop, J generated beside the
equations, where numba is installed: :mod:`.numba_dop853`); every ``interval`` they are
re-orthonormalised, W = Q R, and the logarithms of |R_ii| are summed.  The
running sums divided by the elapsed time converge to the k largest exponents
lambda_1 >= ... >= lambda_k (Benettin, Galgani, Giorgilli & Strelcyn, Meccanica
15 (1980) 9-20 and 21-30; Shimada & Nagashima, Prog. Theor. Phys. 61 (1979)
1605).  With k = 2n, the whole spectrum: its sum is the time average of the
divergence tr J (exactly, since the R_ii multiply to det of the tangent map), 0
for a Hamiltonian flow, whose exponents come in pairs +-lambda.

The first ``transient`` time units carry the state only (it settles on its
attractor); the displacements start orthonormal, from a fixed seed, so a run is
repeatable.  Constrained systems are refused: their flow lives on the
constraint manifold and the stabilised equations add exponents of their own.
Defaults (echoed in the result): rtol 1e-9, atol 1e-11, interval 1.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError, setting
from ..provided import Provided
from .base import check_time_span, positive_setting, transient_setting
from .compiled_dop853 import MIN_FACTOR, TOO_SMALL_STEP, first_step, tangent_loop
from .guard import parameter_problem, start_problem

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

DEFAULT_RTOL = 1e-9
DEFAULT_ATOL = 1e-11
DEFAULT_INTERVAL = 1.0
#: The seed of the first displacements: fixed, so that a run is repeatable.
SEED = 20
#: Steps the compiled loop takes per call (an interval usually takes fewer).
STEPS_PER_CALL = 256


@dataclass(frozen=True)
class LyapunovSpectrum:
    """The k largest Lyapunov exponents of one motion and how their estimates converged.

    ``exponents`` (k,), largest first, 1 / time unit; ``times`` (m,) the times of the
    re-orthonormalisations after the transient; ``history`` (m, k) the estimates
    then (the last row is ``exponents``).
    """

    # drawn by output/, given by the facade (see lagrangian.provided)
    plot = Provided()

    exponents: np.ndarray
    times: np.ndarray
    history: np.ndarray
    coordinate_names: tuple[str, ...]
    initial: Mapping[str, float]
    parameters: Mapping[str, float]
    t_end: float
    transient: float
    interval: float
    rtol: float
    atol: float
    name: str = ""
    system: object = field(default=None, repr=False, compare=False)  # the model, if known

    @property
    def largest(self) -> float:
        return float(self.exponents[0])

    @property
    def count(self) -> int:
        return len(self.exponents)

    def settings(self) -> dict[str, float]:
        """The run's settings, as given or defaulted."""
        return {
            "t_end": self.t_end,
            "transient": self.transient,
            "interval": self.interval,
            "rtol": self.rtol,
            "atol": self.atol,
        }


def lyapunov_spectrum(
    compiled: CompiledSystem,
    *,
    t_end: float,
    count: int | None = None,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
    transient: float = 0.0,
    interval: float = DEFAULT_INTERVAL,
    rtol: float | None = None,
    atol: float | None = None,
    watch: Callable[[float], None] | None = None,
) -> LyapunovSpectrum:
    """The ``count`` largest exponents (default: all 2n) over t_end after ``transient``.

    ``initial`` and ``params`` as for :func:`~lagrangian.integrate.simulate`, and refused
    as it refuses them where the equations have no finite value at the start; ``watch``
    is told the time reached (transient included) during every interval, and may end
    the run by raising (its time budget).
    """
    if compiled.has_constraints:
        raise ModelError("Lyapunov exponents of constrained systems are not supported")
    size = 2 * compiled.n
    count = size if count is None else int(count)
    if not 1 <= count <= size:
        raise ModelError(
            f"the number of exponents must be from 1 to {size} (twice the coordinates), "
            f"not {count}",
            field=setting("count"),
        )
    check_time_span((0.0, t_end))
    transient = transient_setting(transient)
    interval = positive_setting("interval", interval)
    rtol = DEFAULT_RTOL if rtol is None else positive_setting("rtol", rtol)
    atol = DEFAULT_ATOL if atol is None else positive_setting("atol", atol)
    y0 = compiled.state_vector(initial)
    p = compiled.parameter_vector(params)
    # y' = NaN at the start: the adaptive step would shrink without end, never reaching
    # the end of an interval where the watch was told
    problem = parameter_problem(compiled, 0.0, y0, p) or start_problem(compiled, 0.0, y0, p)
    if problem is not None:
        raise ModelError(problem)
    flow = VariationalFlow(compiled, p, count, rtol, atol, watch)
    y = flow.state(0.0, transient, y0)
    start = transient
    displacements = np.linalg.qr(np.random.default_rng(SEED).normal(size=(size, count)))[0]
    sums = np.zeros(count)
    times, history = [], []
    t = start
    while t < start + t_end:
        t_next = min(t + interval, start + t_end)
        y, displacements = flow.extended(t, t_next, y, displacements)
        displacements, stretch = _orthonormalised(displacements, t_next)
        sums += np.log(stretch)
        t = t_next
        times.append(t)
        history.append(sums / (t - start))
    names = compiled.coordinate_names
    state_names = (*names, *(f"{q}_dot" for q in names))
    return LyapunovSpectrum(
        exponents=history[-1].copy(),
        times=np.array(times),
        history=np.array(history),
        coordinate_names=names,
        initial=dict(zip(state_names, map(float, y0), strict=True)),
        parameters=dict(zip(compiled.parameter_names, map(float, p), strict=True)),
        t_end=float(t_end),
        transient=transient,
        interval=interval,
        rtol=rtol,
        atol=atol,
        name=compiled.equations.system.name if compiled.derived else "",
        system=compiled.equations.system if compiled.derived else None,
    )


def _orthonormalised(displacements: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """(Q, |diag R|) of W = Q R; an error where W lost a direction (a zero stretch)."""
    q, r = np.linalg.qr(displacements)
    stretch = np.abs(np.diag(r))
    if not (np.all(np.isfinite(stretch)) and np.all(stretch > 0.0)):
        raise ModelError(
            f"the displacements collapsed or overflowed at t = {t:g}: "
            f"give a shorter {setting('interval')} between re-orthonormalisations"
        )
    return q, stretch


class VariationalFlow:
    """The state alone, or with k displacements (the variational equations), by DOP853:
    in its compiled loop of the variational equations where numba is installed
    (:func:`~.compiled_dop853.tangent_loop`, J generated from the symbolic Jacobian),
    else by SciPy's ``solve_ivp`` over ``rhs`` and ``rhs_jacobian``; the same steps.
    ``watch`` is told the time reached as the steps go (a transient of 1e12 is one
    solve: told only at its end, its budget was never judged)."""

    def __init__(
        self, compiled: CompiledSystem, params: np.ndarray, count: int, rtol, atol, watch=None
    ):
        self._compiled = compiled
        self._params = np.ascontiguousarray(params, dtype=float)
        self._size = 2 * compiled.n
        self._count = count
        self._rtol, self._atol = rtol, atol
        self._first_step: float | None = None
        self._loop = tangent_loop(compiled)
        self._watch = watch

    def _solve(self, t0: float, t1: float, z0: np.ndarray) -> np.ndarray:
        """z(t1) from z(t0) = z0, z the state with or without the displacements."""
        solve = self._by_scipy if self._loop is None else self._by_loop
        z, times = solve(t0, t1, z0)
        if not np.all(np.isfinite(z)):
            raise ModelError(
                f"the integration failed at t = {times[-1]:g}: the state is not finite"
            )
        steps = np.diff(times)
        # the next interval starts with the last full step (the final one may be cut short)
        self._first_step = float(steps[-2] if len(steps) > 1 else steps[-1])
        return z

    def _by_scipy(self, t0: float, t1: float, z0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z(t1), the times of the steps) by SciPy's DOP853."""
        from scipy.integrate import solve_ivp

        compiled, params, size, watch = self._compiled, self._params, self._size, self._watch

        def function(t: float, z: np.ndarray) -> np.ndarray:
            if watch is not None:
                watch(t)
            y = z[:size]
            slope = compiled.rhs(t, y, params)
            if z.shape[0] == size:
                return slope
            w = z[size:].reshape(size, -1)
            tangent = compiled.rhs_jacobian(t, y, params) @ w
            return np.concatenate((slope, tangent.ravel()))

        options = {} if self._first_step is None else {"first_step": self._first_step}
        solution = solve_ivp(
            function, (t0, t1), z0, method="DOP853", rtol=self._rtol, atol=self._atol, **options
        )
        if solution.status != 0:
            raise ModelError(
                f"the integration failed at t = {solution.t[-1]:g}: {solution.message}"
            )
        return solution.y[:, -1], solution.t

    def _by_loop(self, t0: float, t1: float, z0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z(t1), the times of the last steps) by the compiled loop: SciPy's steps."""
        loop, params, rtol, atol = self._loop, self._params, self._rtol, self._atol
        watch = self._watch
        z = np.array(z0, dtype=float)
        flags = np.zeros(1, dtype=np.int64)

        def slope(t: float, y: np.ndarray) -> np.ndarray:
            out = np.empty_like(y)
            loop.slope(t, y, params, out, flags)
            return out

        f = slope(t0, z)
        if self._first_step is None:
            step = first_step(slope, t0, z, f, t1, rtol, atol)
        else:
            step = min(self._first_step, t1 - t0)
        clock = np.array([t0, step])
        counts = np.zeros(4, dtype=np.int64)
        size = z.shape[0]
        ends, ys = np.empty(STEPS_PER_CALL), np.empty((STEPS_PER_CALL, size))
        no_grid, no_rows, no_slopes = np.zeros(0), np.empty((0, size)), np.empty((0, 7, size))
        times, status = [t0], 0
        while status == 0:
            try:
                status = loop.advance(
                    clock, z, f, params, t1, rtol, atol, False, no_grid, no_rows, ends, ys,
                    no_rows, no_slopes, counts, flags,
                )  # fmt: skip
            except ZeroDivisionError:  # NumPy's inf: rejected, as SciPy rejects a NaN error
                flags[0], counts[3] = 1, 1
                clock[1] *= MIN_FACTOR
            times.extend(ends[: counts[1]][-2:])
            counts[1] = 0
            if watch is not None:
                watch(float(clock[0]))
        if status == 2:
            raise ModelError(f"the integration failed at t = {clock[0]:g}: {TOO_SMALL_STEP}")
        return z, np.array(times[-3:])

    def state(self, t0: float, t1: float, y0: np.ndarray) -> np.ndarray:
        """y(t1) from y(t0) = y0."""
        return y0 if t1 <= t0 else self._solve(t0, t1, y0)

    def extended(
        self, t0: float, t1: float, y0: np.ndarray, w0: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """(y(t1), W(t1)) of y' = F(t, y), W' = J(t, y) W."""
        size, count = self._size, self._count
        z = self._solve(t0, t1, np.concatenate((y0, w0.ravel())))
        return z[:size], z[size:].reshape(size, count)


class TangentFlow:
    """The state with one displacement, z = [y, w] (4n[, B]), as a system an explicit
    Runge-Kutta method steps unchanged: ``rhs(t, z, params)`` = [F(t, y), J(t, y) w].

    The ensemble's ``lyapunov`` observable steps it with the members' own method and
    renormalises w after every step (:meth:`renormalised`); the largest exponent is the
    mean of the logarithms of the stretches per unit time.
    """

    def __init__(self, compiled: CompiledSystem):
        self.compiled = compiled
        self.size = 2 * compiled.n

    def start(self, y: np.ndarray) -> np.ndarray:
        """z at the start: y with the unit displacement along (1, ..., 1) / sqrt(2n)."""
        w = np.full_like(y, 1.0 / np.sqrt(self.size))
        return np.concatenate((y, w), axis=0)

    def rhs(self, t, z, params):
        y, w = z[: self.size], z[self.size :]
        jacobian = self.compiled.rhs_jacobian(t, y, params)
        tangent = np.einsum("ij...,j...->i...", jacobian, w)
        return np.concatenate((self.compiled.rhs(t, y, params), tangent), axis=0)

    def renormalised(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(z with |w| = 1, log |w| before): the stretch of the last step per member."""
        w = z[self.size :]
        norm = np.sqrt(np.sum(w * w, axis=0))
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.concatenate((z[: self.size], w / norm), axis=0), np.log(norm)

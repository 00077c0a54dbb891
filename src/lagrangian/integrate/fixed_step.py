"""The driver shared by fixed-step methods: step grid, projection, events, dense output.

A fixed-step method advances from t0 to t_end on the grid t_k = t0 + k dt,
k = 0..N-1, then one last (possibly shorter) step lands exactly on t_end
(N = ceil((t_end - t0)/dt), with a relative slack of 1e-9 so that a span that
is a whole number of steps up to rounding gets no sliver step).  Subclasses
implement ``init`` (their internal state, e.g. momenta) and ``step``.

After every step the state of a constrained system is projected back onto
the constraint manifold (``compiled.project``), so the constraint drift stays
at the projection's accuracy instead of growing.  Outputs are the step points,
or, with ``t_eval``, the cubic Hermite interpolant between them (values and
y' = rhs at both ends; error O(dt^4), below the error of the methods here).
Without a given step, :func:`~lagrangian.integrate.step_size.fixed_step_for` chooses
it from the motion's time scale (``default_omega_dt`` / ω, at most
(t_end - t0) / 1000, ``DEFAULT_STEPS``), and checks a given one against the
method's ``stability_limit``; ``configure`` alone takes (t_end - t0) / 1000.

The run fails (status ``failed``, the message naming the time and the state;
see :mod:`lagrangian.integrate.guard`) where y' is not finite at the start, where
a step ends on a state that is not finite, and, checked on the steps once the
run is done, at the first step that breaks the energy balance (the output then
ends where that step began).
"""

from __future__ import annotations

import abc
import itertools
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..errors import setting
from ..trajectory import EventRecord
from .base import (
    AbstractIntegrator,
    IntegrationResult,
    Run,
    Status,
    Work,
    check_time_span,
    positive_setting,
    reject_settings,
)
from .compiled_loop import CompiledLoop, Newton, Unavailable, compiled_loop
from .events import EventWatcher, hermite, hermite_at
from .guard import energy_jump, state_problem
from .memory import step_count

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem


class StepFailure(Exception):
    """Raised by ``step`` when it cannot take the step (e.g. Newton did not converge)."""


def step_grid(t0: float, t_end: float, dt: float) -> np.ndarray:
    """t0, t0 + dt, ..., t_end: N = ceil((t_end - t0)/dt) steps, the last one ending at t_end."""
    count = step_count(t0, t_end, dt)
    grid = t0 + dt * np.arange(count + 1, dtype=float)
    grid[-1] = t_end
    return grid


def led_grid(t_end: float, dt: float, lead: float = 0.0, lead_steps: int = 0) -> np.ndarray:
    """The grid from t = 0 of an ensemble that keeps states at a phase: ``lead_steps``
    equal steps over [0, ``lead``], then :func:`step_grid` from ``lead`` to ``t_end``
    (steps of ``dt`` from ``lead``); without a lead, ``step_grid(0, t_end, dt)``.

    With ``lead_steps`` = the states kept every so many steps and ``dt`` = period /
    ``lead_steps``, the kept states fall at t = 0, then at lead + k period: a strobe at
    the phase ``lead`` on a fixed step (:mod:`lagrangian.ensemble.bifurcation`).  The lead's
    steps are no longer than ``dt`` when lead < period.  A lead of all of t_end is the
    lead's steps alone."""
    if lead <= 0.0:
        return step_grid(0.0, t_end, dt)
    head = lead * np.arange(lead_steps, dtype=float) / lead_steps
    tail = step_grid(lead, t_end, dt) if t_end > lead else np.array([t_end], dtype=float)
    return np.concatenate([head, tail])


@dataclass(frozen=True)
class AbstractFixedStepIntegrator(AbstractIntegrator):
    """A method taking steps of a fixed size ``dt`` (see the module docstring)."""

    dt: float
    adaptive: ClassVar[bool] = False
    batched: ClassVar[bool] = True
    DEFAULT_STEPS: ClassVar[int] = 1000
    #: ω·dt of the step chosen when none is given (ω: the motion's rate; integrate.step_size)
    default_omega_dt: ClassVar[float]
    #: ω·dt at which the method stops being stable on an oscillation of angular frequency ω
    stability_limit: ClassVar[float]

    def __post_init__(self) -> None:
        positive_setting("dt", self.dt)

    @classmethod
    def configure(cls, *, t_span, dt=None, rtol=None, atol=None):
        reject_settings(
            cls.name, f"a fixed-step method: give {setting('dt')}", rtol=rtol, atol=atol
        )
        t0, t1 = check_time_span(t_span)
        return cls(dt=(t1 - t0) / cls.DEFAULT_STEPS if dt is None else positive_setting("dt", dt))

    def settings(self) -> dict[str, object]:
        return {"method": self.name, "dt": self.dt}

    def kept_steps(self, t_span: tuple[float, float]) -> int:
        return step_count(*t_span, self.dt)

    @abc.abstractmethod
    def init(
        self, compiled: CompiledSystem, t: float, y: np.ndarray, params: np.ndarray, work: Work
    ) -> object:
        """The method's own state at the start (None when it needs none)."""

    @abc.abstractmethod
    def step(
        self,
        compiled: CompiledSystem,
        t: float,
        h: float,
        y: np.ndarray,
        state: object,
        params: np.ndarray,
        work: Work,
    ) -> tuple[np.ndarray, object]:
        """(y, state) at t + h from (y, state) at t; raise StepFailure when impossible."""

    def printed_scheme(self, compiled: CompiledSystem) -> str | None:
        """The scheme of :mod:`lagrangian.codegen.steps` this method takes on ``compiled``
        (then a compiled backend runs its whole loop in generated code), or None."""
        return None

    def newton_settings(self) -> Newton:
        """The settings of the printed scheme's Newton iterations (none by default)."""
        return Newton(tol=0.0, floor=0.0, stall=0.0, iterations=0)

    def prepare(self, compiled: CompiledSystem, y0: np.ndarray, params: np.ndarray) -> str | None:
        """On the numba backend, the loop of a single run made or loaded (see the base class
        and :meth:`.CompiledLoop.prepare`); nothing is said of it (None), as before."""
        if np.ndim(y0) != 1 or np.ndim(params) != 1:
            return None
        loop = compiled_loop(compiled, self.printed_scheme(compiled), self.newton_settings())
        if isinstance(loop, CompiledLoop):
            loop.prepare(y0, params)
        return None

    def integrate(self, compiled: CompiledSystem, run: Run) -> IntegrationResult:
        t0, t1, y, params, events = run.t0, run.t1, run.y0, run.params, run.events
        work = Work()
        project = compiled.project if compiled.has_constraints else None

        def derivative(t: float, state: np.ndarray) -> np.ndarray:
            work.rhs_evaluations += 1
            return compiled.rhs(t, state, params)

        watcher = EventWatcher(events, params, t0, y) if events else None
        march = _March(compiled, params, run.watch, watcher, derivative, project)
        grid = step_grid(t0, t1, self.dt)
        if run.problem is not None:
            t_out, y_out, status, message = grid[:1], y[..., None], Status.FAILED, run.problem
        else:
            loop = None
            if y.ndim == 1 and np.ndim(params) == 1:
                scheme = self.printed_scheme(compiled)
                loop = compiled_loop(compiled, scheme, self.newton_settings())
            try:
                if loop is None:
                    raise Unavailable
                t_out, y_out, status, message = self._compiled(loop, grid, y, work, march)
            except Unavailable:  # step by step in Python (which reports the inf or NaN)
                work = Work()
                if events:
                    march.watcher = EventWatcher(events, params, t0, y)
                t_out, y_out, status, message = self._stepped(grid, y, work, march)
        records = march.watcher.records(y.shape[0]) if events else ()
        jump = energy_jump(compiled, t_out, y_out, params) if y_out.ndim == 2 else None
        if jump is not None:  # the run ends at the start of the step that broke the balance
            k, message = jump
            status, t_out, y_out = Status.FAILED, t_out[: k + 1], y_out[..., : k + 1]
            records = tuple(_until(record, t_out[-1]) for record in records)
        if run.t_eval is not None:
            slopes_of = _batched_slopes(compiled, t_out, y_out, params, work)
            t_out, y_out = _dense(t_out, y_out, run.t_eval, status, derivative, slopes_of)
            if project is not None:
                columns = [project(t, y_out[..., k], params) for k, t in enumerate(t_out)]
                y_out = np.stack(columns, axis=-1) if columns else y_out
        return IntegrationResult(
            t=t_out,
            y=y_out,
            status=status,
            message=message,
            steps=work.steps,
            rhs_evaluations=work.rhs_evaluations,
            jacobian_evaluations=work.jacobian_evaluations,
            events=records,
            settings=self.settings_for(compiled),
        )

    def _stepped(self, grid, y, work, march: _March):
        """(t, y, status, message) of the steps taken one by one in Python along ``grid``."""
        compiled, params, project = march.compiled, march.params, march.project
        times, states = [grid[0]], [y]
        status, message = Status.SUCCESS, "reached the end time"
        solver_state = self.init(compiled, grid[0], y, params, work)
        for ta, tb in itertools.pairwise(grid):
            try:
                y_new, solver_state = self.step(
                    compiled, ta, tb - ta, y, solver_state, params, work
                )
            except StepFailure as failure:
                status, message = Status.FAILED, f"{failure} at t = {ta:.17g}"
                break
            problem = state_problem(compiled, ta, y, y_new)
            if problem is not None:
                status, message = Status.FAILED, problem
                break
            if project is not None:
                y_new = project(tb, y_new, params)
            work.steps += 1
            if march.watch is not None:
                march.watch(tb)
            hit = march.event(ta, y, tb, y_new)
            if hit is not None:
                times.append(hit[0])
                states.append(hit[1])
                status, message = Status.EVENT, march.stopped(hit[0])
                break
            times.append(tb)
            states.append(y_new)
            y = y_new
        return np.array(times), np.stack(states, axis=-1), status, message

    def _compiled(self, loop: CompiledLoop, grid, y, work, march: _March):
        """As :meth:`_stepped`, the steps taken by the compiled loop, a chunk at a time."""
        hits: list[tuple[int, tuple[float, np.ndarray]]] = []

        def chunk(states: np.ndarray, start: int, stop: int) -> bool:
            """Watch the steps start..stop - 1 just taken; True: stop at a terminal event."""
            if march.watch is not None:
                march.watch(float(grid[stop]))
            if march.watcher is not None:
                for k in range(start, stop):
                    hit = march.event(grid[k], states[k], grid[k + 1], states[k + 1])
                    if hit is not None:
                        hits.append((k, hit))
                        return True
            return False

        marched = loop.march(grid, y, march.params, work, chunk)
        k = marched.reached
        t_out, y_out = grid[: k + 1], marched.states[: k + 1].T
        if hits:
            k, (at, state) = hits[0]
            t_out = np.append(grid[: k + 1], at)
            y_out = np.concatenate([marched.states[: k + 1].T, state[:, None]], axis=1)
            return t_out, y_out, Status.EVENT, march.stopped(at)
        if not marched.failed:
            return t_out, y_out, Status.SUCCESS, "reached the end time"
        if marched.failed == 3:
            message = state_problem(march.compiled, grid[k], y_out[:, k], marched.last)
        else:
            message = f"{self.failure_text(marched.failed)} at t = {grid[k]:.17g}"
        return t_out, y_out, Status.FAILED, message

    def failure_text(self, code: int) -> str:
        """What failure ``code`` (1, 2) of the printed scheme's step means (see its Newton)."""
        return f"the step failed (code {code})"


def _batched_slopes(compiled, times, states, params, work):
    """y' at given steps of a single run in one batched call (None for a batch of runs)."""
    if states.ndim != 2 or np.ndim(params) != 1:
        return None

    def slopes_of(ks: np.ndarray) -> np.ndarray:
        work.rhs_evaluations += int(ks.shape[0])
        return np.asarray(compiled.rhs(times[ks], states[:, ks], params), dtype=float)

    return slopes_of


@dataclass
class _March:
    """What both ways of stepping share: the system, the watch and the events."""

    compiled: CompiledSystem
    params: np.ndarray
    watch: Callable[[float], None] | None
    watcher: EventWatcher | None
    derivative: Callable[[float, np.ndarray], np.ndarray]
    project: Callable | None

    def event(self, ta, ya, tb, yb) -> tuple[float, np.ndarray] | None:
        """(time, state) of a terminal event in the step from (ta, ya) to (tb, yb), or None."""
        if self.watcher is None:
            return None
        hit = self.watcher.step(ta, ya, tb, yb, self.derivative)
        if hit is None or self.project is None:
            return hit
        return hit[0], self.project(hit[0], hit[1], self.params)

    @staticmethod
    def stopped(t: float) -> str:
        return f"stopped by a terminal event at t = {t:.17g}"


def _until(record: EventRecord, t: float) -> EventRecord:
    """The occurrences of ``record`` up to time ``t``."""
    kept = record.times <= t
    return EventRecord(record.name, record.times[kept], record.states[:, kept])


def _dense(times, states, t_eval, status, derivative, slopes_of=None):
    """States at ``t_eval`` (up to the last step reached) by cubic Hermite interpolation.

    ``slopes_of(ks)``, where given, gives y' at the steps ``ks`` at once (2n, K): a single
    run's interpolation is then done for every output time together (one batched y' of the
    steps needed, not two calls of ``derivative`` from Python per output time: 90 us an
    output time before issue 36)."""
    inside = t_eval[t_eval <= times[-1]]
    if slopes_of is not None and states.ndim == 2 and len(times) > 1:
        values = _dense_at_once(times, states, inside, slopes_of)
        return _stopped(inside, values, times, states, status)
    slopes: dict[int, np.ndarray] = {}

    def slope(k: int) -> np.ndarray:
        if k not in slopes:
            slopes[k] = derivative(times[k], states[..., k])
        return slopes[k]

    columns = []
    for t in inside:
        k = int(np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2))
        if len(times) == 1 or t == times[k]:
            columns.append(states[..., k])
        elif t == times[k + 1]:
            columns.append(states[..., k + 1])
        else:
            ya, yb = states[..., k], states[..., k + 1]
            columns.append(hermite(times[k], ya, slope(k), times[k + 1], yb, slope(k + 1), t))
    empty = np.empty((*states.shape[:-1], 0))
    values = np.stack(columns, axis=-1) if columns else empty
    return _stopped(inside, values, times, states, status)


def _dense_at_once(times, states, inside, slopes_of) -> np.ndarray:
    """:func:`_dense`'s values of a single run (states (2n, T), two steps or more)."""
    k = np.clip(np.searchsorted(times, inside, side="right") - 1, 0, len(times) - 2)
    left, right = inside == times[k], inside == times[k + 1]
    between = ~(left | right)
    values = np.where(left, states[:, k], states[:, k + 1])
    if np.any(between):
        kb = k[between]
        needed = np.unique(np.concatenate([kb, kb + 1]))
        slopes = slopes_of(needed)
        at = np.searchsorted(needed, kb)
        f0, f1 = slopes[:, at], slopes[:, at + 1]
        h = times[kb + 1] - times[kb]
        s = (inside[between] - times[kb]) / h
        values[:, between] = hermite_at(s, h, states[:, kb], f0, states[:, kb + 1], f1)
    return values


def _stopped(inside, values, times, states, status):
    """(times, values) with where a run that did not succeed stopped as the last output."""
    if status is not Status.SUCCESS and (not inside.size or inside[-1] < times[-1]):
        inside = np.append(inside, times[-1])  # where it stopped: the last output
        values = np.concatenate([values, states[..., -1:]], axis=-1)
    return inside, values

"""Runs with contacts (``[[impacts]]``): free flight, impacts, chattering, held contacts.

The motion is integrated in segments.  A free segment is the method's own run (the compiled
DOP853 loop where it applies, else SciPy's loop) with each open contact's gap as a terminal
event (direction -1), located on the step's dense interpolant (Brent's method to 4 eps, see
:mod:`.compiled_dop853` and :mod:`.events`).  At the event the velocities jump by the impact
law (:mod:`.impact_law`: Newton's restitution in the mass metric; contacts closed at one
instant resolved sequentially in order of approach velocity) and a new segment starts from
the impact state.

**Chattering.** A ball coming to rest bounces infinitely often in finite time.  When a
contact's impact follows its previous one within :data:`CHATTER_FRACTION` of the run's
span (1e-6: 1e-5 s for t_end = 10), or its restitution is 0, the contact is *held*: the
impact is made plastic (e = 0, g' = 0) and g = 0 is kept as a constraint with its
multiplier lambda (:func:`.impact_law.held_multipliers`), integrated by SciPy's DOP853 in
Python (the compiled loop has no constraints yet).  The contact is released where lambda
falls through 0 (it would have to pull), or where another impact makes it separate.

What the run records (:class:`~lagrangian.trajectory.ImpactRecord`): each impact's time,
contact, velocities before and after and energy before and after, and each hold's span.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..trajectory import EventRecord, ImpactRecord
from .base import AbstractIntegrator, IntegrationResult, Status
from .events import Event, named
from .impact_law import contact_set, held_multipliers, plastic, resolve, touching

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem
    from ..numeric.impacts import ContactFunctions

#: An impact within this fraction of the run's span after the contact's previous one
#: starts a held (persistent) contact: the chattering of a body coming to rest.
CHATTER_FRACTION = 1e-6
#: Impacts of one run at most (a run that would take more is stopped, saying so).
MAX_IMPACTS = 1_000_000
#: Contacts at rest at one instant up to which every set is tried for the held ones (2^k
#: sets); above it the held set is found greedily (:meth:`ImpactRun._greedy_set`).
MAX_ENUMERATED = 8
#: Tolerances of the held segments where the method has none (fixed-step methods).
HELD_RTOL, HELD_ATOL = 1e-10, 1e-12


@dataclass
class _Pieces:
    """What the segments produced so far."""

    times: list[np.ndarray] = field(default_factory=list)
    states: list[np.ndarray] = field(default_factory=list)
    impacts: list[ImpactRecord] = field(default_factory=list)
    holds: list[tuple[str, float, float]] = field(default_factory=list)
    events: dict[str, tuple[list, list]] = field(default_factory=dict)
    steps: int = 0
    rhs_evaluations: int = 0


class ImpactRun:
    """One run of a system with contacts (see the module docstring)."""

    def __init__(
        self,
        integrator: AbstractIntegrator,
        compiled: CompiledSystem,
        contacts: ContactFunctions,
        params: np.ndarray,
        t_span: tuple[float, float],
        events: Sequence[Event] = (),
        watch: Callable[[float], None] | None = None,
    ):
        self.integrator, self.compiled, self.contacts = integrator, compiled, contacts
        self.params = np.asarray(params, dtype=float)
        self.t0, self.t1 = (float(t) for t in t_span)
        self.user_events = named(events)
        self.watch = watch
        self.restitution = contacts.restitutions(self.params)
        self.held = np.zeros(contacts.count, dtype=bool)
        self.last = np.full(contacts.count, -np.inf)  # each contact's last impact
        self.chatter = CHATTER_FRACTION * (self.t1 - self.t0)
        self.held_since = np.zeros(contacts.count)
        self.pieces = _Pieces()
        self._last_multipliers: tuple = (None, None)
        settings = integrator.settings()
        self.rtol = float(settings.get("rtol", HELD_RTOL))
        self.atol = float(settings.get("atol", HELD_ATOL))

    # -- the run ---------------------------------------------------------------
    def run(self, y0: np.ndarray, t_eval: np.ndarray | None) -> IntegrationResult:
        t, y = self.t0, np.array(y0, dtype=float)
        self._check_start(y)
        y = self._settle(t, y, ())
        status, message = Status.SUCCESS, ""
        first = True
        while True:
            outputs = None
            if t_eval is not None:
                outputs = t_eval[(t_eval >= t) if first else (t_eval > t)]
            segment = self._held(t, y, outputs) if self.held.any() else self._free(t, y, outputs)
            stop, kind, which, ts, ys = segment
            keep = np.ones(ts.shape[0], bool) if outputs is None else np.isin(ts, outputs)
            self.pieces.times.append(ts[keep])
            self.pieces.states.append(ys[:, keep])
            first = False
            if self.watch is not None:
                self.watch(stop[0])
            if kind in ("end", "failed", "event"):
                status = {"end": Status.SUCCESS, "failed": Status.FAILED, "event": Status.EVENT}
                status, message = status[kind], which
                break
            t, y = stop
            if kind == "release":  # the others held or not as the contact set says
                self._release(which, t)
                y = self._settle(t, y, (), released=which)
            else:
                y = self._settle(t, y, (which,))
            if len(self.pieces.impacts) > MAX_IMPACTS:
                status, message = Status.FAILED, f"more than {MAX_IMPACTS:,} impacts"
                break
        for k in np.flatnonzero(self.held):
            self._release(int(k), float(self.pieces.times[-1][-1]), end=True)
        return self._result(status, message)

    def _check_start(self, y: np.ndarray) -> None:
        gaps = self.contacts.gap_values(self.t0, y, self.params)
        for k, gap in enumerate(gaps):
            if gap < 0 and not touching(gaps[k : k + 1], y[: self.compiled.n])[0]:
                raise ModelError(
                    f"the initial state penetrates the contact '{self.contacts.names[k]}': "
                    f"its gap is {gap:.6g} < 0",
                    field=f"impacts[{k}].gap",
                )

    # -- segments --------------------------------------------------------------
    def _free(self, t, y, outputs):
        """A segment of the method's own run up to the first contact closing."""
        n = self.compiled.n
        gaps = self.contacts.gap_values(t, y, self.params)
        closed = touching(gaps, y[:n])
        shifts = _shifts(gaps, closed, y[:n])
        events = [
            Event(self._gap_event(k, shifts[k]), -1, True, f"contact__{k}")
            for k in range(self.contacts.count)
        ]
        try:
            result = self.integrator.solve(
                self.compiled, (t, self.t1), y, self.params, t_eval=outputs,
                events=[*events, *self.user_events], watch=self.watch,
            )  # fmt: skip
        except RuntimeError as error:  # Brent's method on a gap flat at its zero
            names = ", ".join(self.contacts.names)
            raise ModelError(
                f"a contact ({names}) could not be located after t = {t:.6g} ({error}): a gap "
                "must cross 0 with a nonzero gradient (y, not y^3)",
                source=getattr(self.compiled.equations.system, "source", None),
                field="impacts",
            ) from None
        self.pieces.steps += result.steps
        self.pieces.rhs_evaluations += result.rhs_evaluations
        contact_records = result.events[: len(events)]
        self._keep_user_events(result.events[len(events) :])
        ts, ys = result.t, result.y
        if result.status is Status.SUCCESS:
            return (self.t1, ys[:, -1]), "end", result.message, ts, ys
        if result.status is Status.FAILED:
            return (ts[-1], ys[:, -1]), "failed", result.message, ts, ys
        stop = _stop_of(contact_records)
        if stop is None:  # a terminal event of the user's
            return (ts[-1], ys[:, -1]), "event", result.message, ts, ys
        k, t_stop, y_stop = stop
        return (t_stop, y_stop), "impact", k, ts, ys

    def _gap_event(self, k: int, shift: float):
        """g_k + ``shift`` as an event function (see :func:`_shifts`)."""
        contacts = self.contacts

        def gap(t, y, params):
            return contacts.gap_values(t, y, params)[k] + shift

        return gap

    def _held(self, t, y, outputs):
        """A segment with the held contacts kept closed, by SciPy's DOP853 (in Python)."""
        from scipy.integrate import solve_ivp

        n, held = self.compiled.n, np.flatnonzero(self.held)
        free = np.flatnonzero(~self.held)
        gaps = self.contacts.gap_values(t, y, self.params)
        shifts = _shifts(gaps, touching(gaps, y[:n]), y[:n])

        def rhs(s, state):
            return np.concatenate([state[n:], self._accelerations(s, state, held)[0]])

        events = []
        for j in held:
            events.append(_scipy_event(lambda s, state, j=j: self._multiplier(s, state, held, j)))
        for k in free:
            gap = self._gap_event(int(k), shifts[k])
            events.append(_scipy_event(lambda s, state, gap=gap: gap(s, state, self.params)))
        if self.watch is not None:  # told the time at every step (a time budget, progress)
            watched = events[0]

            def first_event(s, state, watched=watched):
                self.watch(s)
                return watched(s, state)

            events[0] = _scipy_event(first_event)
        solution = solve_ivp(
            rhs, (t, self.t1), y, method="DOP853", rtol=self.rtol, atol=self.atol,
            t_eval=outputs, events=events,
        )  # fmt: skip
        # with outputs and none inside the segment, SciPy gives lists of no times
        ts = np.asarray(solution.t, dtype=float)
        ys = np.asarray(solution.y, dtype=float).reshape(2 * n, ts.shape[0])
        self.pieces.steps += int(ts.shape[0])
        self.pieces.rhs_evaluations += int(solution.nfev)
        if solution.status == -1:
            return (ts[-1], ys[:, -1]), "failed", solution.message, ts, ys
        if solution.status == 0:
            return (self.t1, ys[:, -1]), "end", solution.message, ts, ys
        found = [(float(times[0]), i) for i, times in enumerate(solution.t_events) if times.size]
        t_stop, i = min(found)
        y_stop = solution.y_events[i][0]
        if outputs is not None:
            ts, ys = ts[ts < t_stop], ys[:, ts < t_stop]
        if i < held.size:
            return (t_stop, y_stop), "release", int(held[i]), ts, ys
        return (t_stop, y_stop), "impact", int(free[i - held.size]), ts, ys

    def _accelerations(self, t, y, rows):
        n = self.compiled.n
        q, v = y[:n], y[n:]
        mass = np.asarray(self.compiled.mass_matrix(t, q, v, self.params), dtype=float)
        forcing = np.asarray(self.compiled.forcing(t, q, v, self.params), dtype=float)
        gradient, rate, curvature = self.contacts.geometry(t, y, self.params)
        gaps = self.contacts.gap_values(t, y, self.params)
        return held_multipliers(
            mass, forcing, gradient[rows], rate[rows], curvature[rows], gaps[rows], v
        )

    def _multiplier(self, t, y, rows, j):
        """lambda_j at (t, y) with ``rows`` held; the events of one step ask at the same
        state one after the other, so the last state's multipliers are kept."""
        key = (t, y.tobytes(), rows.tobytes())
        if self._last_multipliers[0] != key:
            self._last_multipliers = (key, self._accelerations(t, y, rows)[1])
        return float(self._last_multipliers[1][list(rows).index(j)])

    # -- impacts ---------------------------------------------------------------
    def _settle(
        self, t: float, y: np.ndarray, hit: tuple[int, ...], released: int | None = None
    ) -> np.ndarray:
        """The state after the impacts at (t, y), and the contacts held from there: ``hit``
        the contacts whose events fired, ``released`` one whose multiplier just fell to 0
        (not held again at once)."""
        n, compiled, p = self.compiled.n, self.compiled, self.params
        q, v = y[:n], y[n:]
        gaps = self.contacts.gap_values(t, y, p)
        closed = touching(gaps, q) | self.held
        closed[list(hit)] = True
        gradient, rate, _ = self.contacts.geometry(t, y, p)
        mass = np.asarray(compiled.mass_matrix(t, q, v, p), dtype=float)
        chattering = (t - self.last) < self.chatter
        restitution = np.where(self.held | chattering, 0.0, self.restitution)
        struck = set()

        def on_impact(k, before, after):
            energy = [float(compiled.energy(t, np.concatenate([q, w]), p)) for w in (before, after)]
            self.pieces.impacts.append(
                ImpactRecord(t, self.contacts.names[k], before.copy(), after.copy(), *energy)
            )
            struck.add(k)

        v = resolve(mass, gradient, rate, v, restitution, closed, on_impact)
        for k in struck:
            self.last[k] = t
        chattering &= closed  # closed again within the chatter interval of their last impact
        if np.count_nonzero(chattering) > 1:  # one after the other they would never settle
            v = self._plastic(t, y, mass, gradient, rate, v, np.flatnonzero(chattering))
        y = np.concatenate([q, v])
        speed = gradient @ v + rate
        resting = closed & (np.abs(speed) <= 1e-12 * (1 + np.max(np.abs(v))))
        if released is not None:
            resting[released] = False
        chosen = self._contact_set(t, y, np.flatnonzero(resting))
        for k in np.flatnonzero(self.held & ~chosen):  # opened by an impact, or would pull
            self._release(int(k), t)
        for k in np.flatnonzero(chosen & ~self.held):
            self.held[k], self.held_since[k] = True, t
        return y

    def _plastic(self, t, y, mass, gradient, rate, v, rows):
        """The contacts ``rows``, chattering together (a block settling flat on two corners,
        each landing again within the chatter interval), stopped at once: q' projected in
        the mass metric onto G q' + g_t = 0 for all of them.  Their speeds are those of the
        chattering, so the impulses are small; one may be slightly negative (the contact
        was about to open): it is the approximation that ends the alternation, as holding
        ends a single contact's chattering."""
        after, _ = plastic(mass, gradient[rows], rate[rows], v)
        n = self.compiled.n
        energy = [
            float(self.compiled.energy(t, np.concatenate([y[:n], w]), self.params))
            for w in (v, after)
        ]
        for k in rows:
            self.pieces.impacts.append(
                ImpactRecord(t, self.contacts.names[k], v.copy(), after.copy(), *energy)
            )
        return after

    def _contact_set(self, t: float, y: np.ndarray, resting: np.ndarray) -> np.ndarray:
        """Which of the closed contacts at rest (``resting``) are held (a boolean array):
        :func:`.impact_law.contact_set` with this state's geometry and multipliers."""
        chosen = np.zeros(self.contacts.count, dtype=bool)
        if resting.size:
            gradient, _, curvature = self.contacts.geometry(t, y, self.params)
            rows = contact_set(
                resting, gradient, curvature, lambda rows: self._accelerations(t, y, rows),
                enumerated=MAX_ENUMERATED,
            )  # fmt: skip
            chosen[rows] = True
        return chosen

    def _release(self, k: int, t: float, end: bool = False) -> None:
        self.pieces.holds.append((self.contacts.names[k], float(self.held_since[k]), float(t)))
        self.held[k] = False

    def _keep_user_events(self, records: Sequence[EventRecord]) -> None:
        for record in records:
            times, states = self.pieces.events.setdefault(record.name, ([], []))
            times.append(record.times)
            states.append(record.states)

    def _result(self, status: Status, message: str) -> IntegrationResult:
        pieces, size = self.pieces, 2 * self.compiled.n
        events = tuple(
            EventRecord(
                event.name,
                np.concatenate(pieces.events.get(event.name, ([np.empty(0)], []))[0]),
                np.concatenate(pieces.events[event.name][1], axis=1)
                if event.name in pieces.events
                else np.empty((size, 0)),
            )
            for event in self.user_events
        )
        return IntegrationResult(
            t=np.concatenate(pieces.times),
            y=np.concatenate(pieces.states, axis=1),
            status=status,
            message=message
            or "The solver successfully reached the end of the integration interval.",
            steps=pieces.steps,
            rhs_evaluations=pieces.rhs_evaluations,
            jacobian_evaluations=0,
            events=events,
            settings=self.integrator.settings(),
        )


def _shifts(gaps: np.ndarray, closed: np.ndarray, q: np.ndarray) -> np.ndarray:
    """What is added to each gap event of a segment: 0 for an open contact; for one closed at
    the start (|g| within TOUCH, e.g. just after its impact, where the located root leaves
    g = +-1e-16) enough that the start counts as open, |g| + 1e-15 (1 + |q|): it closes
    again when g falls below that, a time error of 1e-15 / |g'|."""
    floor = 1e-15 * (1.0 + float(np.max(np.abs(q), initial=0.0)))
    return np.where(closed, np.maximum(-gaps, 0.0) + floor, 0.0)


def _stop_of(records: Sequence[EventRecord]):
    """(contact, t, y) of the contact event that stopped a segment, or None."""
    found = [(float(r.times[-1]), k) for k, r in enumerate(records) if r.count]
    if not found:
        return None
    t, k = max(found)
    return k, t, records[k].states[:, -1]


def _scipy_event(function):
    function.terminal = True
    function.direction = -1
    return function

"""Events: times where a function of the state crosses zero.

An :class:`Event` g(t, y, params) -> float is *triggered* where g changes sign
along the motion; ``direction`` +1 keeps only crossings from negative to
positive, -1 only from positive to negative, 0 both; a ``terminal`` event stops
the integration at its first occurrence.  A zero at the start time is not an
occurrence (the motion must cross zero, not start there).

SciPy's methods locate events on their own dense output (:func:`scipy_event`).
Fixed-step methods (:class:`EventWatcher`) compare the signs of g at the two
ends of every step and locate a root on the cubic Hermite interpolant of the
step, built from y and y' = rhs(t, y) at both ends (local error O(h^4);
Hairer, Norsett & Wanner, *Solving ODEs I*, II.6), with Brent's method to
|dt| ~ 1e-15 |t|.  Two sign changes within one step cancel and go unseen.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..errors import ModelError
from ..trajectory import EventRecord

EventFunction = Callable[[float, np.ndarray, np.ndarray], float]  # (t, y, params)


@dataclass(frozen=True)
class Event:
    """g(t, y, params) = 0 with a crossing ``direction`` (0, +1, -1); ``terminal`` stops."""

    function: EventFunction
    direction: Literal[-1, 0, 1] = 0
    terminal: bool = False
    name: str | None = None

    def __post_init__(self) -> None:
        if self.direction not in (-1, 0, 1):
            raise ModelError(f"event direction must be -1, 0 or +1, not {self.direction!r}")
        if self.name is not None and not self.name.isidentifier():
            raise ModelError(f"event name must be an identifier, not {self.name!r}")


def named(events: Sequence[Event]) -> tuple[Event, ...]:
    """The events with a name each (``event1``, ... where none was given), names unique."""
    result = []
    for i, event in enumerate(events, start=1):
        if event.name is None:
            event = Event(event.function, event.direction, event.terminal, f"event{i}")
        result.append(event)
    names = [event.name for event in result]
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise ModelError(f"two events named {', '.join(map(repr, duplicates))}")
    return tuple(result)


def scipy_event(
    event: Event, params: np.ndarray, t0: float, y0: np.ndarray, f0: np.ndarray
) -> Callable[[float, np.ndarray], float]:
    """``event`` as a ``solve_ivp`` event function (attributes ``terminal``, ``direction``).

    SciPy counts a zero at the start time as an occurrence (and a terminal
    event would stop at once); here it is not one.  So where g(t0, y0) = 0, the
    value at t0 is replaced by a tiny number with the sign g takes just after
    t0 (at y0 + delta f0), which leaves every later crossing as it was.
    """
    g0 = float(event.function(t0, y0, params))
    start = g0
    if g0 == 0.0:
        delta = 1e-7 * max(1.0, abs(t0))
        ahead = float(event.function(t0 + delta, y0 + delta * f0, params))
        start = float(np.copysign(np.finfo(float).tiny, ahead)) if ahead != 0.0 else 0.0

    def function(t: float, y: np.ndarray) -> float:
        if t == t0:
            return start
        return float(event.function(t, y, params))

    function.terminal = event.terminal
    function.direction = event.direction
    return function


def hermite(
    t0: float, y0: np.ndarray, f0: np.ndarray, t1: float, y1: np.ndarray, f1: np.ndarray, t
) -> np.ndarray:
    """The cubic Hermite interpolant with values y and slopes f at t0 and t1, at ``t``.

    ``t`` may be an array (T,): the result then has a trailing axis T.
    """
    h = t1 - t0
    s = (np.asarray(t, dtype=float) - t0) / h
    y0, f0, y1, f1 = (np.asarray(a)[..., None] if np.ndim(t) else a for a in (y0, f0, y1, f1))
    return hermite_at(s, h, y0, f0, y1, f1)


def hermite_at(s, h, y0, f0, y1, f1):
    """The cubic Hermite interpolant at the fraction ``s`` of a step of width ``h`` with
    values y and slopes f at its ends, all broadcast together (many steps at once)."""
    s2, s3 = s * s, s * s * s
    h00, h10 = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s
    h01, h11 = -2 * s3 + 3 * s2, s3 - s2
    return h00 * y0 + h10 * h * f0 + h01 * y1 + h11 * h * f1


class EventWatcher:
    """Sign-change detection and root location for fixed-step methods (single trajectory).

    Call :meth:`step` after every step with the step's ends; ``derivative(t, y)``
    gives y' (it is only called when a sign changes).  It records every
    occurrence and returns the first terminal one, (t, y), or None.
    """

    def __init__(self, events: Sequence[Event], params: np.ndarray, t0: float, y0: np.ndarray):
        self.events = tuple(events)
        self.params = params
        self._values = [self._g(event, t0, y0) for event in self.events]
        self._times: list[list[float]] = [[] for _ in self.events]
        self._states: list[list[np.ndarray]] = [[] for _ in self.events]

    def _g(self, event: Event, t: float, y: np.ndarray) -> float:
        return float(event.function(t, y, self.params))

    def step(
        self,
        t0: float,
        y0: np.ndarray,
        t1: float,
        y1: np.ndarray,
        derivative: Callable[[float, np.ndarray], np.ndarray],
    ) -> tuple[float, np.ndarray] | None:
        new = [self._g(event, t1, y1) for event in self.events]
        crossing = [
            i
            for i, event in enumerate(self.events)
            if _crosses(self._values[i], new[i], event.direction)
        ]
        self._values = new
        if not crossing:
            return None
        f0, f1 = derivative(t0, y0), derivative(t1, y1)
        roots = []
        for i in crossing:
            t = self._locate(self.events[i], t0, y0, f0, t1, y1, f1, new[i])
            roots.append((t, i, hermite(t0, y0, f0, t1, y1, f1, t)))
        roots.sort(key=lambda root: root[0])
        terminal = [(t, y) for t, i, y in roots if self.events[i].terminal]
        stop = terminal[0][0] if terminal else np.inf
        for t, i, y in roots:
            if t <= stop:  # roots after a terminal one never happen
                self._times[i].append(t)
                self._states[i].append(y)
        return terminal[0] if terminal else None

    def _locate(self, event, t0, y0, f0, t1, y1, f1, g1) -> float:
        from scipy.optimize import brentq

        if g1 == 0.0:
            return t1

        def g(t: float) -> float:
            return self._g(event, t, hermite(t0, y0, f0, t1, y1, f1, t))

        if g(t0) * g1 > 0:  # the interpolant misses the crossing the step ends show
            return t1
        xtol = 1e-15 * max(1.0, abs(t1))
        return float(brentq(g, t0, t1, xtol=xtol, rtol=4 * np.finfo(float).eps))

    def records(self, size: int) -> tuple[EventRecord, ...]:
        """The occurrences so far; ``size`` = 2n (the state length) for empty records."""
        return tuple(
            EventRecord(
                event.name or f"event{i + 1}",
                np.array(times, dtype=float),
                np.stack(states, axis=-1) if states else np.empty((size, 0)),
            )
            for i, (event, times, states) in enumerate(
                zip(self.events, self._times, self._states, strict=True)
            )
        )


def _crosses(before: float, after: float, direction: int) -> bool:
    """A sign change from ``before`` (not zero) to ``after`` (zero counts) in ``direction``."""
    upward = before < 0.0 <= after
    downward = before > 0.0 >= after
    return (upward and direction >= 0) or (downward and direction <= 0)

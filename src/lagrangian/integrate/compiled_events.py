"""SciPy's event handling over the steps of the compiled DOP853 loop
(:mod:`.compiled_dop853`): sign changes of each event's g at the step ends, roots by
Brent's method on the step's 7th-order interpolant, as ``solve_ivp`` finds them."""

from __future__ import annotations

import numpy as np

from ..trajectory import EventRecord
from .events import scipy_event

_EPS = float(np.finfo(float).eps)


def interpolate(t: float, t_old: float, h: float, y_old: np.ndarray, slopes: np.ndarray):
    """The step's 7th-order interpolant (SciPy's ``Dop853DenseOutput``) at ``t``."""
    x = (t - t_old) / h
    y = np.zeros_like(y_old)
    for i, row in enumerate(slopes[::-1]):
        y += row
        y *= x if i % 2 == 0 else 1 - x
    return y + y_old


class StepEvents:
    """SciPy's event handling (``solve_ivp``: find_active_events, handle_events) over the
    steps of a chunk: sign changes of g at the step ends, roots by Brent's method on the
    step's interpolant, the run stopped at the first terminal one."""

    def __init__(self, events, params, t0, y0, f0):
        self.events = tuple(events)
        self.functions = [scipy_event(e, params, t0, y0, f0) for e in self.events]
        self.values = [function(t0, y0) for function in self.functions]
        self.times: list[list[float]] = [[] for _ in self.events]
        self.states: list[list[np.ndarray]] = [[] for _ in self.events]

    def steps(self, t_start, ts, ys, olds, slopes) -> tuple[int, tuple[float, np.ndarray]] | None:
        """(index of the step that stops, (t, y) where) at the first terminal event, or None."""

        def interpolant(k, t_old, t):
            return lambda s: interpolate(s, t_old, t - t_old, olds[k], slopes[k])

        return self.located(t_start, ts, ys, interpolant)

    def located(self, t_start, ts, ys, interpolant) -> tuple[int, tuple[float, np.ndarray]] | None:
        """As :meth:`steps`, on any method's steps: ``interpolant(k, t_old, t)`` is the state
        as a function of the time within step k, from ``t_old`` to ``t`` (heyoka's continuous
        output for the taylor method, :mod:`.taylor_propagate`)."""
        from scipy.optimize import brentq

        t_old = t_start
        for k in range(ts.shape[0]):
            t, y = float(ts[k]), ys[k]
            new = [function(t, y) for function in self.functions]
            active = [
                i for i, event in enumerate(self.events)
                if _crosses(self.values[i], new[i], event.direction)
            ]  # fmt: skip
            self.values = new
            if active:
                at = interpolant(k, t_old, t)
                roots = []
                for i in active:
                    function = self.functions[i]
                    root = brentq(
                        lambda s, g=function, at=at: g(s, at(s)),
                        t_old,
                        t,
                        xtol=4 * _EPS,
                        rtol=4 * _EPS,
                    )
                    roots.append((root, i))
                roots.sort()
                for root, i in roots:
                    self.times[i].append(root)
                    self.states[i].append(at(root))
                    if self.events[i].terminal:
                        return k, (root, at(root))
            t_old = t
        return None

    def records(self, size: int) -> tuple[EventRecord, ...]:
        return tuple(
            EventRecord(
                event.name,
                np.array(times, dtype=float),
                np.stack(states, axis=-1) if states else np.empty((size, 0)),
            )
            for event, times, states in zip(self.events, self.times, self.states, strict=True)
        )


def _crosses(before: float, after: float, direction: int) -> bool:
    """SciPy's find_active_events: g <= 0 <= g_new up, g >= 0 >= g_new down."""
    up = before <= 0 <= after
    down = before >= 0 >= after
    return (up and direction > 0) or (down and direction < 0) or ((up or down) and direction == 0)

"""Where a stroboscopic section samples: at t ≡ phase (mod period), counted from t = 0.

A strobe is the Poincaré map of a system driven with its period: the state at
t_k = phase + k * period.  The phase, not the transient, fixes the section: the
transient only says which of those times are kept (those after it), so two runs with
transients that differ by any time (a non-integer number of periods too) sample the
same times and give the same points of one map (at phase 0: the textbook's, the state
whenever the drive A cos(omega t) is at its maximum).  The sample times are computed as
phase + k * period, never by adding periods up, so they do not drift with k.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .base import positive_setting, transient_setting

#: A time within this fraction of a period of the transient counts as at it (not after).
AT_TRANSIENT = 1e-9


@dataclass(frozen=True)
class Strobe:
    """The strobe times phase + k * period, k = 0, 1, ... (``phase`` in [0, period))."""

    period: float
    phase: float = 0.0

    @classmethod
    def of(cls, period: float, phase: float | None = None) -> Strobe:
        """The strobe of ``period`` (finite, > 0) at ``phase`` (any finite time, taken
        modulo the period; default 0), or ModelError naming the bad setting."""
        period = positive_setting("strobe", period)
        try:
            number = float(0.0 if phase is None else phase)
        except (TypeError, ValueError):
            raise ModelError(f"the phase must be a time, not {phase!r}") from None
        if not math.isfinite(number):
            raise ModelError(f"the phase must be a finite time, not {number:g}")
        reduced = math.fmod(number, period)
        reduced = reduced + period if reduced < 0 else reduced
        return cls(period, 0.0 if reduced >= period else reduced)

    def first(self, transient: float) -> int:
        """The k of the first strobe time after ``transient`` (a time within
        :data:`AT_TRANSIENT` of a period of it is at it, and not kept)."""
        transient = transient_setting(transient)
        return math.floor((transient - self.phase) / self.period + AT_TRANSIENT) + 1

    def time(self, k: int | np.ndarray) -> float | np.ndarray:
        """t_k = phase + k * period."""
        return self.phase + np.asarray(k, dtype=float) * self.period

    def times(self, transient: float, t_end: float) -> np.ndarray:
        """The strobe times after ``transient`` up to ``t_end`` (one within 1e-12 of a
        period past it is taken as at it: its state is the state at ``t_end``)."""
        first = self.first(transient)
        last = math.floor((t_end - self.phase) / self.period + 1e-12)
        times = self.time(np.arange(first, max(first, last + 1)))
        return np.minimum(times, t_end)

    def describe(self) -> str:
        """'every 9.42478' or 'every 9.42478 at phase 1.5'."""
        text = f"every {self.period:.6g}"
        return text + (f" at phase {self.phase:.6g}" if self.phase else "")


class AngleWrapping:
    """Differences and points of a strobe map with its ``angles`` (indices of the state,
    coordinates on which the map is 2π-periodic) taken into [-π, π)."""

    angles: np.ndarray

    def difference(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """a - b with the angles' differences in [-π, π)."""
        return self.wrapped(a - b)

    def wrapped(self, x: np.ndarray) -> np.ndarray:
        """x (2n, ...) with its angles in [-π, π)."""
        x = np.array(x, dtype=float)
        x[self.angles] = (x[self.angles] + math.pi) % (2 * math.pi) - math.pi
        return x

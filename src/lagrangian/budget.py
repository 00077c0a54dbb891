"""Time budgets for the symbolic stages: nothing hangs, nothing is silently wrong.

Budgets are seconds of this process's own CPU time (user + system, every thread,
and the children it has waited for; :func:`cpu_seconds`), not wall time: a
stage that needs 3 s of CPU needs them on a quiet machine and beside four busy
processes alike, so the same machine gives the same verdict at any load.

SymPy is pure Python, so a deadline can interrupt it anywhere: :func:`deadline`
arms the process's CPU-time timer (``ITIMER_PROF``, delivering ``SIGPROF``) and
raises :class:`OutOfTime` (a ``BaseException``, so that no ``except Exception``
inside SymPy swallows it) in the code it guards.  The guarded code is abandoned
whole: its caller gets either the complete result or :class:`OutOfTime`, never
a half-made one, and reports the part as undecided (:func:`attempt`) or falls
back to a cheaper route that is still correct.  However the block is left, the
deadline is cleared with its signal held back, and nothing of it outlives the
block (:class:`deadline`): the next stage in the same process starts clean.

A process has one CPU-time timer, so deadlines nest: an inner one arms the
timer for the earlier of its own end and the outer end, and on leaving re-arms
whatever was armed before it (a profiler's timer included).  Signals reach only
the main thread: elsewhere (a web server's worker) a deadline is not armed and
the code runs to its end, bounded only by the size limits.  The timer counts
this process only: work handed to a child (SymPy's solve in
:mod:`lagrangian.analysis.solving`) is given :func:`remaining` as its own CPU
budget, and :func:`recount` charges its time once it has been waited for.

The size budgets, which bound what no deadline reaches, are in :mod:`lagrangian.sizes`.
"""

from __future__ import annotations

import contextlib
import math
import numbers
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import TypeVar

from .errors import ModelError

try:
    import resource
except ImportError:  # Windows
    resource = None  # type: ignore[assignment]

#: Default CPU seconds for each stage of ``analyze`` (conserved quantities, H, equilibria,
#: ...): every built-in example decides each stage well within it (the longest, the heavy
#: top's steady motions, takes 7.6 s of CPU on a 2-core x86_64 machine; benchmarks/load.py).
STAGE_SECONDS = 20.0
#: Default budget of a single run started from the command line or ``System.simulate``
#: (:mod:`lagrangian.integrate.pace` judges a run against it).
RUN_SECONDS = 300.0
#: CPU seconds at least for work that always ends (linearization: normal modes, the state
#: space at a point): a budget there only stops what would take unreasonably long.
ENDING_SECONDS = 120.0
#: The longest time budget a caller may give (a week): more is a typo, and infinity would
#: switch the budget off (``None`` says "no limit" where a library function allows it).
MAX_SECONDS = 7 * 86400.0

T = TypeVar("T")


class OutOfTime(BaseException):  # like KeyboardInterrupt: an interruption, not an error
    """The deadline of ``stage`` (``seconds`` long) has passed."""

    def __init__(self, stage: str, seconds: float):
        super().__init__(f"{stage}: not decided within {seconds:g} s")
        self.stage, self.seconds = stage, seconds


@dataclass(frozen=True)
class Undecided:
    """A part of a result that was not decided, and why (``"not decided within 5 s"``);
    ``seconds``: the CPU time it had, when it ran out of time."""

    stage: str
    reason: str
    seconds: float | None = field(default=None, compare=False)

    def __str__(self) -> str:
        return f"{self.stage}: {self.reason}"


def generous(seconds: float | None) -> float | None:
    """The budget of work that always ends, given a stage's: at least :data:`ENDING_SECONDS`."""
    return None if seconds is None else max(seconds, ENDING_SECONDS)


def checked_seconds(value: object, name: str = "timeout") -> float:
    """``value`` as the seconds of a time budget: a number > 0 and at most :data:`MAX_SECONDS`.

    Anything else (NaN, infinity, 0, a negative number, a string, True) is a one-line
    :class:`~lagrangian.errors.ModelError` naming the parameter ``name``; the command
    line's ``--timeout`` is checked by this same function.
    """
    if (
        isinstance(value, bool)
        or not isinstance(value, numbers.Real)
        or not math.isfinite(value)
        or not 0 < value <= MAX_SECONDS
    ):
        number = isinstance(value, numbers.Real) and not isinstance(value, bool)
        shown = f"{value:g}" if number else repr(value)
        raise ModelError(
            f"must be a number of seconds > 0 and at most {MAX_SECONDS:g} (a week), not {shown}",
            field=name,
        )
    return float(value)


def cpu_seconds() -> float:
    """CPU seconds used so far by this process (all threads) and the children it waited for."""
    if resource is None:  # Windows: no children's times, 1/64 s ticks
        used = os.times()
        return used.user + used.system
    own, children = (
        resource.getrusage(resource.RUSAGE_SELF),
        resource.getrusage(resource.RUSAGE_CHILDREN),
    )  # microseconds, where os.times counts 1/100 s ticks
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


# The armed deadlines, innermost last: (end on the cpu_seconds clock, the exception to raise).
_active: list[tuple[float, OutOfTime]] = []

#: CPU seconds after which an expired deadline raises again, should its error have been lost.
REPEAT_SECONDS = 0.05

#: The timer the deadlines use, and its signal: CPU time of the process, not wall time.
TIMER, SIGNAL = getattr(signal, "ITIMER_PROF", None), getattr(signal, "SIGPROF", None)


def _can_arm() -> bool:
    return TIMER is not None and threading.current_thread() is threading.main_thread()


class deadline:  # named as the function it was: ``with deadline(seconds, stage)``
    """Raise :class:`OutOfTime` in the guarded block once it has used ``seconds`` of CPU.

    ``None`` (or a thread other than the main one) arms nothing.  A class rather than a
    generator: contextlib's ``__exit__`` runs Python code before the generator's
    ``finally``, and a signal handled there (the error repeating while a large
    expression is freed) escaped with the timer and handler left behind: the process
    was killed by SIGPROF once the interpreter reset the handler, and every later
    deadline in it saw the stale one.  Here ``__exit__`` is never interrupted by its
    own deadline, and clears it with the signal held back (:func:`_disarmed`).
    """

    def __init__(self, seconds: float | None, stage: str):
        self.seconds, self.stage = seconds, stage
        self.armed = self.entered = False  # raising from its handler; to be cleared
        self.fired = False  # its error was raised inside the block

    def __enter__(self) -> None:
        if self.seconds is None or not _can_arm():
            return
        now = cpu_seconds()
        self.end = now + max(float(self.seconds), 0.0)
        self.error = OutOfTime(self.stage, self.seconds)
        self.previous_handler = signal.getsignal(SIGNAL)
        previous_delay, self.previous_interval = signal.getitimer(TIMER)
        self.outer = now + previous_delay if previous_delay > 0 else None
        if self.outer is not None and _active:
            # The timer tells what is left in whole ticks of the kernel's accounting, so
            # an end read back from it drifts later at each deadline entered and left
            # within a tick: an enclosing deadline's own end is exact.
            self.outer = min(self.outer, min(end for end, _ in _active))
        self.armed = self.entered = True
        # A timer due at once (a deadline of microseconds, or the outer one) may fire
        # before the guarded block starts, with no __exit__ to follow: undone here.
        try:
            signal.signal(SIGNAL, self._expired)
            _active.append((self.end, self.error))
            due = self.end if self.outer is None else min(self.end, self.outer)
            signal.setitimer(TIMER, max(due - now, 1e-6))
        except BaseException:
            self._leave()
            raise

    def __exit__(self, kind, error, traceback) -> bool:
        if self.entered:
            self._leave()
        if kind is None and self.fired:
            # Its error was raised in the block and lost on the way (in a gc callback or
            # a __del__, where Python prints it as unraisable, or caught by the work): the
            # work went on past its end, which is still not within the deadline.
            raise self.error
        return False  # an OutOfTime goes on to attempt() or the caller

    def _expired(self, signum, frame) -> None:
        if not self.armed:
            return  # late: the block is being left
        if self.outer is not None and self.outer < self.end:  # the outer timer is due first
            self.armed = False  # hand it on; leaving the block re-arms what was there
            signal.signal(SIGNAL, self.previous_handler)
            if callable(self.previous_handler):
                self.previous_handler(signum, frame)
            else:
                signal.raise_signal(SIGNAL)
            return
        # Again every REPEAT_SECONDS until the block is left: Python runs the handler at
        # the next bytecode, which may be a gc callback's or a __del__'s, where the error
        # is printed as unraisable and lost.
        signal.setitimer(TIMER, REPEAT_SECONDS)
        if isinstance(sys.exc_info()[1], OutOfTime) or _leaving(frame):
            return  # already on its way out, or in a clean-up that must run whole
        self.fired = True  # should this error be lost, leaving the block raises it
        raise self.error

    def _leave(self) -> None:
        """Disarm: no signal of this deadline reaches anyone after this returns."""
        self.armed = self.entered = False  # first: a signal from here on is ignored
        overdue = False
        with _disarmed(self.previous_handler):
            if any(error is self.error for _, error in _active):
                _active.remove(next(a for a in _active if a[1] is self.error))
            if self.outer is not None:  # re-arm what was armed before
                left = self.outer - cpu_seconds()
                overdue = left <= 0
                signal.setitimer(TIMER, max(left, 1e-6), self.previous_interval)
        if overdue:
            # Its signal now, not a timer tick later: a deadline entered and left within
            # that tick would re-arm it for a microsecond again, and a loop of short
            # stages would push it on for ever.
            signal.raise_signal(SIGNAL)


def _leaving(frame) -> bool:
    """Whether ``frame`` is a context manager's ``__exit__``: an error raised there
    would skip the clean-up (sympy's ``evaluate`` restoring its global flag)."""
    return frame is not None and frame.f_code.co_name in ("__exit__", "__aexit__")


@contextlib.contextmanager
def _disarmed(handler) -> Iterator[None]:
    """The timer stopped with its signal held back, then ``handler`` installed.

    Held back, a signal that came meanwhile is discarded rather than delivered to
    ``handler`` (the default disposition of SIGPROF ends the process): setting it
    to be ignored discards one pending, and a Python call lets the interpreter run
    one it has noted but not yet handled, while our handler is still there."""
    held = hasattr(signal, "pthread_sigmask")
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {SIGNAL}) if held else None
    try:
        signal.setitimer(TIMER, 0)
        _settle()
        signal.signal(SIGNAL, signal.SIG_IGN)
        signal.signal(SIGNAL, handler)
        yield
    finally:
        if held:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)


def _settle() -> None:
    """Nothing: calling a Python function runs a signal handler that is due."""


def remaining() -> float | None:
    """CPU seconds left before the earliest armed deadline (None when none is armed).

    For work a deadline cannot interrupt in-process (a forked child's solve).
    """
    if not _active:
        return None
    return max(min(end for end, _ in _active) - cpu_seconds(), 0.0)


def recount() -> None:
    """Charge the CPU time of children waited for since the timer was armed.

    The timer counts this process only: it is re-armed for what is left on the clock
    of :func:`cpu_seconds`, and a deadline already spent ends here (a signal due
    after a microsecond of CPU would come late to a parent that goes on waiting).
    """
    if not _active or not _can_arm():
        return
    end, error = min(_active, key=lambda armed: armed[0])
    left = end - cpu_seconds()
    if left <= 0:
        raise error
    signal.setitimer(TIMER, left)


def attempt(
    stage: str, seconds: float | None, work: Callable[[], T]
) -> tuple[T | None, Undecided | None]:
    """``(work(), None)``, or ``(None, Undecided(stage, ...))`` when ``seconds`` ran out.

    Only this deadline's :class:`OutOfTime` is caught: an outer one passes on.
    """
    try:
        with deadline(seconds, stage):
            return work(), None
    except OutOfTime as error:
        if any(error is outer for _, outer in _active):  # an enclosing deadline's: not ours
            raise
        return None, Undecided(stage, f"not decided within {seconds:g} s", seconds)


def within(
    seconds: float | None, stage: str, work: Callable[[], T], fallback: Callable[[], T]
) -> T:
    """``work()`` if it finishes within ``seconds``, else ``fallback()`` (cheaper, correct)."""
    result, undecided = attempt(stage, seconds, work)
    return fallback() if undecided is not None else result

"""The time budget of one run, judged from the time the integrator has reached.

The budget is seconds of this process's CPU time (every thread, and children
waited for: :func:`lagrangian.budget.cpu_seconds`), so a run refused on a busy
machine is refused on a quiet one too.  Work done elsewhere uses no CPU here
(a GPU's kernels, dask's workers): such a run is timed on the wall clock
(``clock=time.monotonic``).

A run's cost is not known before it starts: an adaptive method's step follows
the motion, and ``--t-end 1e9`` of an oscillator is a few billion steps, hours
of work that would otherwise run until killed.  :class:`RunPace` is told the
time reached at every step and ends the run with a :class:`RunTooLong` error
(one line: the time reached, the pace, what to change) as soon as

- the run has spent its ``seconds``, or
- after ``PROBE_SECONDS`` the pace so far projects a total over ``PROJECTION``
  times the budget: a run that cannot finish is refused in about a second,
  not after the whole budget (an ensemble tells the fraction of its work
  done instead of the time).  The pace is the better of the one since the
  start and the latest (since the read before), and it is judged once it has
  settled: not while the latest pace is over ``SETTLING`` times the one
  before (an ensemble's chunks growing past a fixed cost each, a step size
  still growing); the margin allows for a pace that improves further.

Reading the CPU clock costs two system calls (2 us alone, about 10 us inside a
run: more than a small system's right-hand side), and the watch is told at every
evaluation of it (benchmarks/README.md, "The run budget reads its clock").  So
the clock is read at the first call (the budget starts there), then once every
``stride`` calls: at each read the stride becomes the number of calls that took
``READ_SECONDS`` of the clock since it last moved, growing at most
``STRIDE_GROWTH``-fold a read and never past ``MAX_STRIDE``.  Between reads a
call only keeps ``reached``; the budget and the pace are judged at the reads.
A budget is overshot by about ``READ_SECONDS``, by more only where the calls
grow dearer before the next read (up to 8 reads' time when they grow 8-fold, as
an ensemble's chunks may).  A clock that moves by ``READ_SECONDS`` or more a
call, on average since it last moved (a compiled loop's chunks, an ensemble's,
a test's clock), is read at every call.
"""

from __future__ import annotations

from collections.abc import Callable

from ..budget import checked_seconds, cpu_seconds
from ..errors import LagrangianError, choices, setting

# Each remedy names its setting: a command that has no option for it leaves it out (plot
# has no --rtol nor --dt, lyapunov no --dt).
RUN_ADVICE = (
    "give "
    + choices(
        f"a shorter {setting('t_end')}", f"a looser {setting('rtol')}", f"a larger {setting('dt')}"
    )
    + f", or allow more time with {setting('timeout')}"
)
ENSEMBLE_ADVICE = (
    "give "
    + choices(
        "fewer members",
        f"a shorter {setting('t_end')}",
        f"a larger {setting('dt')}",
        f"a faster {setting('backend')}",
    )
    + f", or allow more time with {setting('timeout')}"
)
#: Seconds after which the pace so far is trusted enough to project the total.
PROBE_SECONDS = 1.0
#: A projected total over this many budgets ends the run at once.
PROJECTION = 2.0
#: A latest pace over this many times the one before is still improving: not judged yet.
SETTLING = 2.0
#: Seconds of the clock between two reads of it (the calls in between only keep ``reached``):
#: the overshoot of a budget, and the reads' cost (10 us each in a run: 0.2 %).
READ_SECONDS = 5e-3
#: The most the stride between reads grows from one read to the next.
STRIDE_GROWTH = 2
#: The most calls between two reads of the clock.
MAX_STRIDE = 256


class RunTooLong(LagrangianError):
    """The run would not finish within its time budget."""


class RunPace:
    """Called with the time reached (often); raises :class:`RunTooLong` past the budget.

    The budget counts from the first call; the pace from the first read past the
    start time, so a compile on the way (numba's, seconds long) is not mistaken
    for slow stepping.  ``clock``: seconds used so far (None: CPU time,
    :func:`~lagrangian.budget.cpu_seconds`), read every ``stride`` calls (see the
    module); ``reads`` counts its reads.
    """

    def __init__(
        self,
        t_span: tuple[float, float],
        seconds: float,
        *,
        describe: Callable[[float], str] | None = None,
        advice: str = RUN_ADVICE,
        clock: Callable[[], float] | None = None,
    ):
        self.t0, self.t1 = float(t_span[0]), float(t_span[1])
        self.seconds = checked_seconds(seconds, "timeout")
        self.describe = describe or (lambda t: f"t = {t:.6g} of t_end = {self.t1:g}")
        self.advice = advice
        self.clock = clock or cpu_seconds
        self.started: float | None = None
        self.moving: tuple[float, float] | None = None  # (clock, t) when t first moved
        self.last: tuple[float, float] | None = None  # (clock, t) of the read before
        self.latest = 0.0  # the pace since the read before that (model time / s)
        self.reached = self.t0
        self.calls = self.reads = 0
        self.stride = 1
        self.due = 1  # the call that reads the clock next
        self.anchor: tuple[float, int] | None = None  # (clock, calls) when it last moved

    def __call__(self, t: float) -> None:
        if t > self.reached:  # max(reached, min(t, t1)), without the builtins' cost; not NaN
            self.reached = float(t) if t < self.t1 else max(self.reached, self.t1)
        self.calls += 1
        if self.calls >= self.due:
            self._judge(self.clock())

    def _judge(self, now: float) -> None:
        """Raise :class:`RunTooLong` if the run is over its budget at ``now`` (a read of
        the clock) or its pace projects a total over ``PROJECTION`` budgets."""
        self.reads += 1
        if self.started is None:
            self.started = now
        self._next_read(now)
        if self.moving is None and self.reached > self.t0:
            self.moving = (now, self.reached)
        elapsed = now - self.started
        if elapsed > self.seconds:
            raise RunTooLong(
                f"the run did not finish within {self.seconds:g} s: it reached "
                f"{self.describe(self.reached)}; {self.advice}"
            )
        settling = self._settling(now)
        if self.moving is None or now - self.moving[0] < PROBE_SECONDS or settling:
            return
        clock, t_moving = self.moving
        if self.reached <= t_moving:
            return
        rate = max((self.reached - t_moving) / (now - clock), self.latest)
        projected = elapsed + (self.t1 - self.reached) / rate
        if projected > PROJECTION * self.seconds:
            raise RunTooLong(
                f"at its pace so far the run would take {_duration(projected)} "
                f"({self.describe(self.reached)} in {elapsed:.1f} s), "
                f"more than the {self.seconds:g} s allowed; {self.advice}"
            )

    def _next_read(self, now: float) -> None:
        """Set the call of the next read: ``READ_SECONDS`` of the clock away at the cost
        per call since the clock last moved (the stride kept while it has not moved)."""
        anchor, calls = self.anchor, self.calls
        if anchor is None or now != anchor[0]:
            if anchor is not None:
                per_call = (now - anchor[0]) / (calls - anchor[1])
                wanted = READ_SECONDS / per_call if per_call > 0 else 1.0
                self.stride = max(1, min(int(wanted), STRIDE_GROWTH * self.stride, MAX_STRIDE))
            self.anchor = (now, calls)
        self.due = calls + self.stride

    def _settling(self, now: float) -> bool:
        """Whether the pace since the read before is over ``SETTLING`` times the one before
        it (the pace still improves); keeps the latest pace."""
        last, self.last = self.last, (now, self.reached)
        if last is None or now <= last[0]:
            return False
        latest = (self.reached - last[1]) / (now - last[0])
        settling = latest > SETTLING * self.latest
        self.latest = latest
        return settling


def _duration(seconds: float) -> str:
    """About 5 minutes, 3 hours, 12 days, 4,000 years, 1.3e+290 years: a short number."""
    units = (("years", 365.25 * 86400.0), ("days", 86400.0), ("hours", 3600.0), ("minutes", 60.0))
    for unit, size in units:
        if seconds >= 2 * size:
            amount = seconds / size
            return f"about {amount:,.0f} {unit}" if amount < 1e6 else f"about {amount:.2g} {unit}"
    return f"about {seconds:.0f} s"


def watching(*watchers: Callable[[float], None] | None) -> Callable[[float], None] | None:
    """One watch telling each given watcher (None ones left out) what it is told; None
    when there is none, so a run without budget or progress bar pays nothing (and a
    single watcher is itself the watch: no call in between)."""
    # a RunPace's bound __call__: calling the instance looks __call__ up at every call
    present = [w.__call__ if isinstance(w, RunPace) else w for w in watchers if w is not None]
    if not present:
        return None
    if len(present) == 1:
        return present[0]

    def told(reached: float) -> None:
        for watcher in present:
            watcher(reached)

    return told

"""Pages made in a process of their own, one at a time, each within a time budget.

The symbolic stages bound themselves with :func:`lagrangian.budget.deadline`, which
arms a signal and so works only in a process's main thread: in a web server's thread
it would arm nothing.  So the server hands each model text to a worker process, whose
main thread runs the whole page within :data:`PAGE_SECONDS` of its CPU time (the
stages' own budgets inside it), and waits for the answer off the event loop.  A
worker that has not answered after :data:`WALL_FACTOR` times that in wall time (a
busy machine stretches CPU seconds), plus :data:`GRACE_SECONDS`, is stuck in code no
signal interrupts (or stopped): it is killed and replaced; so is one that died, and so
is one in which any deadline ran out (the page's, or a stage's inside it): the signal
and timer state a time-out leaves behind is never trusted with the next edit.  The
replacement is started at once, and imports the toolkit while the user reads the
message.  The worker is started with ``spawn``, never ``fork``: the server has threads,
and a forked copy of a threaded process may hang.
"""

from __future__ import annotations

import multiprocessing
import signal
import threading
from collections import OrderedDict
from dataclasses import dataclass
from typing import Protocol

from ..budget import OutOfTime, deadline
from ..errors import LagrangianError

#: Seconds for one page: reading the model, deriving, analysing, writing the page.
PAGE_SECONDS = 60.0
#: Wall seconds the server waits for a page, in multiples of its CPU budget: beside four
#: busy processes on two cores a worker gets a third of a core.
WALL_FACTOR = 4.0
#: Seconds past that before a worker that has not answered is killed.
GRACE_SECONDS = 10.0
#: Seconds a new worker may take to import the toolkit (SymPy, ...) and say it is ready:
#: not counted in a page's time, and generous, as a busy machine may be slow to start one.
START_SECONDS = 120.0
#: Pages kept for texts seen again (an example chosen again, an edit undone): each is
#: about a megabyte, and made anew costs seconds of derivation and analysis.
PAGES_KEPT = 16
_READY = "ready"


@dataclass(frozen=True)
class Rendered:
    """The page of a model text, or the one-line error that says why there is none;
    ``timed_out``: a deadline ran out while making it (the whole page's, or a stage's
    whose part the page then says is undecided)."""

    page: str | None = None
    error: str | None = None
    timed_out: bool = False


class Renderer(Protocol):
    """What the server needs of a page maker (:class:`PageWorker`, or a test's stand-in)."""

    def start(self) -> None: ...
    def render(self, text: str, exercise: bool = False) -> Rendered: ...
    def close(self) -> None: ...


def render(text: str, *, seconds: float = PAGE_SECONDS, exercise: bool = False) -> Rendered:
    """The page of the model ``text`` (see :mod:`lagrangian.serve.models`), made within
    ``seconds`` (with ``exercise``: the exercise page of every step); an error the user
    caused comes back as its line, as the CLI prints it."""
    from ..output.exercise import STEPS
    from ..output.page import built_page
    from .models import model_from_text

    try:
        with deadline(seconds, "page"):
            made = built_page(model_from_text(text), exercise=STEPS if exercise else None)
        return Rendered(page=made.html, timed_out=not made.decided)
    except LagrangianError as error:
        return Rendered(error=_line(str(error)))
    except OutOfTime as error:
        message = f"{error}: the model is too costly to derive here"
        return Rendered(error=_line(message), timed_out=True)
    except (RecursionError, MemoryError) as error:
        return Rendered(error=_line(f"the model is too large to derive ({type(error).__name__})"))
    except Exception as error:  # a bug of ours: one line, as the CLI says it
        return Rendered(error=_line(f"internal error: {type(error).__name__}: {error}"))


class PageWorker:
    """A worker process that renders model texts, restarted when it hangs or dies.

    :meth:`render` blocks (call it from a thread); calls are served one at a time.  The
    last :data:`PAGES_KEPT` pages are kept, by text (errors are not: they come quickly;
    nor are pages with a part undecided: being out of time depends on the machine's
    load).  A worker that ran out of time anywhere is replaced before the next page.
    """

    def __init__(self, *, seconds: float = PAGE_SECONDS, grace: float = GRACE_SECONDS):
        self.seconds = seconds
        self.grace = grace
        self._lock = threading.Lock()
        self._context = multiprocessing.get_context("spawn")
        self._process = None
        self._connection = None
        self._ready = False
        self._pages: OrderedDict[tuple[str, bool], str] = OrderedDict()

    def start(self) -> None:
        """Start the worker now (else the first :meth:`render` does), so that the first
        page does not wait for the worker's imports.  A worker that fails to start is
        tried again by :meth:`render`, which reports it."""
        with self._lock:
            try:
                self._ensure_started()
            except _NotStarted:
                self._stop()

    def render(self, text: str, exercise: bool = False) -> Rendered:
        """The page of ``text`` (its exercise page with ``exercise``), or its error line
        (one for a model out of time too)."""
        key = (text, exercise)
        with self._lock:
            if key in self._pages:
                self._pages.move_to_end(key)
                return Rendered(page=self._pages[key])
            try:
                self._ensure_started()
                self._connection.send(key)
                waited = WALL_FACTOR * self.seconds + self.grace
                if self._connection.poll(waited):
                    return self._kept(key, self._connection.recv())
                error = f"page: not made within {waited:g} s; stopped"
            except (EOFError, OSError):
                ended = _how_it_ended(self._process)
                error = f"the process making the page {ended}; try again"
            except _NotStarted as failure:
                error = str(failure)
            self._stop()
            return Rendered(error=error)

    def _kept(self, key: tuple[str, bool], rendered: Rendered) -> Rendered:
        if rendered.timed_out:  # a deadline's signal and timer state is not trusted again
            self._stop()
            self._spawn()
        elif rendered.page is not None:
            self._pages[key] = rendered.page
            while len(self._pages) > PAGES_KEPT:
                self._pages.popitem(last=False)
        return rendered

    def close(self) -> None:
        """Stop the worker process."""
        with self._lock:
            self._stop()

    def _ensure_started(self) -> None:
        if self._process is None or not self._process.is_alive():
            self._stop()
            self._spawn()
        if self._ready:
            return
        try:
            self._ready = self._connection.poll(START_SECONDS) and self._connection.recv() == _READY
        except (EOFError, OSError):
            self._ready = False
        if not self._ready:
            raise _NotStarted(
                f"the process making the pages did not start within {START_SECONDS:g} s: "
                f"it {_how_it_ended(self._process)}"
            )

    def _spawn(self) -> None:
        """Start a worker process, which says it is ready once it has imported the toolkit."""
        ours, theirs = self._context.Pipe()
        # Not a daemon: the analysis forks children of its own (bounded solves), which a
        # daemonic process may not; the server stops it (close), and it ends by itself
        # when the server's end of the pipe closes.
        process = self._context.Process(
            target=_serve, args=(theirs, self.seconds), name="lagrangian-page"
        )
        process.start()
        theirs.close()
        self._process, self._connection, self._ready = process, ours, False

    def _stop(self) -> None:
        if self._connection is not None:
            self._connection.close()
        if self._process is not None:
            self._process.kill()
            self._process.join(timeout=5)
            self._process.close()
        self._process = self._connection = None
        self._ready = False


def _how_it_ended(process) -> str:
    """How a worker process that stopped answering ended, said after "the process ...".

    Its pipe closes an instant before the process is reaped: waited for briefly, so that
    a killed worker is reported as killed, not with an exit code not yet known.
    """
    process.join(timeout=5)
    code = process.exitcode
    if code is None:
        return "is still running but does not answer"
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return f"was killed ({name})"
    return f"ended (exit code {code})"


def _serve(connection, seconds: float) -> None:
    """The worker's loop: (text, exercise) in, a :class:`Rendered` out, until the pipe
    closes."""
    # Ctrl-C in the terminal reaches the whole process group: the server stops the worker.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # Imported before the first page, so that their import is not counted in its time.
    from ..output import page  # noqa: F401
    from . import models  # noqa: F401

    connection.send(_READY)
    while True:
        try:
            text, exercise = connection.recv()
        except (EOFError, OSError):
            return
        connection.send(render(text, seconds=seconds, exercise=exercise))


class _NotStarted(Exception):
    """The worker process did not say it was ready."""


def _line(text: str) -> str:
    return " ".join(text.split())

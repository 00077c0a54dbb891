"""One chunk of an ensemble, and the protocol of the backends that integrate chunks.

:func:`~lagrangian.ensemble.run_ensemble` splits the members into chunks (memory stays
bounded whatever the ensemble's size) and hands them to a backend.  Every backend
receives the same :class:`Chunk` (the compiled system, the configured fixed-step
integrator, the members' initial states and parameters, t_end, the observables, saving
and precision) and reads from it the same step grid, flags and Newton settings, and
returns its outputs through :meth:`Chunk.result`, so that all backends give the same
arrays.

The chunks come from :class:`Chunks`, made one at a time: of a fixed size, or (a run
with a time budget) each sized from the time the chunks before it took, so that a budget
checked between chunks is kept within a chunk's time whatever one member costs.  The
backend tells :meth:`Chunks.took` how long each chunk took on its clock: this process's
CPU time where the work is done here, the wall clock where it is done elsewhere (a GPU,
dask's workers).

A backend is a leaf class of :class:`AbstractEnsembleBackend`: the class constants
``name`` (its key in :data:`~lagrangian.ensemble.core.ENSEMBLE_BACKENDS` and the value of
``--backend``), ``precisions``, ``chunk_size`` and ``compiles_per_shape`` (its chunks are
then of one size, not sized by time), and
:meth:`~AbstractEnsembleBackend.integrate` of one chunk.
:meth:`~AbstractEnsembleBackend.run` integrates the chunks one after the other, timing
each; a backend that spreads them (dask) overrides it.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..errors import ModelError
from ..integrate.fixed_step import led_grid
from .choices import PRECISIONS
from .observables import finish, stops_early

if TYPE_CHECKING:
    from ..codegen.forms import SymbolicForms
    from ..integrate.compiled_loop import Newton
    from ..integrate.fixed_step import AbstractFixedStepIntegrator
    from ..numeric.compiled import CompiledSystem

#: Members integrated together; memory per chunk is a few dozen (2n)-vectors per member.
DEFAULT_CHUNK_SIZE = 65_536
#: A GPU needs far more members at once than a CPU to be busy.
GPU_CHUNK_SIZE = 1_048_576

#: Members of the first chunk when chunks are sized by time: a cheap first measurement.
FIRST_CHUNK = 256
#: The most a chunk sized by time grows over the one before (the first may include a
#: compile, the pace of a few members is noisy).
CHUNK_GROWTH = 8

#: A chunk's outputs: observables (each (B,)), ``failed``, ``steps`` and optionally ``paths``.
Outputs = dict[str, np.ndarray]
Progress = Callable[[float], None]


@dataclass(frozen=True)
class Chunk:
    """What every chunk integrator receives.

    ``y0`` is (2n, B), one column per member; ``params`` is (P,) (shared) or (P, B) (per
    member); the run goes from t = 0 to ``t_end`` on the single run's step grid;
    ``names`` are the observables; ``save_every``: also keep every k-th step's state;
    ``precision``: ``float64`` or ``float32`` (the backends that offer it); ``lead``: with
    ``save_every``, the first ``save_every`` steps span [0, lead] and the steps of dt
    start there, so the states kept fall at lead + k save_every dt (0: no lead;
    :func:`~lagrangian.integrate.fixed_step.led_grid`).
    """

    compiled: CompiledSystem
    integrator: AbstractFixedStepIntegrator
    y0: np.ndarray
    params: np.ndarray
    t_end: float
    names: tuple[str, ...]
    save_every: int | None = None
    precision: str = "float64"
    lead: float = 0.0

    def __post_init__(self) -> None:
        if self.precision not in PRECISIONS:
            raise ModelError(
                f"unknown precision '{self.precision}' (precisions: {', '.join(PRECISIONS)})"
            )

    @cached_property
    def grid(self) -> np.ndarray:
        """The single run's step times (after the lead, if any), the last one on t_end."""
        return led_grid(float(self.t_end), self.integrator.dt, self.lead, self.every)

    @property
    def steps(self) -> int:
        return len(self.grid) - 1

    @property
    def count(self) -> int:
        """The members B."""
        return int(np.shape(self.y0)[1])

    @property
    def every(self) -> int:
        """``save_every`` as a whole number, 0 when nothing is saved."""
        return int(self.save_every or 0)

    @property
    def saved(self) -> int:
        """The states kept per member: the start and every ``every``-th step (1 if none)."""
        return self.steps // self.every + 1 if self.every else 1

    @property
    def track(self) -> bool:
        """Whether flips are looked for."""
        return "flip_time" in self.names

    @property
    def stop(self) -> bool:
        """Whether a member may stop once it has flipped (nothing needs its end state)."""
        return stops_early(self.names) and not self.every

    @property
    def dtype(self) -> type[np.floating]:
        return np.float32 if self.precision == "float32" else np.float64

    @property
    def newton(self) -> Newton:
        """The Newton settings of the method's printed scheme (tolerance, rounding floor,
        stall ratio, iterations; zeros for rk4, which has none)."""
        return self.integrator.newton_settings()

    def scheme(self, backend: str) -> str:
        """The loop a generated-code ``backend`` runs: ``rk4``, or the variational scheme
        :class:`~lagrangian.integrate.variational.Variational` picks for the system."""
        scheme = self.integrator.printed_scheme(self.compiled)
        if scheme is None:
            raise ModelError(
                f"backend '{backend}' integrates with rk4 or variational, "
                f"not {self.integrator.name}"
            )
        return scheme

    def check_newton(self, failures: np.ndarray) -> None:
        """One line when some member's Newton iteration failed (``failures``: per member
        the index in the grid of the failed step, negative when none)."""
        failed = failures[failures >= 0]
        if failed.size:
            raise ModelError(
                "the ensemble integration failed: Newton's method of the variational step did "
                f"not converge in {self.newton.iterations} iterations at t = "
                f"{self.grid[int(failed.min())]:.17g}"
            )

    def flip_times(self, indices: np.ndarray) -> np.ndarray:
        """Times of the flips given as grid indices (negative: never), from the float64 grid."""
        return np.where(indices >= 0, self.grid[np.clip(indices, 0, self.steps)], np.nan)

    def result(
        self, final: np.ndarray, flip_time: np.ndarray, paths: np.ndarray | None = None
    ) -> Outputs:
        """The chunk's outputs from its end states ``final`` (2n, B), flip times (B,) and,
        when saving, the saved states ``paths`` (2n, B, saved)."""
        grid = self.grid
        values = finish(
            self.compiled, self.names, t0=grid[0], y0=np.asarray(self.y0, dtype=float),
            t1=grid[-1], y1=np.asarray(final, dtype=float), params=self.params,
            flip_time=flip_time,
        )  # fmt: skip
        if self.every:
            values["paths"] = np.asarray(paths, dtype=float)
        values["steps"] = np.array(self.steps)
        return values


def generated_forms(compiled: CompiledSystem, backend: str) -> SymbolicForms:
    """The symbolic forms a backend that generates code from the equations prints."""
    if compiled.has_constraints:
        raise ModelError(
            f"backend '{backend}' does not handle constraints (use backend numpy or numba)"
        )
    if compiled.forms is None:
        raise ModelError(
            f"backend '{backend}' generates code from derived equations, not given functions"
        )
    return compiled.forms


class Chunks:
    """The chunks of a run, made one at a time as a backend asks for them.

    ``make(start, stop)`` is the chunk of members ``start:stop`` of ``count``.  Without
    ``seconds`` every chunk has ``largest`` members (the last the rest).  With ``seconds``
    they are sized by time: ``FIRST_CHUNK`` members until a chunk's time is known
    (:meth:`took`), then each sized to take about ``seconds``, at most ``CHUNK_GROWTH``
    times the one before and ``largest``.  ``clock``: the seconds that the backend
    measures a chunk's time with (see the module docstring).

    A chunk's time is modelled as a latency plus a cost per member, both read from the
    two latest chunks of different sizes: on a CPU the latency is nil and the cost that
    of one member, but a GPU takes about as long for 256 members as for 100,000 (each
    thread runs the whole loop), and sizing by the time per member of a small chunk
    would keep every chunk small.  While the cost is unknown or nil the chunks grow;
    where the latency exceeds half of ``seconds``, a chunk spends as long on its members
    as on the latency (half its time goes to the work, at least).
    """

    def __init__(
        self,
        make: Callable[[int, int], Chunk] | None,
        count: int,
        largest: int,
        *,
        seconds: float | None = None,
        clock: Callable[[], float] | None = None,
    ):
        self.make, self.count, self.largest = make, int(count), int(largest)
        self.seconds = seconds
        self.clock = clock or time.monotonic
        self.given_chunks: list[Chunk] | None = None
        self.latency, self.cost = 0.0, None  # seconds a chunk, seconds a member
        self.timed: tuple[int, float] | None = None  # the latest chunk timed: (members, s)
        self.sizes: list[int] = []

    @classmethod
    def given(cls, chunks: list[Chunk]) -> Chunks:
        """Chunks already made (no timing)."""
        made = cls(None, sum(chunk.count for chunk in chunks), max(1, len(chunks)))
        made.given_chunks = list(chunks)
        return made

    def __iter__(self) -> Iterator[Chunk]:
        if self.given_chunks is not None:
            yield from self.given_chunks
            return
        start = 0
        while start < self.count:
            stop = min(self.count, start + self._next_size())
            self.sizes.append(stop - start)
            yield self.make(start, stop)
            start = stop

    def took(self, chunk: Chunk, seconds: float) -> None:
        """``chunk`` took ``seconds`` on :attr:`clock` (see the class docstring)."""
        members, seconds = chunk.count, max(seconds, 1e-9)
        if not members:
            return
        if self.timed is not None and self.timed[0] != members:
            before, spent = self.timed
            self.cost = max((seconds - spent) / (members - before), 0.0)
            self.latency = min(max(seconds - self.cost * members, 0.0), seconds)
        else:  # the first chunk timed, or one of the same size: the latency as known
            self.cost = max(seconds - self.latency, 0.0) / members
        self.timed = (members, seconds)

    def _next_size(self) -> int:
        if self.seconds is None:
            return self.largest
        size = min(self.largest, FIRST_CHUNK)
        if self.timed is not None:
            grown = CHUNK_GROWTH * (self.sizes[-1] if self.sizes else size)
            size = min(self.largest, grown)
            if self.cost:
                spent = max(self.seconds - self.latency, self.latency)  # on the members
                size = min(size, int(spent / self.cost))
        return max(1, size)


class AbstractEnsembleBackend(ABC):
    """How the chunks of an ensemble are integrated (see the module docstring)."""

    #: The key in ENSEMBLE_BACKENDS and the value of ``--backend``.
    name: ClassVar[str]
    #: The precisions it computes in.
    precisions: ClassVar[tuple[str, ...]] = ("float64",)
    #: Members per chunk unless the run says otherwise.
    chunk_size: ClassVar[int] = DEFAULT_CHUNK_SIZE
    #: Whether a chunk of a new size costs a compile: its chunks are then all of one
    #: size, not sized by time.
    compiles_per_shape: ClassVar[bool] = False

    @abstractmethod
    def integrate(self, chunk: Chunk, progress: Progress | None = None) -> Outputs:
        """The outputs of one chunk (:meth:`Chunk.result`); ``progress``, if the backend
        can tell, is called with the fraction of the chunk's steps done."""

    def run(self, chunks: Chunks, progress: Progress | None = None) -> list[Outputs]:
        """The outputs of ``chunks`` in order, one chunk after the other, each asked for
        when the one before is done and timed (:meth:`Chunks.took`); ``progress`` is
        called with the fraction of members done."""
        total = max(1, chunks.count)
        parts, done = [], 0
        if progress is not None:
            progress(0.0)  # the start: a budget counts from here, whatever the first chunk
        for chunk in chunks:
            report = None
            if progress is not None:

                def report(fraction: float, done: int = done, size: int = chunk.count) -> None:
                    progress((done + fraction * size) / total)

            started = chunks.clock()
            parts.append(self.integrate(chunk, report))
            chunks.took(chunk, chunks.clock() - started)
            done += chunk.count
            if progress is not None:
                progress(done / total)
        return parts

"""The dask backend: the numpy path on the workers of a ``dask.distributed`` cluster.

A :class:`~lagrangian.numeric.compiled.CompiledSystem` holds closures and
locks that do not pickle, so the model travels instead: its equations of
motion, the function definitions and the Baumgarte rate (cloudpickled once),
and each worker process compiles them on first use and keeps the result
(keyed by a hash of the payload).  Each chunk of members is one task running
:class:`~lagrangian.ensemble.numpy_backend.NumpyBackend`; the results come
back in chunk order.  A chunk is made when a worker thread is free for it (one
in flight per thread), so chunks sized by time (:class:`~.chunk.Chunks`) are sized
from the time the tasks before took on their worker.

Without ``scheduler`` a ``LocalCluster`` of two worker processes, one thread
each, is started for the run (its scratch files in a temporary folder) and closed
after it; with an address (``tcp://host:port`` or ``tls://``) the run uses that
cluster, after a check of the address's form and a connection within
``CONNECT_SECONDS``.  Workers that die during the run and are started again (by
their nannies) cost only time: the model's payload is a task's result, which the
scheduler computes again, their chunks run again, and one warning says how many
workers left; distributed's own log lines are held back meanwhile.  A cluster that
fails (workers that do not start, a task whose workers died four times, a scheduler
that goes away) ends the run with one :class:`ClusterError` line.  dask is imported here only
(``pip install ".[dask]"``).
"""

from __future__ import annotations

import contextlib
import hashlib
import itertools
import logging
import os
import re
import socket
import tempfile
import time
import warnings
from collections.abc import Iterator
from concurrent.futures import CancelledError
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from ..errors import LagrangianError, LagrangianWarning, MissingDependencyError, ModelError
from .chunk import AbstractEnsembleBackend, Chunk, Chunks, Outputs, Progress
from .numpy_backend import NumpyBackend

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Compiled systems of this worker process, by payload hash.
_WORKER_SYSTEMS: dict[str, CompiledSystem] = {}
#: Seconds a scheduler has to accept the connection (a refused one fails at once).
CONNECT_SECONDS = 5.0
_ADDRESS = re.compile(r"(tcp|tls)://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):([0-9]{1,5})")


class ClusterError(LagrangianError):
    """The dask cluster cannot be reached or could not run the ensemble."""


def check_scheduler(address: str) -> tuple[str, int]:
    """(host, port) of a scheduler address ``tcp://HOST:PORT`` (or ``tls://``); ModelError
    naming the expected form otherwise."""
    match = _ADDRESS.fullmatch(address)
    port = int(match.group(3)) if match else 0
    if match is None or not 1 <= port <= 65535:
        shown = address if len(address) <= 80 else address[:77] + "..."
        raise ModelError(
            f"the dask scheduler address must be tcp://HOST:PORT (PORT 1-65535), not {shown!r}"
        )
    return match.group(2).strip("[]"), port


def _distributed():
    try:
        import cloudpickle
        import distributed
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingDependencyError("backend 'dask'", "dask.distributed", "dask") from None
    return distributed, cloudpickle


def model_payload(compiled: CompiledSystem) -> bytes:
    """What a worker needs to compile ``compiled`` again, as bytes."""
    from ..codegen.forms import DEFAULT_BAUMGARTE

    _, cloudpickle = _distributed()
    baumgarte = compiled.baumgarte if compiled.has_constraints else DEFAULT_BAUMGARTE
    definitions = dict(compiled.definitions) or None
    return cloudpickle.dumps((compiled.equations, definitions, baumgarte, compiled.backend))


def compiled_from_payload(key: str, payload: bytes) -> CompiledSystem:
    """The compiled system of ``payload``, compiled once per process."""
    found = _WORKER_SYSTEMS.get(key)
    if found is None:
        import pickle

        from ..numeric import compile_equations

        equations, definitions, baumgarte, backend = pickle.loads(payload)
        found = compile_equations(
            equations, backend=backend, definitions=definitions, baumgarte=baumgarte
        )
        _WORKER_SYSTEMS[key] = found
    return found


#: The clock a task times itself with on its worker (a name, so that tests can move it).
task_seconds = time.monotonic


def _task(key, payload, integrator, y0, params, t_end, names, save_every, lead=0.0):
    """(the chunk's outputs, the seconds it took on the worker)."""
    started = task_seconds()
    compiled = compiled_from_payload(key, payload)
    chunk = Chunk(compiled, integrator, y0, params, t_end, names, save_every, lead=lead)
    return NumpyBackend().integrate(chunk), task_seconds() - started


@dataclass(frozen=True)
class DaskBackend(AbstractEnsembleBackend):
    """The chunks as tasks on a dask cluster: the local one started for the run, or the
    one at ``scheduler`` (checked when the backend is made, before any work)."""

    name: ClassVar[str] = "dask"
    scheduler: str | None = None

    def __post_init__(self) -> None:
        if self.scheduler is not None:
            check_scheduler(self.scheduler)

    def integrate(self, chunk: Chunk, progress: Progress | None = None) -> Outputs:
        return self.run(Chunks.given([chunk]), progress)[0]

    def run(self, chunks: Chunks, progress: Progress | None = None) -> list[Outputs]:
        """The chunks' outputs (in order), integrated on the cluster; see the module."""
        pending = iter(chunks)
        first = next(pending, None)
        if first is None:
            return []
        distributed, _ = _distributed()
        import dask.config

        payload = model_payload(first.compiled)
        key = hashlib.sha256(payload).hexdigest()
        # CommClosedError is an OSError; a task whose input was lost for good is cancelled
        failures = (OSError, TimeoutError, distributed.KilledWorker, CancelledError)
        with (
            tempfile.TemporaryDirectory(prefix="lagrangian-dask-") as scratch,
            dask.config.set({"temporary-directory": scratch}),  # the scheduler's scratch too
            _quiet_cluster_logs(),
        ):
            client, cluster = _connect(distributed, self.scheduler, scratch)
            try:
                workers = _worker_addresses(client)
                # the model as the result of a task, not scattered data: when the workers
                # holding it die, the scheduler computes it again for the tasks that need it
                # (scattered data is lost with them, and every task waiting on it cancelled)
                shared = client.submit(_model_bytes, payload, key=f"lagrangian-model-{key}")
                work = _Work(client, key, shared, chunks)
                outputs = work.run(distributed, itertools.chain([first], pending), progress)
                _warn_lost(workers - _worker_addresses(client))
                return outputs
            except failures as error:
                raise ClusterError(
                    f"the dask cluster failed during the run: {_first_line(error)}"
                ) from None
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()


def _model_bytes(payload: bytes) -> bytes:
    """The model's payload, as a task's result (see :meth:`DaskBackend.run`)."""
    return payload


def _worker_addresses(client) -> set[str]:
    return set(client.scheduler_info().get("workers", {}))


def _warn_lost(lost: set[str]) -> None:
    """Say that workers were lost and their chunks ran again (the results are complete)."""
    if lost:
        count = len(lost)
        warnings.warn(
            LagrangianWarning(
                f"{count} dask worker{'s' if count > 1 else ''} left the cluster during the "
                "run (killed or restarted); their chunks ran again on the workers there"
            ),
            stacklevel=4,
        )


@contextlib.contextmanager
def _quiet_cluster_logs() -> Iterator[None]:
    """distributed's own log lines (a worker removed, restarted, data lost: dozens when
    workers die) held back during the run: what they mean is said once, by the warning
    of :func:`_warn_lost` or by the one line of a :class:`ClusterError`."""
    names = ["distributed"] + [
        name for name in logging.root.manager.loggerDict if name.startswith("distributed.")
    ]
    loggers = [logging.getLogger(name) for name in names]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(logging.CRITICAL + 1)
    # the worker processes of a local cluster (and those their nannies start again) read
    # their logging level from the environment they inherit
    environment = os.environ.get(_WORKER_LOGGING)
    os.environ[_WORKER_LOGGING] = "critical"
    try:
        yield
    finally:
        for logger, level in zip(loggers, levels, strict=True):
            logger.setLevel(level)
        if environment is None:
            os.environ.pop(_WORKER_LOGGING, None)
        else:
            os.environ[_WORKER_LOGGING] = environment


#: dask's configuration of distributed's logging level, as an environment variable.
_WORKER_LOGGING = "DASK_LOGGING__DISTRIBUTED"


def _connect(distributed, scheduler: str | None, scratch: str):
    """(client, the local cluster or None) for ``scheduler``; ClusterError when none runs."""
    if scheduler:
        host, port = check_scheduler(scheduler)
        try:  # a refused port fails here at once; distributed would retry until its timeout
            socket.create_connection((host, port), timeout=CONNECT_SECONDS).close()
            return distributed.Client(scheduler, timeout=f"{CONNECT_SECONDS:g}s"), None
        except (OSError, TimeoutError) as error:
            raise ClusterError(
                f"cannot reach the dask scheduler {scheduler} within {CONNECT_SECONDS:g} s: "
                f"{_first_line(error)}"
            ) from None
    try:
        cluster = distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
            local_directory=scratch,
        )  # fmt: skip
    except (RuntimeError, OSError, TimeoutError) as error:  # "Nanny failed to start"
        raise ClusterError(f"the local dask cluster did not start: {_first_line(error)}") from None
    try:
        return distributed.Client(cluster), cluster
    except (OSError, TimeoutError) as error:
        cluster.close()
        raise ClusterError(f"the local dask cluster did not start: {_first_line(error)}") from None


def _first_line(error: BaseException) -> str:
    text = (str(error).strip().splitlines() or [type(error).__name__])[0]
    return text if len(text) <= 160 else text[:157] + "..."


class _Work:
    """The tasks of one run: ``shared`` is the model's payload, scattered to the workers."""

    def __init__(self, client, key: str, shared, chunks: Chunks):
        self.client, self.key, self.shared, self.chunks = client, key, shared, chunks
        self.futures: list = []
        self.made: dict = {}  # future -> its chunk

    def submit(self, pending: Iterator[Chunk]):
        """The next chunk's task (None when there is none); the chunk is sent without its
        compiled system, which does not pickle."""
        chunk = next(pending, None)
        if chunk is None:
            return None
        fields = (chunk.integrator, chunk.y0, chunk.params, chunk.t_end, chunk.names)
        future = self.client.submit(
            _task, self.key, self.shared, *fields, chunk.save_every, chunk.lead, pure=False
        )
        self.futures.append(future)
        self.made[future] = chunk
        return future

    def run(self, distributed, pending: Iterator[Chunk], progress) -> list[Outputs]:
        total, done, outputs = max(1, self.chunks.count), 0, {}
        if progress is not None:
            progress(0.0)  # the start: a budget counts from here
        threads = max(1, sum(self.client.nthreads().values()))
        started = [self.submit(pending) for _ in range(threads)]
        running = distributed.as_completed([future for future in started if future is not None])
        for future in running:
            chunk = self.made[future]
            outputs[future], seconds = future.result()
            self.chunks.took(chunk, seconds)
            done += chunk.count
            if progress is not None:
                progress(done / total)
            following = self.submit(pending)
            if following is not None:
                running.add(following)
        return [outputs[future] for future in self.futures]

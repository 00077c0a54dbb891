"""The dask backend: the numpy path on the workers of a ``dask.distributed`` cluster.

A :class:`~lagrangian.numeric.compiled.CompiledSystem` holds closures and
locks that do not pickle, so the model travels instead: its equations of
motion, the function definitions and the Baumgarte rate (cloudpickled once),
and each worker process compiles them on first use and keeps the result
(keyed by a hash of the payload).  Each chunk of members is one task running
:func:`~lagrangian.ensemble.numpy_backend.integrate_chunk`; the results come
back in chunk order.

Without ``scheduler`` a ``LocalCluster`` of two worker processes, one thread
each, is started for the run and closed after it; with an address
(``tcp://host:port``) the run uses that cluster.  dask is imported here only
(``pip install ".[dask]"``).
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from ..errors import MissingDependencyError, ModelError
from .numpy_backend import integrate_chunk

if TYPE_CHECKING:
    from ..integrate.fixed_step import AbstractFixedStepIntegrator
    from ..numeric.compiled import CompiledSystem

#: Compiled systems of this worker process, by payload hash.
_WORKER_SYSTEMS: dict[str, CompiledSystem] = {}


def _distributed():
    try:
        import cloudpickle
        import distributed
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingDependencyError("backend 'dask'", "dask.distributed", "dask") from None
    return distributed, cloudpickle


def model_payload(compiled: CompiledSystem) -> bytes:
    """What a worker needs to compile ``compiled`` again, as bytes."""
    from ..numeric.compile import DEFAULT_BAUMGARTE

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


def _task(key, payload, integrator, y0, params, t_end, names, save_every):
    compiled = compiled_from_payload(key, payload)
    return integrate_chunk(compiled, integrator, y0, params, t_end, names, save_every=save_every)


def integrate_dask(
    compiled: CompiledSystem,
    integrator: AbstractFixedStepIntegrator,
    chunks: list[tuple[np.ndarray, np.ndarray]],
    t_end: float,
    names: tuple[str, ...],
    *,
    save_every: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[float], None] | None = None,
) -> list[dict[str, np.ndarray]]:
    """The chunks' results (in order), integrated on a dask cluster; see the module."""
    distributed, _ = _distributed()
    payload = model_payload(compiled)
    key = hashlib.sha256(payload).hexdigest()
    cluster = None
    if scheduler:
        try:
            client = distributed.Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as error:
            raise ModelError(f"cannot reach the dask scheduler {scheduler}: {error}") from None
    else:
        cluster = distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = distributed.Client(cluster)
    try:
        shared = client.scatter(payload, broadcast=True)
        futures = [
            client.submit(
                _task, key, shared, integrator, y0, p, t_end, names, save_every, pure=False
            )
            for y0, p in chunks
        ]
        for done, _ in enumerate(distributed.as_completed(futures), start=1):
            if progress is not None:
                progress(done / len(futures))
        return client.gather(futures)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

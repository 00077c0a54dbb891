"""`run_ensemble`: many runs of one compiled system, the single run applied to a batch.

The members (initial values and parameters, broadcast together; see
:mod:`.members`) are split into chunks of ``chunk_size`` so memory stays
bounded whatever the ensemble's size.  With ``chunk_seconds`` (a run with a
time budget) the backends size their chunks by measured time instead
(:class:`~.chunk.Chunks`; not jax, which compiles per chunk size): a small first
chunk, then each sized from the time per member so far to take about
``chunk_seconds`` (``chunk_size`` the largest), so a budget checked between chunks
is kept within a chunk's time whatever one member costs.  The time is
:func:`budget_clock`'s: this process's CPU time, or the wall clock for a backend
that computes elsewhere.  Each :class:`~.chunk.Chunk` is
integrated by a backend, a class of :data:`ENSEMBLE_BACKENDS` (the protocol is in
:mod:`.chunk`):

- ``numpy``: the single-run fixed-step integrator (rk4 or variational)
  stepping the chunk's states (2n, B) (:mod:`.numpy_backend`);
- ``numba``: a parallel (prange over members) fixed-step loop (rk4 or
  variational) around scalar expressions compiled by numba from the same
  symbolic equations (:mod:`.numba_backend`; optional dependency);
- ``jax``: the same fixed-step loop over the equations compiled by the JAX
  array backend, one ``jax.jit`` per run shape, on JAX's default device (a GPU
  when one is there; :mod:`.jax_backend`; optional dependency);
- ``cuda``: generated CUDA C, one GPU thread per member with the whole
  fixed-step loop in the kernel, compiled at run time by CuPy
  (:mod:`.cuda_backend`; optional dependency, needs an NVIDIA GPU);
- ``dask``: the numpy path on the workers of a ``dask.distributed`` cluster
  (:mod:`.dask_backend`; optional dependency).

``precision`` is ``float64`` (every backend) or ``float32`` (jax and cuda, where
GPUs are several times faster in single precision).

The step grid is the single run's (dt, the last step landing on t_end), so a
member's result equals a single :func:`~lagrangian.integrate.simulate` run
with the same method and dt.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Iterable, Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np
import xarray as xr

from ..budget import cpu_seconds
from ..errors import LagrangianError, LagrangianWarning, ModelError, setting
from ..integrate import method_class
from ..integrate.base import check_time_span
from ..integrate.fixed_step import AbstractFixedStepIntegrator, led_grid
from ..integrate.memory import check_fits, count_text, step_count
from ..integrate.start import constrained_start
from ..integrate.step_size import fixed_step_for
from ..model.impacts import refuse_impacts
from .choices import BACKENDS, METHODS, PRECISIONS
from .chunk import AbstractEnsembleBackend, Chunk, Chunks
from .cuda_backend import CudaBackend
from .dask_backend import DaskBackend
from .jax_backend import JaxBackend
from .members import Members, members
from .numba_backend import NumbaBackend
from .numpy_backend import NumpyBackend
from .observables import INDICATORS, indicator_refusal, observable_names
from .result import EnsembleTrajectory

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Backend name (``--backend``) -> class: how the chunks are integrated (see .chunk).
ENSEMBLE_BACKENDS: Mapping[str, type[AbstractEnsembleBackend]] = MappingProxyType(
    {kind.name: kind for kind in (NumpyBackend, NumbaBackend, JaxBackend, CudaBackend, DaskBackend)}
)
#: The backends that compute the observable ``lyapunov`` (the others refuse it at once).
LYAPUNOV_BACKENDS = ("numpy", "numba", "jax", "dask")
#: The backends that compute the chaos indicators (sali, gali<k>).
INDICATOR_BACKENDS = ("numpy", "numba")
#: The (2n)-vectors of work per member of a chunk (stages, Newton, observables).
WORK_VECTORS = 40
#: The wall clock of a run computed elsewhere (a name, so that tests can move it).
wall_seconds = time.monotonic


def run_ensemble(
    compiled: CompiledSystem,
    *,
    initial: Mapping[str, object] | None = None,
    params: Mapping[str, object] | None = None,
    t_end: float,
    method: str = "rk4",
    dt: float | None = None,
    backend: str = "numpy",
    observables: str | Iterable[str] = ("final_state",),
    save_every: int | None = None,
    chunk_size: int | None = None,
    precision: str = "float64",
    scheduler: str | None = None,
    progress: Callable[[float], None] | None = None,
    chunk_seconds: float | None = None,
    memory_advice: str | None = None,
    lead: float = 0.0,
) -> EnsembleTrajectory:
    """Integrate every member from t = 0 to ``t_end``; see the module docstring.

    ``initial`` / ``params`` map names to values (scalars, lists, grids); the
    rest come from the model.  ``dt`` defaults to t_end / 1000.
    ``save_every``: also keep every k-th step's state (paths).  ``scheduler``:
    the address of a dask scheduler (backend ``dask``; default a local cluster
    of two worker processes).  ``chunk_size``: members per chunk (default
    65,536; 2^20 on the GPU backends).  ``progress`` is called with the fraction done.
    ``chunk_seconds``: seconds a chunk should take on :func:`budget_clock` (chunks sized
    by measured time, at most ``chunk_size``; not jax; a budget gives 1.5 % of itself).
    ``memory_advice``: what to change when the ensemble would not fit in memory, in the
    settings of a caller that chose these for its user (a bifurcation diagram's values,
    samples and transient); by default the ensemble's own (members, dt, save_every).
    ``lead`` (with ``save_every``; 0 <= lead <= t_end): the first ``save_every`` steps span
    [0, lead] and the steps of ``dt`` start there, so the states kept after t = 0 fall at
    lead + k save_every dt, a strobe at a phase
    (:func:`~lagrangian.integrate.fixed_step.led_grid`).
    """
    t0, t1 = check_time_span((0.0, t_end))
    refuse_impacts(getattr(compiled.equations, "system", None), "an ensemble")
    if method not in METHODS:
        raise ModelError(f"unknown ensemble method '{method}' (methods: {', '.join(METHODS)})")
    if backend not in BACKENDS:
        raise ModelError(f"unknown backend '{backend}' (backends: {', '.join(BACKENDS)})")
    if precision not in PRECISIONS:
        raise ModelError(f"unknown precision '{precision}' (precisions: {', '.join(PRECISIONS)})")
    kind = ENSEMBLE_BACKENDS[backend]
    if precision not in kind.precisions:
        offered = " or ".join(
            other.name for other in ENSEMBLE_BACKENDS.values() if precision in other.precisions
        )
        raise ModelError(f"precision {precision} needs backend {offered} (not {backend})")
    if scheduler is not None and backend != "dask":
        raise ModelError(f"a dask scheduler needs backend dask (not {backend})")
    # the scheduler's address is checked here, before the model is compiled and the members made
    runner = kind() if scheduler is None else DaskBackend(scheduler)
    if chunk_size is None:
        chunk_size = kind.chunk_size
    names = observable_names(observables)
    if "lyapunov" in names and backend not in LYAPUNOV_BACKENDS:
        offered = ", ".join(LYAPUNOV_BACKENDS)
        raise ModelError(f"observable lyapunov runs on backends {offered}, not {backend}")
    for name in names:
        if name in INDICATORS and backend not in INDICATOR_BACKENDS:
            offered = ", ".join(INDICATOR_BACKENDS)
            raise ModelError(f"observable {name} runs on backend {offered}, not {backend}")
        if name in INDICATORS and INDICATORS[name] > 2 * compiled.n:
            raise ModelError(
                f"observable {name} needs {INDICATORS[name]} deviation vectors: the state of "
                f"{compiled.n} coordinates has {2 * compiled.n} dimensions"
            )
        refusal = indicator_refusal(compiled, name) if name in INDICATORS else None
        if refusal:
            raise ModelError(refusal)
    integrator = method_class(method).configure(t_span=(t0, t1), dt=dt)
    assert isinstance(integrator, AbstractFixedStepIntegrator)
    integrator.check(compiled)
    if save_every is not None and (int(save_every) != save_every or save_every < 1):
        raise ModelError(f"save_every must be a whole number >= 1, not {save_every!r}")
    if int(chunk_size) != chunk_size or chunk_size < 1:
        raise ModelError(f"chunk_size must be a whole number >= 1, not {chunk_size!r}")
    lead = _lead_setting(lead, save_every, t1)
    steps = _steps(t1, integrator.dt, lead, save_every)

    def fits(count: int) -> None:
        kept = f", keeping {count_text(steps // save_every + 1)} states each" if save_every else ""
        check_fits(
            ensemble_bytes(compiled, count, steps, names, save_every, int(chunk_size)),
            f"an ensemble of {count_text(count)} members{kept} ({count_text(steps)} steps)",
            memory_advice
            or f"use fewer members (fewer points per {setting('grid')}), or fewer steps "
            f"(a larger {setting('dt')})"
            + (f" or fewer states kept (a larger {setting('save_every')})" if save_every else ""),
        )

    batch = members(compiled, initial, params, before_allocating=fits)
    if compiled.has_constraints and compiled.project is not None:
        batch = _projected(compiled, batch)
    # the step from the members' time scale (or the given one checked against it)
    integrator = fixed_step_for(type(integrator), compiled, (t0, t1), dt, batch.y0, batch.params)
    steps = _steps(t1, integrator.dt, lead, save_every)
    fits(batch.count)  # again with the step chosen

    def chunk(start: int, stop: int) -> Chunk:
        p = batch.params[:, start:stop] if batch.params.ndim == 2 else batch.params
        y0 = batch.y0[:, start:stop]
        return Chunk(compiled, integrator, y0, p, t1, names, save_every, precision, lead)

    timed = None if kind.compiles_per_shape else chunk_seconds
    chunks = Chunks(chunk, batch.count, int(chunk_size), seconds=timed, clock=budget_clock(backend))
    start = time.perf_counter()
    parts = runner.run(chunks, progress)
    wall_time = time.perf_counter() - start
    grid = led_grid(t1, integrator.dt, lead, int(save_every or 0))
    result = _assemble(
        compiled, integrator, batch, parts, names, grid, backend, wall_time, save_every, precision
    )
    _report_failures(result, integrator)
    return result


def _lead_setting(lead: float, save_every: int | None, t_end: float) -> float:
    """``lead`` as a float, or ModelError when it is not a time in [0, t_end] or is given
    without ``save_every`` (it places the states kept: without them it means nothing)."""
    try:
        number = float(lead)
    except (TypeError, ValueError):
        raise ModelError(f"the lead must be a time, not {lead!r}") from None
    if not (np.isfinite(number) and 0.0 <= number <= t_end):
        raise ModelError(f"the lead must be a time from 0 to t_end = {t_end:g}, not {lead!r}")
    if number > 0.0 and not save_every:
        raise ModelError("a lead places the states kept: give save_every with it")
    return number


def _steps(t_end: float, dt: float, lead: float, save_every: int | None) -> int:
    """The steps of the run: those of dt from ``lead`` to t_end, and the lead's."""
    if lead <= 0.0:
        return step_count(0.0, t_end, dt)
    return (step_count(lead, t_end, dt) if t_end > lead else 0) + int(save_every or 0)


def _report_failures(result: EnsembleTrajectory, integrator: AbstractFixedStepIntegrator) -> None:
    """All members failed: the run failed (an error, as a failed single run); some: a warning."""
    failed = int(result.attrs["failed"])
    if not failed:
        return
    count = int(result.attrs["members"])
    what = f"the state is not finite by t_end with {integrator.name} dt = {integrator.dt:.3g}"
    if failed == count:
        raise LagrangianError(
            f"the ensemble integration failed for all {count_text(count)} members: {what}"
        )
    warnings.warn(
        LagrangianWarning(
            f"{count_text(failed)} of {count_text(count)} members failed ({what}); their "
            "results are NaN and the variable 'failed' marks them"
        ),
        stacklevel=3,
    )


def ensemble_bytes(
    compiled: CompiledSystem,
    count: int,
    steps: int,
    names: tuple[str, ...],
    save_every: int | None,
    chunk_size: int,
) -> float:
    """Bytes an ensemble of ``count`` members holds: per member the initial state and
    parameters (2n + P numbers), its observables twice (the chunks' and the joined
    arrays), its saved path (three copies: the chunks', the joined, the dataset's);
    the step grid; and the work arrays of one chunk (a few dozen 2n-vectors a member)."""
    state = 2 * compiled.n
    observables = sum(state if name == "final_state" else 1 for name in names)
    per_member = state + len(compiled.parameter_names) + 2 * observables
    if save_every:
        per_member += 3 * state * (steps // save_every + 1)
    work = WORK_VECTORS * state * min(count, chunk_size)
    return 8.0 * (float(count) * per_member + steps + 1 + work)


def _projected(compiled: CompiledSystem, batch: Members) -> Members:
    y0 = constrained_start(compiled, 0.0, batch.y0, batch.params)
    return Members(y0, batch.params, batch.shape, batch.dims, batch.coords)


def runs_elsewhere(backend: str) -> bool:
    """Whether ``backend`` computes away from this process's CPU (a GPU, dask's workers):
    its time budget is then wall time, as CPU time here would hardly move."""
    if backend == "jax":
        try:
            import jax
        except ImportError:  # the backend says so itself, when it is run
            return False
        return jax.default_backend() != "cpu"
    return backend in ("cuda", "dask")


def budget_clock(backend: str) -> Callable[[], float]:
    """The seconds a run on ``backend`` is timed in: this process's CPU time (every thread
    and the children it waited for), or the wall clock where the work is done elsewhere."""
    return wall_seconds if runs_elsewhere(backend) else cpu_seconds


def _assemble(
    compiled, integrator, batch, parts, names, grid, backend, wall_time, save_every, precision
):
    steps = int(parts[0]["steps"])
    data_vars = {}
    keys = [key for key in parts[0] if key not in ("paths", "steps")]
    for key in keys:
        values = np.concatenate([part[key] for part in parts]).reshape(batch.shape)
        data_vars[key] = (batch.dims, values)
    coords: dict[str, object] = dict(batch.coords)
    if "paths" in parts[0]:
        paths = np.concatenate([part["paths"] for part in parts], axis=1)
        state_names = [*compiled.coordinate_names]
        state_names += [f"{q}_dot" for q in compiled.coordinate_names]
        count = paths.shape[-1]
        for i, name in enumerate(state_names):
            data_vars[f"path_{name}"] = (
                (*batch.dims, "t"),
                paths[i].reshape(*batch.shape, count),
            )
        coords["t"] = ("t", grid[::save_every][:count])
    system = getattr(compiled.equations, "system", None)
    trajectory_steps = batch.count * steps
    attrs = {
        "model": getattr(system, "name", ""),
        "method": integrator.name,
        "dt": float(integrator.dt),
        "t_end": float(grid[-1]),
        "backend": backend,
        "precision": precision,
        "members": batch.count,
        "steps": steps,
        "wall_time": float(wall_time),
        "trajectory_steps_per_second": trajectory_steps / wall_time if wall_time > 0 else 0.0,
        "observables": ",".join(names),
        "failed": int(np.count_nonzero(data_vars["failed"][1])),
    }
    return EnsembleTrajectory(xr.Dataset(data_vars, coords=coords, attrs=attrs))

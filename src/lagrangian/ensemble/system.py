"""`ensemble_of_system`: `System` -> `EnsembleTrajectory` with the model's defaults;
`bifurcation_of_system`: `System` -> `BifurcationDiagram`; `basins_of_system`: `System`
-> `BasinMap`."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING

from ..budget import RUN_SECONDS
from ..derive import derive
from ..errors import ModelError
from ..integrate.pace import ENSEMBLE_ADVICE, RunPace, watching
from .bifurcation import BifurcationDiagram, bifurcation_diagram
from .core import METHODS, budget_clock, run_ensemble
from .result import EnsembleTrajectory

if TYPE_CHECKING:
    from ..model import System
    from .basins import BasinMap

#: The share of a time budget one chunk of members should take (chunks sized by time).
CHUNK_SHARE = 0.015


def ensemble_of_system(
    system: System,
    *,
    t_end: float | None = None,
    method: str | None = None,
    dt: float | None = None,
    definitions: Mapping[str, str] | None = None,
    timeout: float | None = RUN_SECONDS,
    progress: Callable[[float], None] | None = None,
    **options: object,
) -> EnsembleTrajectory:
    """Run an ensemble of ``system`` (options as :func:`~lagrangian.ensemble.run_ensemble`).

    An explicit argument wins, then the model's ``[simulate]`` table (its
    method only when it is rk4 or variational), then t_end = 10, rk4 and
    dt = t_end / 1000.  ``timeout``: seconds the runs may take (None: no limit), judged
    from their progress (:mod:`lagrangian.integrate.pace`: after a second, an ensemble
    whose pace projects more than twice that is refused; a backend that compiles the
    whole loop reports progress per chunk).  The seconds are CPU time of this process
    (every thread), or wall time for a backend that computes elsewhere (a GPU, dask);
    the backends size their chunks to take ``CHUNK_SHARE`` of the budget each on that
    clock, so the budget is kept within a few percent (not jax, whose chunks are all of
    one size: a new size costs a compile; its budget is checked between chunks).
    """
    from ..simulation import DEFAULT_T_END

    settings = dict(system.simulate_settings)
    if method is None:
        method = settings.get("method") if settings.get("method") in METHODS else "rk4"
    if t_end is None:
        t_end = float(settings.get("t_end", DEFAULT_T_END))
    if dt is None and settings.get("dt") is not None:
        dt = float(settings["dt"])
    compiled, progress = _compiled_runs(system, definitions, timeout, progress, options)
    result = run_ensemble(compiled, t_end=t_end, method=method, dt=dt, progress=progress, **options)
    if system.units is not None:
        _name_units(result, system.units)
    return result


#: The units of observables that are not a state's: a time, a rate.
_OBSERVABLE_UNITS = {"flip_time": "s", "lyapunov": "1/s", "t": "s"}


def _name_units(result: EnsembleTrajectory, units) -> None:
    """CF ``units`` attributes on a dimensioned model's ensemble: each grid coordinate,
    final state and saved path by its name, and the observables that have one."""
    for name, variable in result.dataset.variables.items():
        name = str(name)
        base = name.removeprefix("final_").removeprefix("path_")
        unit = _OBSERVABLE_UNITS.get(name) or units.column_unit(base)
        if unit is not None:
            variable.attrs["units"] = unit


def bifurcation_of_system(
    system: System,
    *,
    vary: Mapping[str, object],
    definitions: Mapping[str, str] | None = None,
    timeout: float | None = RUN_SECONDS,
    progress: Callable[[float], None] | None = None,
    **options: object,
) -> BifurcationDiagram:
    """The bifurcation diagram of ``system`` over ``vary`` ({parameter: values}, one
    parameter); options as :func:`~lagrangian.ensemble.bifurcation.bifurcation_diagram`
    (variable, period or section, transient, samples, ...); ``timeout`` as for an ensemble;
    a section's runs go on for the model's t_end after the transient unless told."""
    from ..simulation import DEFAULT_T_END

    if len(vary) != 1:
        raise ModelError(f"vary one parameter, not {len(vary)}")
    if options.get("section") is not None and options.get("t_end") is None:
        options["t_end"] = float(system.simulate_settings.get("t_end", DEFAULT_T_END))
    ((parameter, values),) = vary.items()
    compiled, progress = _compiled_runs(system, definitions, timeout, progress, options)
    return bifurcation_diagram(
        compiled, parameter=parameter, values=values, progress=progress, **options
    )


def _compiled_runs(system, definitions, timeout, progress, options: dict):
    """(the compiled equations, the progress callback with the runs' pace watched); with a
    budget, ``options`` (the runs') get the chunks' share of it (``chunk_seconds``)."""
    from ..numeric import compile_equations

    pace = None
    if timeout is not None:
        pace = RunPace(
            (0.0, 1.0),
            timeout,
            describe=lambda done: f"{100 * done:.3g} % of the runs",
            advice=ENSEMBLE_ADVICE,
            clock=budget_clock(str(options.get("backend", "numpy"))),
        )
        options.setdefault("chunk_seconds", CHUNK_SHARE * pace.seconds)
    compiled = compile_equations(derive(system), definitions=definitions)
    return compiled, watching(pace, progress)


def basins_of_system(
    system: System,
    *,
    grid: Mapping[str, object],
    interval: float | None = None,
    definitions: Mapping[str, str] | None = None,
    timeout: float | None = RUN_SECONDS,
    progress: Callable[[float], None] | None = None,
    **options: object,
) -> BasinMap:
    """The basin map of ``system`` over ``grid`` (options as
    :func:`~lagrangian.ensemble.basins.basins_of_attraction`: period, phase, params,
    steps, cells, max_iterations, basin_hits, backend); without a strobe period the flow
    is sampled every ``interval`` (default: the model's t_end / 100); ``timeout`` as for an
    ensemble, the share of the starts labelled being the progress."""
    from ..simulation import DEFAULT_T_END
    from .basins import basins_of_attraction

    if options.get("period") is None and interval is None:
        interval = float(system.simulate_settings.get("t_end", DEFAULT_T_END)) / 100.0
    # the budget's clock is the backend's (the wall clock where JAX runs on a GPU)
    backend = {"backend": str(options.get("backend", "numba"))}
    compiled, progress = _compiled_runs(system, definitions, timeout, progress, backend)
    return basins_of_attraction(
        compiled, grid=grid, interval=interval, progress=progress, **options
    )

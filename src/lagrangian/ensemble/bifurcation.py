"""Bifurcation diagrams: a stroboscopic or a Poincaré section against a parameter, from
one ensemble.

Each value of the varied parameter is one member of an ensemble (any backend of
:func:`~lagrangian.ensemble.run_ensemble`: numpy, numba, jax, cuda, dask), integrated
by its fixed-step method from the same initial state.  With a strobe ``period`` the
points are the states of ``variable`` at t = ``phase`` + k period (phase default 0;
:mod:`lagrangian.integrate.strobe`), the first ``samples`` of them after ``transient``:
the step is period / ``steps_per_period``, the states are kept every period (the
ensemble's ``save_every``), and a phase > 0 is reached first by ``steps_per_period``
shorter steps (the ensemble's ``lead``), so the points are those of one map whatever
the transient.  One point for a periodic response at the strobe period, two after a
period doubling, a smear where the motion is chaotic.  With a ``section`` ("x = 0",
:mod:`lagrangian.integrate.section`) instead, every step is kept, the runs go on for
``t_end`` after the transient, and the points are ``variable`` at the first
``samples`` crossings after the transient, located between steps on the cubic
interpolant of the motion (:mod:`lagrangian.integrate.sampled_crossings`); a value
whose motion crosses fewer times has NaN for the rest.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import LagrangianWarning, ModelError, setting
from ..files import write_csv
from ..integrate.base import positive_setting, transient_setting
from ..integrate.strobe import Strobe
from ..provided import Provided

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Steps of the fixed-step method per strobe period, unless told.
DEFAULT_STEPS_PER_PERIOD = 200
#: Points kept per parameter value, unless told.
DEFAULT_SAMPLES = 100


@dataclass(frozen=True)
class BifurcationDiagram:
    """``points`` (M, samples) of ``variable`` at the times ``times`` for each of the M
    ``values`` of ``parameter``: the strobe times (samples,), shared, or the crossing
    times of a section (M, samples), NaN (as the point) past a value's last crossing."""

    # drawn by output/, given by the facade (see lagrangian.provided)
    plot = Provided()

    parameter: str
    values: np.ndarray
    variable: str
    points: np.ndarray
    times: np.ndarray
    settings: Mapping[str, object] = field(default_factory=dict)
    name: str = ""
    system: object = field(default=None, repr=False, compare=False)  # the model, if known

    def unit(self, name: str) -> str | None:
        """The SI unit of the parameter, t or the variable for a dimensioned model, else
        None."""
        units = getattr(self.system, "units", None)
        return None if units is None else units.column_unit(name)

    def to_csv(self, path: str | os.PathLike) -> Path:
        """The points as CSV: columns the parameter, t and the variable, atomically; a
        column with a unit is headed ``name [unit]``, as simulate's CSV."""
        names = (self.parameter, "t", self.variable)
        headers = [f"{name} [{unit}]" if (unit := self.unit(name)) else name for name in names]
        return write_csv(path, self.table(), headers)

    def table(self) -> np.ndarray:
        """(K, 3): parameter value, time, value of the variable, one row per point, value
        by value (a section's missing crossings left out)."""
        samples = self.points.shape[1]
        rows = np.column_stack(
            [
                np.repeat(self.values, samples),
                np.broadcast_to(self.times, self.points.shape).ravel(),
                self.points.ravel(),
            ]
        )
        return rows if "period" in self.settings else rows[np.isfinite(rows[:, 1])]


def bifurcation_diagram(
    compiled: CompiledSystem,
    *,
    parameter: str,
    values: object,
    variable: str,
    period: float | None = None,
    phase: float | None = None,
    section: str | None = None,
    direction: str = "+",
    transient: float = 0.0,
    samples: int = DEFAULT_SAMPLES,
    steps_per_period: int = DEFAULT_STEPS_PER_PERIOD,
    t_end: float | None = None,
    dt: float | None = None,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
    method: str = "rk4",
    backend: str = "numpy",
    progress: Callable[[float], None] | None = None,
    **options: object,
) -> BifurcationDiagram:
    """The states of ``variable`` (a coordinate or velocity) after the transient, every
    ``period`` (at t = ``phase`` + k period) or where the motion crosses ``section`` in
    ``direction`` ("+", "-", "both"; ``t_end`` after the transient, step ``dt``: by
    default chosen for the motion, :func:`~lagrangian.integrate.step_size.fixed_step_for`),
    for each of ``values`` of ``parameter``; see the module docstring.  ``options`` go to
    :func:`~lagrangian.ensemble.run_ensemble` (chunk_size, precision, scheduler)."""
    from .core import run_ensemble  # xarray: loaded when a diagram is made, not to name one

    names = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    if variable not in names:
        raise ModelError(f"'{variable}' is not a coordinate or velocity ({', '.join(names)})")
    if parameter not in compiled.parameter_names:
        known = ", ".join(compiled.parameter_names) or "none"
        raise ModelError(f"unknown parameter '{parameter}' (parameters: {known})")
    if (period is None) == (section is None):
        raise ModelError("give a strobe period or a section (one of them)")
    if phase is not None and period is None:
        raise ModelError("a phase goes with a strobe period, not with a section")
    transient = transient_setting(transient)
    for name, number in (("samples", samples), ("steps_per_period", steps_per_period)):
        if int(number) != number or number < 1:
            raise ModelError(f"{name} must be a whole number >= 1, not {number!r}")
    run = {
        "initial": initial, "params": {**(params or {}), parameter: values}, "method": method,
        "backend": backend, "progress": progress, **options,
    }  # fmt: skip
    if section is not None:
        return _section_diagram(
            compiled, parameter, values, variable, section, direction, transient,
            int(samples), t_end, dt, run,
        )  # fmt: skip
    strobe = Strobe.of(positive_setting("period", period), phase)
    first = strobe.first(transient)
    result = run_ensemble(
        compiled, t_end=float(strobe.time(first + int(samples) - 1)),
        dt=strobe.period / int(steps_per_period), save_every=int(steps_per_period),
        lead=strobe.phase, **run,
        memory_advice=(
            f"use fewer values of {setting('vary')}, fewer {setting('samples')} or a shorter "
            f"{setting('transient')}"
        ),
    )  # fmt: skip
    dataset = result.dataset
    path = dataset[f"path_{variable}"].values.reshape(-1, dataset.sizes["t"])
    # column 0 is t = 0; then t_k at column k, or with a lead (a phase) at column k + 1
    column = first + (1 if strobe.phase else 0)
    kept = slice(column, column + int(samples))
    settings = {
        "period": strobe.period, "phase": strobe.phase, "transient": transient,
        "samples": int(samples),
    }  # fmt: skip
    return _diagram(
        compiled, result, parameter, values, variable, path[:, kept], dataset["t"].values[kept],
        settings,
    )  # fmt: skip


def _section_diagram(
    compiled, parameter, values, variable, text, direction, transient, samples, t_end, dt, run
) -> BifurcationDiagram:
    """The diagram of ``variable`` where the motions cross the section ``text``."""
    from ..integrate.sampled_crossings import sampled_crossings
    from ..integrate.section import parse_section
    from .core import run_ensemble
    from .members import members

    if t_end is None:
        raise ModelError("a diagram from a section needs t_end, the time after the transient")
    t_end = positive_setting("t_end", t_end)
    section = parse_section(compiled, text, direction)
    advice = (
        f"use fewer values of {setting('vary')}, a shorter {setting('transient')} or "
        f"{setting('t_end')}, or a larger {setting('dt')}"
    )
    result = run_ensemble(
        compiled, t_end=transient + t_end, dt=dt, save_every=1, **run, memory_advice=advice
    )
    dataset = result.dataset
    states = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    paths = np.stack(
        [dataset[f"path_{name}"].values.reshape(-1, dataset.sizes["t"]) for name in states]
    )
    batch = members(compiled, run["initial"], run["params"])
    crossings = sampled_crossings(
        compiled, section, dataset["t"].values, paths, batch.params, after=transient,
        limit=samples,
    )  # fmt: skip
    settings = {
        "section": text, "direction": direction, "transient": transient, "t_end": t_end,
        "samples": samples,
    }  # fmt: skip
    points = crossings.states[states.index(variable)]
    _warn_uncrossed(section, parameter, np.isfinite(points).any(axis=1), transient, t_end)
    return _diagram(
        compiled, result, parameter, values, variable, points, crossings.times, settings
    )


def _warn_uncrossed(section, parameter: str, crossed: np.ndarray, transient, t_end) -> None:
    """Say for how many of the values the motion never crosses the section after the
    transient: those values have no points (a diagram of none is no result)."""
    missing = int(np.count_nonzero(~crossed))
    if not missing:
        return
    which = "none" if missing == crossed.size else f"{crossed.size - missing}"
    warnings.warn(
        LagrangianWarning(
            f"the motion crosses the section {section.text} (direction {section.direction_name}) "
            f"for {which} of the {crossed.size} values of {parameter} between t = "
            f"{transient:g} and {transient + t_end:g}: "
            + ("no points" if missing == crossed.size else f"{missing} have no points")
        ),
        stacklevel=3,
    )


def _diagram(
    compiled, result, parameter, values, variable, points, times, settings
) -> BifurcationDiagram:
    """The diagram of the ensemble ``result``, its run's settings added to ``settings``."""
    attrs = result.dataset.attrs
    varied = np.broadcast_to(np.asarray(values, dtype=float), (points.shape[0],)).copy()
    return BifurcationDiagram(
        parameter=parameter,
        values=varied,
        variable=variable,
        points=points,
        times=times,
        settings={
            **settings,
            "method": attrs["method"],
            "dt": attrs["dt"],
            "backend": attrs["backend"],
            "wall_time": attrs["wall_time"],
            "failed": attrs["failed"],
        },
        name=attrs["model"],
        system=getattr(compiled.equations, "system", None),
    )

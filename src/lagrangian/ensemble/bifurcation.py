"""Bifurcation diagrams: a stroboscopic section against a parameter, from one ensemble.

Each value of the varied parameter is one member of an ensemble (any backend of
:func:`~lagrangian.ensemble.run_ensemble`: numpy, numba, jax, cuda, dask), integrated
by its fixed-step method with ``steps_per_period`` steps per strobe period (dt =
period / steps_per_period) from the same initial state.  The states are kept every
period (the ensemble's ``save_every``); the first ``transient`` time (rounded up to
whole periods) is dropped, and the next ``samples`` states of ``variable`` are the
diagram's points for that value: one point for a periodic response at the strobe
period, two after a period doubling, a smear where the motion is chaotic.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..files import write_csv
from ..integrate.base import positive_setting

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Steps of the fixed-step method per strobe period, unless told.
DEFAULT_STEPS_PER_PERIOD = 200
#: Points kept per parameter value, unless told.
DEFAULT_SAMPLES = 100


@dataclass(frozen=True)
class BifurcationDiagram:
    """``points`` (M, samples) of ``variable`` at the strobe times ``times`` (samples,),
    for each of the M ``values`` of ``parameter``."""

    parameter: str
    values: np.ndarray
    variable: str
    points: np.ndarray
    times: np.ndarray
    settings: Mapping[str, object] = field(default_factory=dict)
    name: str = ""
    system: object = field(default=None, repr=False, compare=False)  # the model, if known

    def to_csv(self, path: str | os.PathLike) -> Path:
        """The points as CSV: columns the parameter, t and the variable, atomically."""
        return write_csv(path, self.table(), (self.parameter, "t", self.variable))

    def table(self) -> np.ndarray:
        """(M * samples, 3): parameter value, time, value of the variable, row by row."""
        count, samples = self.points.shape
        return np.column_stack(
            [
                np.repeat(self.values, samples),
                np.tile(self.times, count),
                self.points.ravel(),
            ]
        )


def bifurcation_diagram(
    compiled: CompiledSystem,
    *,
    parameter: str,
    values: object,
    variable: str,
    period: float,
    transient: float = 0.0,
    samples: int = DEFAULT_SAMPLES,
    steps_per_period: int = DEFAULT_STEPS_PER_PERIOD,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
    method: str = "rk4",
    backend: str = "numpy",
    progress: Callable[[float], None] | None = None,
    **options: object,
) -> BifurcationDiagram:
    """The stroboscopic states of ``variable`` (a coordinate or velocity) after the
    transient, for each of ``values`` of ``parameter``; see the module docstring.
    ``options`` go to :func:`~lagrangian.ensemble.run_ensemble` (chunk_size, precision,
    scheduler)."""
    from .core import run_ensemble  # xarray: loaded when a diagram is made, not to name one

    names = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    if variable not in names:
        raise ModelError(f"'{variable}' is not a coordinate or velocity ({', '.join(names)})")
    if parameter not in compiled.parameter_names:
        known = ", ".join(compiled.parameter_names) or "none"
        raise ModelError(f"unknown parameter '{parameter}' (parameters: {known})")
    period = positive_setting("period", period)
    transient = float(transient)
    if not (math.isfinite(transient) and transient >= 0):
        raise ModelError(f"the transient must be a time >= 0, not {transient:g}")
    for name, number in (("samples", samples), ("steps_per_period", steps_per_period)):
        if int(number) != number or number < 1:
            raise ModelError(f"{name} must be a whole number >= 1, not {number!r}")
    dropped = math.ceil(transient / period - 1e-9)
    t_end = (dropped + int(samples)) * period
    result = run_ensemble(
        compiled, initial=initial, params={**(params or {}), parameter: values}, t_end=t_end,
        method=method, dt=period / int(steps_per_period), backend=backend,
        save_every=int(steps_per_period), progress=progress, **options,
    )  # fmt: skip
    dataset = result.dataset
    path = dataset[f"path_{variable}"].values.reshape(-1, dataset.sizes["t"])
    kept = slice(dropped + 1, dropped + 1 + int(samples))  # column 0 is t = 0
    attrs = dataset.attrs
    varied = np.broadcast_to(np.asarray(values, dtype=float), (path.shape[0],)).copy()
    return BifurcationDiagram(
        parameter=parameter,
        values=varied,
        variable=variable,
        points=path[:, kept],
        times=dataset["t"].values[kept],
        settings={
            "period": period,
            "transient": dropped * period,
            "samples": int(samples),
            "method": attrs["method"],
            "dt": attrs["dt"],
            "backend": attrs["backend"],
            "wall_time": attrs["wall_time"],
            "failed": attrs["failed"],
        },
        name=attrs["model"],
        system=getattr(compiled.equations, "system", None),
    )

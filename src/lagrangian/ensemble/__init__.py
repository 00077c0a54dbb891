"""Ensembles: many runs of one system at once, the single run applied to a batch.

:func:`run_ensemble` integrates a grid or list of initial values and
parameters with the fixed-step single-run methods (rk4, variational) on a
backend (``numpy``, ``numba``, ``dask``) and returns an
:class:`EnsembleTrajectory` (an xarray Dataset of observables, final states
and optional paths).  :func:`ensemble_of_system` does the same from a
:class:`~lagrangian.model.System` with the model's ``[simulate]`` defaults.
"""

from __future__ import annotations

from .core import BACKENDS, DEFAULT_CHUNK_SIZE, METHODS, run_ensemble
from .observables import OBSERVABLES, Observable, observable_names
from .result import EnsembleTrajectory
from .system import ensemble_of_system

__all__ = [
    "BACKENDS",
    "DEFAULT_CHUNK_SIZE",
    "METHODS",
    "OBSERVABLES",
    "EnsembleTrajectory",
    "Observable",
    "ensemble_of_system",
    "observable_names",
    "run_ensemble",
]

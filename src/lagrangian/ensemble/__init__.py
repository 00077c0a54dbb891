"""Ensembles: many runs of one system at once, the single run applied to a batch.

:func:`run_ensemble` integrates a grid or list of initial values and
parameters with the fixed-step single-run methods (rk4, variational) on a
backend (``numpy``, ``numba``, ``dask``) and returns an
:class:`EnsembleTrajectory` (an xarray Dataset of observables, final states
and optional paths).  :func:`ensemble_of_system` does the same from a
:class:`~lagrangian.model.System` with the model's ``[simulate]`` defaults.
"""

from __future__ import annotations

from ..lazy import on_use
from .choices import BACKENDS, METHODS

#: Public name -> the module that defines it, imported on first use: the runner brings
#: xarray and the integrators, which the command line does not need to list its choices.
_LAZY = {
    "DEFAULT_CHUNK_SIZE": ".chunk",
    "run_ensemble": ".core",
    "OBSERVABLES": ".observables",
    "Observable": ".observables",
    "observable_names": ".observables",
    "EnsembleTrajectory": ".result",
    "ensemble_of_system": ".system",
    "bifurcation_of_system": ".system",
    "BifurcationDiagram": ".bifurcation",
}
__getattr__ = on_use(__name__, _LAZY)


__all__ = [
    "BACKENDS",
    "DEFAULT_CHUNK_SIZE",
    "METHODS",
    "OBSERVABLES",
    "BifurcationDiagram",
    "EnsembleTrajectory",
    "Observable",
    "bifurcation_of_system",
    "ensemble_of_system",
    "observable_names",
    "run_ensemble",
]

"""`ensemble_of_system`: `System` -> `EnsembleTrajectory` with the model's defaults."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from .core import METHODS, run_ensemble
from .result import EnsembleTrajectory

if TYPE_CHECKING:
    from ..model import System


def ensemble_of_system(
    system: System,
    *,
    t_end: float | None = None,
    method: str | None = None,
    dt: float | None = None,
    definitions: Mapping[str, str] | None = None,
    **options: object,
) -> EnsembleTrajectory:
    """Run an ensemble of ``system`` (options as :func:`~lagrangian.ensemble.run_ensemble`).

    An explicit argument wins, then the model's ``[simulate]`` table (its
    method only when it is rk4 or variational), then t_end = 10, rk4 and
    dt = t_end / 1000.
    """
    from ..numeric import compile_equations
    from ..simulation import DEFAULT_T_END

    settings = dict(system.simulate_settings)
    if method is None:
        method = settings.get("method") if settings.get("method") in METHODS else "rk4"
    if t_end is None:
        t_end = float(settings.get("t_end", DEFAULT_T_END))
    if dt is None and settings.get("dt") is not None:
        dt = float(settings["dt"])
    compiled = compile_equations(system.equations_of_motion(), definitions=definitions)
    return run_ensemble(compiled, t_end=t_end, method=method, dt=dt, **options)

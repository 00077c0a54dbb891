"""Integration: one motion of a `CompiledSystem` -> `Trajectory`.

``simulate(compiled, t_end=..., method=...)`` is the entry point; the methods
(registry ``METHODS``) are ``dop853`` and ``radau`` (SciPy, adaptive; dop853's loop
compiled on the numba backend),
``rk4`` (fixed step), ``variational`` (fixed step, symplectic) and ``taylor``
(heyoka's Taylor method, optional: ``pip install ".[taylor]"``).  Without a method or
backend, ``choice.choose_run`` picks them for the run's length.
"""

from .base import AbstractIntegrator, IntegrationResult, Status
from .events import Event
from .explicit_rk import RK4, RK38, AbstractExplicitRungeKutta
from .fixed_step import AbstractFixedStepIntegrator
from .registry import METHODS, method_class
from .scipy_methods import AbstractScipyIntegrator, Dop853, Radau
from .simulate import simulate
from .tableaus import ButcherTableau
from .variational import Variational

__all__ = [
    "METHODS",
    "RK4",
    "RK38",
    "AbstractExplicitRungeKutta",
    "AbstractFixedStepIntegrator",
    "AbstractIntegrator",
    "AbstractScipyIntegrator",
    "ButcherTableau",
    "Dop853",
    "Event",
    "IntegrationResult",
    "Radau",
    "Status",
    "Variational",
    "method_class",
    "simulate",
]

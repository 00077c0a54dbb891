"""The integrator protocol: `AbstractIntegrator`, its result and its work counter.

An integrator advances the state ``y = [q, q']`` of a
:class:`~lagrangian.numeric.compiled.CompiledSystem` (conventions in that
module: argument order ``(t, y, params)``, a trailing batch axis everywhere).
Every concrete integrator is a small frozen dataclass holding its settings
(``dt`` or ``rtol``/``atol``); what it can do is declared by class constants,
which the driver (:func:`~lagrangian.integrate.simulate.simulate`) reads
before running:

- ``name``: the registry key (``--method NAME``);
- ``order``: the global order of accuracy p (error O(h^p));
- ``symplectic``: whether the discrete flow preserves the symplectic form
  (then the energy error stays bounded over exponentially long times,
  Hairer, Lubich & Wanner, *Geometric Numerical Integration*, 2nd ed. 2006, IX.8);
- ``adaptive``: step size chosen from ``rtol``/``atol`` (else a fixed ``dt``);
- ``batched``: whether ``solve`` accepts a batch of states ``y0`` of shape (2n, B);
- ``needs``: the form of the problem it integrates, ``"first_order"``
  (the right-hand side y' = rhs(t, y)) or ``"lagrangian"`` (L and its
  derivatives, for variational integrators).

``check(compiled)`` raises one :class:`~lagrangian.errors.ModelError` when the
method does not fit the system (e.g. a variational integrator and constraints).
"""

from __future__ import annotations

import abc
import enum
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Literal

import numpy as np

from ..errors import ModelError, setting
from .events import named
from .guard import start_problem

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem
    from ..trajectory import EventRecord
    from .events import Event


class Status(enum.Enum):
    """How an integration ended."""

    SUCCESS = "success"  # reached t_end
    EVENT = "event"  # stopped by a terminal event
    FAILED = "failed"  # the method gave up (step size underflow, Newton failure, non-finite state)


@dataclass
class Work:
    """Counts of the work done (never timed): steps and function evaluations."""

    steps: int = 0
    rhs_evaluations: int = 0
    jacobian_evaluations: int = 0
    newton_iterations: int = 0


@dataclass(frozen=True, eq=False)
class IntegrationResult:
    """What an integrator returns: the states at the output times and the work done.

    ``y`` has shape (2n, T) for one trajectory, (2n, B, T) for a batch (time is
    the last axis, so ``y[..., k]`` is a valid state argument of the compiled
    functions).  ``events`` holds one record per event, in the order given,
    even when it never occurred.  ``settings`` echoes every setting used,
    defaults included (``method``, ``rtol``/``atol`` or ``dt``, ...).
    ``rhs_evaluations`` counts evaluations of the right-hand side (for the
    variational integrator: of the set L_q', L_q, Q that replaces it).
    """

    t: np.ndarray
    y: np.ndarray
    status: Status
    message: str
    steps: int
    rhs_evaluations: int
    jacobian_evaluations: int
    events: tuple[EventRecord, ...]
    settings: Mapping[str, object]

    @property
    def success(self) -> bool:
        return self.status is not Status.FAILED


class AbstractIntegrator(abc.ABC):
    """An integration method: class constants declare it, ``solve`` runs it.

    ``solve(compiled, t_span, y0, params, t_eval=None, events=())`` integrates
    from ``t_span[0]`` to ``t_span[1]`` (> ``t_span[0]``) and returns an
    :class:`IntegrationResult`: at the times ``t_eval`` when given (sorted,
    inside ``t_span``), otherwise at every step.  The last output of a run that
    is not stopped by an event is the state at ``t_span[1]`` exactly.
    """

    name: ClassVar[str]
    order: ClassVar[int]
    symplectic: ClassVar[bool]
    adaptive: ClassVar[bool]
    batched: ClassVar[bool]
    needs: ClassVar[Literal["first_order", "lagrangian"]]

    @classmethod
    @abc.abstractmethod
    def configure(
        cls,
        *,
        t_span: tuple[float, float],
        dt: float | None = None,
        rtol: float | None = None,
        atol: float | None = None,
    ) -> AbstractIntegrator:
        """An instance from the user's settings; a setting that does not apply is an error."""

    def check(self, compiled: CompiledSystem) -> None:
        """Raise ModelError when this method cannot integrate ``compiled`` (default: all fit)."""
        return None

    @abc.abstractmethod
    def settings(self) -> dict[str, object]:
        """Every setting of this instance (defaults included), for results and files."""

    def prepare(self, compiled: CompiledSystem, y0: np.ndarray, params: np.ndarray) -> str | None:
        """Make (or load from the code cache) the compiled code a run of ``compiled`` needs
        besides its right-hand side, before the run, so that its cost is measured apart
        (the run's ``compile_time``); what it made, in words, or None where nothing
        (default)."""
        return None

    def kept_steps(self, t_span: tuple[float, float]) -> int | None:
        """How many steps ``solve`` keeps over ``t_span`` (None: unknown before the run)."""
        return None

    def settings_for(self, compiled: CompiledSystem) -> dict[str, object]:
        """The settings as used on ``compiled`` (a method may add what it chose for it)."""
        return self.settings()

    def solve(
        self,
        compiled: CompiledSystem,
        t_span: tuple[float, float],
        y0: np.ndarray,
        params: np.ndarray,
        *,
        t_eval: np.ndarray | None = None,
        events: Sequence[Event] = (),
        watch: Callable[[float], None] | None = None,
    ) -> IntegrationResult:
        """Integrate; see the class docstring.

        ``watch``, when given, is called with the time reached at least once per
        step, from Python, and may end the run by raising (a time budget, a
        progress bar).  The checks every method makes come first, here; the method's
        own work is :meth:`integrate`.
        """
        self.check(compiled)
        t0, t1 = check_time_span(t_span)
        y = np.array(y0, dtype=float)
        events = named(events)
        if y.ndim != 1 and not self.batched:
            raise ModelError(f"method '{self.name}' integrates one trajectory, not a batch")
        if y.ndim != 1 and events:
            raise ModelError("events are watched on a single trajectory, not on a batch")
        params = np.asarray(params, dtype=float)
        t_eval = None if t_eval is None else np.asarray(t_eval, dtype=float)
        problem = start_problem(compiled, t0, y, params)
        return self.integrate(compiled, Run(t0, t1, y, params, t_eval, events, watch, problem))

    @abc.abstractmethod
    def integrate(self, compiled: CompiledSystem, run: Run) -> IntegrationResult:
        """The method's own work on a checked ``run`` (a run whose start is already a
        problem, ``run.problem``, ends there as failed, as the method reports it)."""


@dataclass(frozen=True)
class Run:
    """One call of :meth:`AbstractIntegrator.solve`, checked: floats and arrays, the
    events named, and why the start state cannot be integrated (None when it can)."""

    t0: float
    t1: float
    y0: np.ndarray
    params: np.ndarray
    t_eval: np.ndarray | None
    events: tuple[Event, ...]
    watch: Callable[[float], None] | None
    problem: str | None


def positive_setting(name: str, value: float) -> float:
    """``value`` as a float, or ModelError when it is not finite and > 0."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ModelError(f"{name} must be a number, not {value!r}") from None
    if not np.isfinite(number) or number <= 0:
        raise ModelError(f"{name} must be a finite number > 0, not {value!r}")
    return number


def transient_setting(value: float) -> float:
    """The time run before a result is kept (``transient``) as a float, or ModelError when
    it is not a finite time >= 0: a negative one would integrate backwards first."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ModelError(f"the transient must be a time >= 0, not {value!r}") from None
    if not (np.isfinite(number) and number >= 0.0):
        raise ModelError(f"the transient must be a time >= 0, not {number:g}")
    return number


def tolerance_setting(name: str, value: float, *, method: str, floor: float, further: str) -> float:
    """``value`` as a float, or ModelError when it is not finite and > 0 or below ``floor``,
    the smallest tolerance ``method`` can use in double precision (``further``: where to go
    for less).  A smaller one would be raised to the floor (SciPy) or cost without bound
    (heyoka's Taylor order grows with -log(tol)) for no gain in accuracy."""
    number = positive_setting(name, value)
    if number < floor:
        raise ModelError(
            f"{name} = {number:g} is below what {method} can deliver in double precision: "
            f"give {setting(name)} {floor:.3g} or more{further}"
        )
    return number


def reject_settings(method: str, kind: str, **given: float | None) -> None:
    """ModelError naming the settings in ``given`` that were set but do not apply."""
    extra = [name for name, value in given.items() if value is not None]
    if extra:
        names = " and ".join(setting(name) for name in extra)
        raise ModelError(f"{names} does not apply to method '{method}' ({kind})")


def adaptive_settings(method: str, t_span: tuple[float, float], dt: float | None) -> None:
    """ModelError when an adaptive ``method`` is given a step size, or ``t_span`` is wrong."""
    reject_settings(method, f"an adaptive method: give {setting('rtol')}/{setting('atol')}", dt=dt)
    check_time_span(t_span)


def check_time_span(t_span: tuple[float, float]) -> tuple[float, float]:
    t0, t1 = (float(t) for t in t_span)
    if not (np.isfinite(t0) and np.isfinite(t1)) or t1 <= t0:
        raise ModelError(f"the end time must be finite and after the start time {t0:g}, not {t1!r}")
    return t0, t1

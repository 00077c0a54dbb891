"""SciPy's adaptive methods behind the integrator protocol: DOP853 and Radau IIA.

- ``dop853``: the explicit Runge-Kutta pair of order 8(5,3) of Dormand and
  Prince with 7th-order dense output (Hairer, Norsett & Wanner, *Solving ODEs I*,
  II.10).  The default for non-stiff motion.  Defaults rtol = 1e-10,
  atol = 1e-12.
- ``radau``: the implicit Radau IIA method of order 5 with the analytic
  Jacobian ``compiled.rhs_jacobian`` (Hairer & Wanner, *Solving ODEs II*,
  IV.8): for stiff systems (stiff springs, strong damping).  Defaults
  rtol = 1e-8, atol = 1e-10 (each step solves a nonlinear system, so tighter
  tolerances cost more there).

Neither is symplectic: the energy error of a conservative system drifts,
slowly at these tolerances.  Outputs are SciPy's steps, or with ``t_eval`` the
method's dense output there; events are located by ``solve_ivp`` on the dense
output (see :func:`~lagrangian.integrate.events.scipy_event`).  A run stopped
by a terminal event or a failure ends with the state where it stopped.

A start where y' is not finite fails at once (SciPy's first step size would be
NaN, and its loop would never end); a run that fails for want of a step size
after the right-hand side was not finite says so, with the last state reached;
radau stops where its Jacobian, taken at accepted states, is not finite (see
:mod:`lagrangian.integrate.guard`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..trajectory import EventRecord
from .base import (
    AbstractIntegrator,
    IntegrationResult,
    Run,
    Status,
    adaptive_settings,
    positive_setting,
    tolerance_setting,
)
from .compiled_dop853 import (
    compiled_loop,
    linked_loop,
    loop_applies,
    solve_compiled,
    what_is_compiled,
)
from .events import scipy_event
from .guard import UNDEFINED, describe_state, state_problem

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem
    from .compiled_dop853 import Loop

#: The smallest rtol SciPy's methods honour (100 machine epsilons); below it they use it.
MIN_RTOL = 100 * float(np.finfo(float).eps)

_STATUS = {0: Status.SUCCESS, 1: Status.EVENT, -1: Status.FAILED}


@dataclass(frozen=True)
class AbstractScipyIntegrator(AbstractIntegrator):
    """An adaptive method of ``scipy.integrate.solve_ivp`` (single trajectories)."""

    rtol: float
    atol: float
    scipy_method: ClassVar[str]
    uses_jacobian: ClassVar[bool] = False
    adaptive: ClassVar[bool] = True
    batched: ClassVar[bool] = False
    symplectic: ClassVar[bool] = False
    needs: ClassVar[str] = "first_order"

    def __post_init__(self) -> None:
        # SciPy would raise rtol to 100 eps and say so only in a warning
        tolerance_setting(
            "rtol",
            self.rtol,
            method=self.name,
            floor=MIN_RTOL,
            further=" (method taylor goes further)",
        )
        positive_setting("atol", self.atol)

    @classmethod
    def configure(cls, *, t_span, dt=None, rtol=None, atol=None):
        adaptive_settings(cls.name, t_span, dt)
        given = {"rtol": rtol, "atol": atol}
        return cls(
            **{name: positive_setting(name, v) for name, v in given.items() if v is not None}
        )

    def settings(self) -> dict[str, object]:
        return {"method": self.name, "rtol": self.rtol, "atol": self.atol}

    def integrate(self, compiled: CompiledSystem, run: Run) -> IntegrationResult:
        from scipy.integrate import solve_ivp

        t0, t1, y0, params, events, watch = (
            run.t0, run.t1, run.y0, run.params, run.events, run.watch
        )  # fmt: skip
        if run.problem is not None:  # SciPy's first step size would be NaN: it would never stop
            return self._stopped(compiled, [t0], [y0], run.problem, events)
        if watch is not None:  # the budget's clock starts before a compile, which counts
            watch(t0)
        loop = self.compiled_loop(compiled)
        if loop is not None:
            settings = self.settings_for(compiled)
            return solve_compiled(
                loop, compiled, run, rtol=self.rtol, atol=self.atol, settings=settings
            )
        # A trial stage may leave the domain of the equations (rejected, the step shrinks);
        # the last such evaluation explains a run that then fails for want of a step size.
        undefined: list[float] = []

        def fun(t: float, y: np.ndarray) -> np.ndarray:
            if watch is not None:
                watch(t)
            slope = compiled.rhs(t, y, params)
            if not np.all(np.isfinite(slope)):
                undefined[:] = [t]
            return slope

        def jac(t: float, y: np.ndarray) -> np.ndarray:
            jacobian = compiled.rhs_jacobian(t, y, params)
            if not np.all(np.isfinite(jacobian)):  # at an accepted state: no way on
                raise _Undefined(t, y)
            return jacobian

        options: dict[str, object] = {}
        if self.uses_jacobian:
            options["jac"] = jac
        if events:
            f0 = fun(t0, y0)
            options["events"] = [scipy_event(e, params, t0, y0, f0) for e in events]
        try:
            solution = solve_ivp(
                fun,
                (t0, t1),
                y0,
                method=self.scipy_method,
                rtol=self.rtol,
                atol=self.atol,
                dense_output=run.t_eval is not None,
                **options,
            )
        except _Undefined as stop:
            message = (
                f"the Jacobian of the right-hand side is not finite at t = {stop.t:.6g} "
                f"({describe_state(compiled, stop.y)}): {UNDEFINED}"
            )
            points = ([t0], [y0]) if stop.t == t0 else ([t0, stop.t], [y0, stop.y])
            return self._stopped(compiled, *points, message, events)
        status = _STATUS.get(solution.status, Status.FAILED)
        message = str(solution.message)
        if status is Status.FAILED:
            where = f"t = {solution.t[-1]:.6g} ({describe_state(compiled, solution.y[:, -1])})"
            message = f"{message.rstrip('.')} at {where}"
            if undefined:
                message = (
                    f"the right-hand side is not finite just after {where}, so no step "
                    f"size works: {UNDEFINED}, or the motion reaches a singularity"
                )
        finite = np.all(np.isfinite(solution.y), axis=0)
        if not finite.all():  # kept out by the error control, in case one slips through
            k = int(np.argmin(finite))
            status = Status.FAILED
            message = state_problem(
                compiled, solution.t[k - 1], solution.y[:, k - 1], solution.y[:, k]
            )
            solution.t, solution.y = solution.t[:k], solution.y[:, :k]
        t_out, y_out = solution.t, solution.y
        if run.t_eval is not None:
            t_out, y_out = _at(run.t_eval, solution, status)
        records = tuple(
            EventRecord(event.name, np.asarray(times, float), np.asarray(states, float).T)
            if len(times)
            else EventRecord(event.name, np.empty(0), np.empty((y0.shape[0], 0)))
            for event, times, states in zip(
                events, solution.t_events or [], solution.y_events or [], strict=False
            )
        )
        return IntegrationResult(
            t=t_out,
            y=y_out,
            status=status,
            message=message,
            steps=max(0, len(solution.t) - 1),
            rhs_evaluations=int(solution.nfev),
            jacobian_evaluations=int(solution.njev),
            events=records,
            settings=self.settings_for(compiled),
        )

    def compiled_loop(self, compiled: CompiledSystem) -> Loop | None:
        """The method's compiled loop for ``compiled`` (None: SciPy's loop runs)."""
        return None

    def _stopped(self, compiled, times, states, message, events) -> IntegrationResult:
        """The failed result of a run that stopped, SciPy's steps lost, at the last state."""
        size = states[0].shape[0]
        return IntegrationResult(
            t=np.array(times, dtype=float),
            y=np.stack(states, axis=-1),
            status=Status.FAILED,
            message=message,
            steps=0,
            rhs_evaluations=0,
            jacobian_evaluations=0,
            events=tuple(
                EventRecord(event.name, np.empty(0), np.empty((size, 0))) for event in events
            ),
            settings=self.settings_for(compiled),
        )


class _Undefined(Exception):
    """Raised inside SciPy's loop to stop it at (t, y), where the equations are not finite."""

    def __init__(self, t: float, y: np.ndarray):
        super().__init__(t)
        self.t, self.y = float(t), np.array(y, dtype=float)


def _at(t_eval: np.ndarray, solution, status: Status) -> tuple[np.ndarray, np.ndarray]:
    """The dense output at ``t_eval`` up to where the run stopped, then the stopping state."""
    inside = t_eval[t_eval <= solution.t[-1]]
    if solution.sol is None or not inside.size:
        states = np.empty((solution.y.shape[0], 0))
    else:
        states = solution.sol(inside).reshape(solution.y.shape[0], inside.size)
    if status is not Status.SUCCESS and (not inside.size or inside[-1] < solution.t[-1]):
        inside = np.append(inside, solution.t[-1])
        states = np.concatenate([states, solution.y[:, -1:]], axis=1)
    return inside, states


@dataclass(frozen=True)
class Dop853(AbstractScipyIntegrator):
    """Dormand-Prince 8(5,3), explicit, adaptive; rtol 1e-10, atol 1e-12 by default."""

    rtol: float = 1e-10
    atol: float = 1e-12
    name: ClassVar[str] = "dop853"
    order: ClassVar[int] = 8
    scipy_method: ClassVar[str] = "DOP853"

    #: On the llvm backend, the compiled loop too (:func:`.compiled_dop853.linked_loop`:
    #: the method compiled once on a machine, over SymEngine's M and f), not SciPy's loop.
    linked: bool = False

    def compiled_loop(self, compiled: CompiledSystem) -> Loop | None:
        """On the numba backend, the whole loop compiled (:mod:`.compiled_dop853`); on
        llvm with ``linked``, the same loop over the LLVM code of M and f."""
        if compiled.backend == "numba":
            return compiled_loop(compiled)
        if self.linked and compiled.backend == "llvm":
            return linked_loop(compiled)
        return None

    def prepare(self, compiled: CompiledSystem, y0: np.ndarray, params: np.ndarray) -> str | None:
        """The compiled loop made, or loaded from the code cache (see the base class)."""
        linked = compiled.backend == "llvm" and self.linked
        if not (linked or compiled.backend == "numba") or not loop_applies(compiled):
            return None
        paid = what_is_compiled(compiled, linked=linked)
        loop = self.compiled_loop(compiled)
        if loop is None:
            return None
        loop.prepare(np.shape(y0)[0], np.shape(params)[0])
        return paid


@dataclass(frozen=True)
class Radau(AbstractScipyIntegrator):
    """Radau IIA of order 5, implicit, adaptive, for stiff systems; rtol 1e-8, atol 1e-10."""

    rtol: float = 1e-8
    atol: float = 1e-10
    name: ClassVar[str] = "radau"
    order: ClassVar[int] = 5
    scipy_method: ClassVar[str] = "Radau"
    uses_jacobian: ClassVar[bool] = True

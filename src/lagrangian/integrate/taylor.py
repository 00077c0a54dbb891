"""Taylor's method through heyoka (optional): single runs at tolerances down to rounding.

heyoka (F. Biscani and D. Izzo, "Revisiting high-order Taylor methods for
astrodynamics and celestial mechanics", MNRAS 504 (2021) 2614-2628;
``pip install ".[taylor]"``) integrates an explicit ODE by adaptive
Taylor series of high order (15 to 25 here), generated as machine code by LLVM.
It is fed from our equations: M and f of M q'' = f (:mod:`lagrangian.numeric.forms`,
declared functions replaced by their definitions) converted with
``heyoka.from_sympy``, the parameters as heyoka's runtime parameters, and q'' =
M^{-1} f written out as Gaussian elimination in heyoka's expressions (M of an
unconstrained system is symmetric positive definite: no pivoting).

One tolerance ``tol`` (heyoka's: relative and absolute at once; default 1e-15)
sets the order and the step.  Measured (benchmarks/simulate.py --taylor): at
1e-15 it is 2-3 orders of magnitude faster than DOP853 for the same or smaller
error, at 1e-10 still about 100x.  Outputs are heyoka's steps, or with
``t_eval`` its dense output there.  Not handled: constraints, events, batches (use
dop853, radau or rk4).  The compiled integrator is kept per system and tolerance
(its first build takes 0.1 s for the double pendulum, about 1.5 s for a 10-link
chain).  A run fails with status ``failed`` where heyoka meets a state or a
derivative that is not finite.
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..errors import MissingDependencyError, ModelError
from .base import (
    AbstractIntegrator,
    IntegrationResult,
    Status,
    check_time_span,
    positive_setting,
    reject_settings,
)
from .events import Event

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

_BUILT: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_LOCK = threading.Lock()


@dataclass(frozen=True)
class Taylor(AbstractIntegrator):
    """Adaptive Taylor method of heyoka with tolerance ``tol``; see the module."""

    tol: float = 1e-15
    name: ClassVar[str] = "taylor"
    order: ClassVar[int] = 0  # variable: chosen from tol
    symplectic: ClassVar[bool] = False
    adaptive: ClassVar[bool] = True
    batched: ClassVar[bool] = False
    needs: ClassVar[str] = "first_order"

    def __post_init__(self) -> None:
        positive_setting("tol", self.tol)

    @classmethod
    def configure(cls, *, t_span, dt=None, rtol=None, atol=None):
        """``tol`` is the smaller of rtol and atol where given (heyoka has one tolerance)."""
        reject_settings(cls.name, "an adaptive method: give --rtol/--atol", dt=dt)
        check_time_span(t_span)
        given = [positive_setting(n, v) for n, v in (("rtol", rtol), ("atol", atol)) if v]
        return cls(tol=min(given) if given else cls.tol)

    def settings(self) -> dict[str, object]:
        return {"method": self.name, "tol": self.tol}

    def check(self, compiled: CompiledSystem) -> None:
        try:
            import heyoka  # noqa: F401
        except ImportError:
            raise MissingDependencyError("method 'taylor'", "heyoka", "taylor") from None
        if compiled.has_constraints:
            raise ModelError("method 'taylor' does not handle constraints: use dop853 or radau")

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
        import heyoka as hy

        self.check(compiled)
        if events:
            raise ModelError("method 'taylor' does not watch events: use dop853 or radau")
        t0, t1 = check_time_span(t_span)
        y0 = np.array(y0, dtype=float)
        if y0.ndim != 1:
            raise ModelError("method 'taylor' integrates one trajectory, not a batch")
        integrator = _integrator(compiled, self.tol)
        integrator.time = t0
        integrator.state[:] = y0
        integrator.pars[:] = np.asarray(params, dtype=float)
        status, message = Status.SUCCESS, "reached the end time"
        if t_eval is not None:
            grid = np.asarray(t_eval, dtype=float)
            outcome, _, _, steps, _, states = integrator.propagate_grid(
                grid, **_step_callback(watch)
            )
            times, values = grid, np.asarray(states).T
            if outcome != hy.taylor_outcome.time_limit:
                reached = int(np.searchsorted(grid, integrator.time, side="right"))
                times, values = grid[:reached], values[:, :reached]
        else:
            times, values, steps, outcome = [t0], [y0], 0, hy.taylor_outcome.time_limit
            while integrator.time < t1:
                outcome, _ = integrator.step(max_delta_t=t1 - integrator.time)
                steps += 1
                if watch is not None:
                    watch(integrator.time)
                if outcome not in (hy.taylor_outcome.success, hy.taylor_outcome.time_limit):
                    break
                times.append(integrator.time)
                values.append(np.array(integrator.state))
            times, values = np.array(times), np.stack(values, axis=-1)
        if outcome not in (hy.taylor_outcome.success, hy.taylor_outcome.time_limit):
            status = Status.FAILED
            message = f"heyoka stopped ({outcome.name}) at t = {float(integrator.time):.17g}"
        return IntegrationResult(
            t=np.asarray(times, dtype=float),
            y=values,
            status=status,
            message=message,
            steps=int(steps),
            rhs_evaluations=0,
            jacobian_evaluations=0,
            events=(),
            settings=self.settings_for(compiled),
        )


def _integrator(compiled: CompiledSystem, tol: float):
    """heyoka's compiled integrator of ``compiled`` at ``tol`` (built once, then kept)."""
    with _LOCK:
        built = _BUILT.setdefault(compiled, {})
        if tol not in built:
            built[tol] = _build(compiled, tol)
        return built[tol]


def _build(compiled: CompiledSystem, tol: float):
    import heyoka as hy

    from ..numeric.definitions import function_definitions
    from ..numeric.forms import symbolic_forms

    system = compiled.equations.system
    forms = symbolic_forms(
        compiled.equations, function_definitions(system, dict(compiled.definitions))
    )
    n = forms.n
    q = [hy.make_vars(f"q{i}") for i in range(n)]
    v = [hy.make_vars(f"v{i}") for i in range(n)]
    replace = {forms.time: hy.time}
    replace |= dict(zip(forms.coordinates, q, strict=True))
    replace |= dict(zip(forms.velocities, v, strict=True))
    replace |= {symbol: hy.par[j] for j, symbol in enumerate(forms.parameters)}
    mass, forcing = forms.mass_matrix, forms.forcing
    try:
        matrix = [[hy.from_sympy(mass[i, j], replace) for j in range(n)] for i in range(n)]
        force = [hy.from_sympy(forcing[i, 0], replace) for i in range(n)]
    except (TypeError, ValueError) as error:
        raise ModelError(f"method 'taylor' cannot express the equations: {error}") from None
    accelerations = eliminated(matrix, force)
    ode = [(q[i], v[i]) for i in range(n)] + [(v[i], accelerations[i]) for i in range(n)]
    state = np.zeros(2 * n)
    parameters = np.zeros(len(forms.parameters))
    return hy.taylor_adaptive(ode, state, tol=tol, pars=parameters, compact_mode=n > 2)


def eliminated(matrix: list, force: list) -> list:
    """x with matrix x = force, as expressions: elimination without pivoting, back substitution."""
    n = len(force)
    for k in range(n):
        for i in range(k + 1, n):
            factor = matrix[i][k] / matrix[k][k]
            for j in range(k + 1, n):
                matrix[i][j] = matrix[i][j] - factor * matrix[k][j]
            force[i] = force[i] - factor * force[k]
    x = [None] * n
    for i in range(n - 1, -1, -1):
        total = force[i]
        for j in range(i + 1, n):
            total = total - matrix[i][j] * x[j]
        x[i] = total / matrix[i][i]
    return x


def _step_callback(watch: Callable[[float], None] | None) -> dict:
    """heyoka's step callback telling ``watch`` the time reached (an exception it raises
    ends the propagation and reaches the caller)."""
    if watch is None:
        return {}

    def told(integrator) -> bool:
        watch(integrator.time)
        return True

    return {"callback": told}

"""Taylor's method, by heyoka (optional) or by our own code (numba): single runs at
tolerances down to rounding.

Two backends (``Taylor(backend=...)``): ``"heyoka"``, described below, and ``"numba"``, our
own Taylor coefficients by automatic differentiation compiled by numba
(:mod:`.taylor_compiled`), with heyoka's order and step rule, for machines where heyoka is
not installed (it is an optional extra with wheels for few platforms).  By default
(``backend=None``) heyoka runs where it is installed, ours elsewhere; the run's settings
say which (``backend``).  Both locate events on each step's polynomial.

heyoka (F. Biscani and D. Izzo, "Revisiting high-order Taylor methods for
astrodynamics and celestial mechanics", MNRAS 504 (2021) 2614-2628;
``pip install ".[taylor]"``) integrates an explicit ODE by adaptive
Taylor series of high order (15 to 25 here), generated as machine code by LLVM.
It is fed from our equations by the heyoka target (:mod:`lagrangian.codegen.heyoka`): M and
f of M q'' = f (declared functions replaced by their definitions) converted with
``heyoka.from_sympy``, the parameters as heyoka's runtime parameters, and q'' =
M^{-1} f written out as Gaussian elimination in heyoka's expressions.  Those are
symbolic, so the elimination cannot pivot on the values met along the motion; it
is exact and backward stable without pivoting where M is definite (the pivots are
ratios of leading principal minors; Higham, *Accuracy and Stability of Numerical
Algorithms*, 2nd ed. 2002, 10.1), as M of a kinetic energy is.  M stays definite
along a motion that starts where it is, until M is singular (an eigenvalue would
have to pass 0), where no method goes on; so a start where M is indefinite (a
legitimate but unusual Lagrangian, L = x'y' - V) is refused, naming dop853,
which solves with pivoting at every step.

One tolerance ``tol`` (heyoka's: relative and absolute at once; default 1e-15,
echoed as ``rtol`` and ``atol``) sets the order and the step.  The order heyoka
picks grows as -ln(tol)/2 (20 at machine epsilon, 346 at 1e-300, which builds for
minutes), so tolerances below machine epsilon, which double precision cannot
deliver, are refused (:data:`MIN_TOL`); the build counts against the run's time
budget (``watch`` is told the start time before it).  Outputs are heyoka's steps,
or with ``t_eval`` its grid propagation there, run in chunks of thousands of steps
with no Python per step (:mod:`.taylor_propagate`): the double pendulum's t = 1000 at
1e-10 takes heyoka's own time within 1.1-1.5x (benchmarks/taylor_path.py; it took
10-15x with a Python callback per step).  Events (Python functions g(t, y, params),
which heyoka's own event detection, given its expressions, cannot take) are found as
the compiled DOP853 finds them: g at every step's end, a sign change located by Brent's
method on heyoka's continuous output of that step (:class:`.compiled_events.StepEvents`).
Not handled: constraints, batches (use dop853, radau or rk4).  The compiled integrator
is kept per system and tolerance (its first build takes 0.1 s for the double pendulum,
about 1.5 s for a 10-link chain); :meth:`Taylor.prepare` builds it before the run, so that
the run's ``compile_time`` and ``compiled`` say what the build cost.  A run fails with
status ``failed`` where heyoka meets a state or a derivative that is not finite, naming
the last finite state.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..codegen.cache import built, built_already
from ..codegen.heyoka import HeyokaTarget
from ..errors import MissingDependencyError, ModelError
from . import taylor_compiled
from .base import (
    AbstractIntegrator,
    IntegrationResult,
    Run,
    Status,
    adaptive_settings,
    tolerance_setting,
)
from .compiled_dop853 import TERMINATED, TOO_SMALL_STEP, numba_installed
from .compiled_events import StepEvents
from .guard import UNDEFINED, describe_state
from .taylor_propagate import propagate

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: The implementations of the method: heyoka's, and ours (our code generation, numba).
BACKENDS = ("heyoka", "numba")

#: The smallest tolerance, heyoka's default: machine epsilon (Taylor order 20).
MIN_TOL = float(np.finfo(float).eps)


@dataclass(frozen=True)
class Taylor(AbstractIntegrator):
    """Adaptive Taylor method of heyoka with tolerance ``tol``; see the module."""

    tol: float = 1e-15
    #: "heyoka", "numba" (:mod:`.taylor_compiled`), or None: heyoka where it is installed
    backend: str | None = None
    name: ClassVar[str] = "taylor"
    order: ClassVar[int] = 0  # variable: chosen from tol
    symplectic: ClassVar[bool] = False
    adaptive: ClassVar[bool] = True
    batched: ClassVar[bool] = False
    needs: ClassVar[str] = "first_order"

    def __post_init__(self) -> None:
        _tolerance("tol", self.tol)
        if self.backend not in (None, *BACKENDS):
            raise ModelError(
                f"unknown backend {self.backend!r} of method 'taylor' (backends: "
                f"{', '.join(BACKENDS)})"
            )

    @property
    def chosen_backend(self) -> str:
        """The backend a run uses: the one given, else heyoka where it is installed."""
        from .choice import heyoka_installed  # the one test, which tests replace

        if self.backend is not None:
            return self.backend
        return "heyoka" if heyoka_installed() else "numba"

    @classmethod
    def configure(cls, *, t_span, dt=None, rtol=None, atol=None):
        """``tol`` is the smaller of rtol and atol where given (heyoka has one tolerance)."""
        adaptive_settings(cls.name, t_span, dt)
        given = [
            _tolerance(name, value)
            for name, value in (("rtol", rtol), ("atol", atol))
            if value is not None
        ]
        return cls(tol=min(given) if given else cls.tol)

    def settings(self) -> dict[str, object]:
        """heyoka's one tolerance is relative and absolute at once: echoed as both."""
        return {
            "method": self.name, "tol": self.tol, "rtol": self.tol, "atol": self.tol,
            "backend": self.chosen_backend,
        }  # fmt: skip

    def check(self, compiled: CompiledSystem) -> None:
        if self.chosen_backend == "heyoka":
            HeyokaTarget().check()
        elif not numba_installed():
            raise MissingDependencyError("method 'taylor' (backend numba)", "numba", "numba")
        if compiled.has_constraints:
            raise ModelError("method 'taylor' does not handle constraints: use dop853 or radau")
        if compiled.forms is None:
            raise ModelError("method 'taylor' generates code from derived equations, not functions")

    def prepare(self, compiled: CompiledSystem, y0: np.ndarray, params: np.ndarray) -> str | None:
        """heyoka's integrator built (LLVM compiles its Taylor series: 0.1 s for the double
        pendulum, seconds for a long chain), or taken from this process, before the run so
        that the run's ``compile_time`` counts it (see the base class); with the numba
        backend its Taylor loop (:mod:`.taylor_compiled`)."""
        if self.chosen_backend == "numba":
            return taylor_compiled.what_is_compiled(compiled)
        if built_already(compiled.forms.fingerprint, "heyoka", self.tol):
            return "nothing: heyoka's integrator was built earlier in this process"
        integrator, _ = _integrator(compiled, self.tol)
        return f"heyoka's Taylor integrator (order {integrator.order})"

    def integrate(self, compiled: CompiledSystem, run: Run) -> IntegrationResult:
        t0, t1, y0, params, watch = run.t0, run.t1, run.y0, run.params, run.watch
        if run.problem is not None:  # as dop853 reports it
            return self._result(compiled, [t0], y0[:, None], Status.FAILED, run.problem, 0)
        _check_definite(compiled, t0, y0, params)
        if self.chosen_backend == "numba":  # heyoka may not be installed: not imported
            return self._numba(compiled, run)
        import heyoka as hy

        if watch is not None:  # the budget's clock starts before the build, which counts
            watch(t0)
        integrator, constants = _integrator(compiled, self.tol)  # built by prepare, or now
        if watch is not None:
            watch(t0)
        integrator.time = t0
        integrator.state[:] = y0
        integrator.pars[:] = constants(params)
        events = None
        if run.events:
            f0 = np.asarray(compiled.rhs(t0, y0, params), dtype=float)
            events = StepEvents(run.events, params, t0, y0, f0)
        reached = propagate(integrator, t1, run.t_eval, watch, events)
        times, values, steps = reached.times, reached.values, reached.steps
        outcome = reached.outcome
        records = events.records(y0.shape[0]) if events is not None else ()
        if reached.stopped:
            return self._result(compiled, times, values, Status.EVENT, TERMINATED, steps, records)
        if outcome in (hy.taylor_outcome.success, hy.taylor_outcome.time_limit):
            return self._result(
                compiled, times, values, Status.SUCCESS, "reached the end time", steps, records
            )
        where = f"t = {reached.last_t:.6g} ({describe_state(compiled, reached.last_y)})"
        if outcome == hy.taylor_outcome.err_nf_state:
            message = (
                f"the state is not finite after {where}: {UNDEFINED}, "
                "or the motion reaches a singularity"
            )
        else:
            message = f"heyoka stopped ({outcome.name}) after {where}"
        return self._result(compiled, times, values, Status.FAILED, message, steps, records)

    def _numba(self, compiled: CompiledSystem, run: Run) -> IntegrationResult:
        if run.watch is not None:  # the budget's clock starts before the build, which counts
            run.watch(run.t0)
        loop = taylor_compiled.taylor_loop(compiled)
        events = None
        if run.events:
            f0 = np.asarray(compiled.rhs(run.t0, run.y0, run.params), dtype=float)
            events = StepEvents(run.events, run.params, run.t0, run.y0, f0)
        reached = taylor_compiled.propagate(loop, run, self.tol, events)
        times, values, steps = reached.times, reached.values, reached.steps
        records = events.records(run.y0.shape[0]) if events is not None else ()
        if reached.stopped:
            return self._result(compiled, times, values, Status.EVENT, TERMINATED, steps, records)
        if reached.status == 1:
            return self._result(
                compiled, times, values, Status.SUCCESS, "reached the end time", steps, records
            )
        where = f"t = {reached.last_t:.6g} ({describe_state(compiled, reached.last_y)})"
        if reached.status == 3:
            message = (
                f"the state is not finite after {where}: {UNDEFINED}, "
                "or the motion reaches a singularity"
            )
        else:
            message = f"{TOO_SMALL_STEP.rstrip('.')} at {where}"
        if t_eval_missing_last(run, times, reached.last_t):
            times = np.append(times, reached.last_t)
            values = np.concatenate([values, reached.last_y[:, None]], axis=1)
        return self._result(compiled, times, values, Status.FAILED, message, steps, records)

    def _result(
        self, compiled, times, values, status, message, steps, records=()
    ) -> IntegrationResult:
        return IntegrationResult(
            t=np.asarray(times, dtype=float),
            y=values,
            status=status,
            message=message,
            steps=int(steps),
            rhs_evaluations=0,
            jacobian_evaluations=0,
            events=records,
            settings=self.settings_for(compiled),
        )


def t_eval_missing_last(run: Run, times: np.ndarray, last_t: float) -> bool:
    """Whether a failed run's outputs (on ``t_eval``) lack its last state, which names where
    it failed (as the compiled DOP853 appends it)."""
    return run.t_eval is not None and (not times.size or times[-1] < last_t)


def _integrator(compiled: CompiledSystem, tol: float):
    """(heyoka's compiled integrator of ``compiled`` at ``tol``, the function of the
    parameters that gives its ``pars``), built once, then kept."""
    build = lambda: _build(compiled, tol)  # noqa: E731
    return built(compiled.forms.fingerprint, "heyoka", build, tol)


def _build(compiled: CompiledSystem, tol: float):
    import heyoka as hy

    ode = HeyokaTarget().load(compiled.program)
    n = compiled.n
    state = np.zeros(2 * n)
    parameters = ode.constants(np.zeros(len(compiled.program.forms.parameters)))
    integrator = hy.taylor_adaptive(
        ode.equations, state, tol=tol, pars=np.zeros(parameters.shape), compact_mode=n > 2
    )
    return integrator, ode.constants


def _tolerance(name: str, value: float) -> float:
    return tolerance_setting(name, value, method="taylor", floor=MIN_TOL, further="")


def _check_definite(compiled: CompiledSystem, t: float, y: np.ndarray, params: np.ndarray) -> None:
    """ModelError unless M at (t, y) is definite, as the elimination without pivoting needs
    (see the module docstring)."""
    problem = indefinite_mass(compiled, t, y, params)
    if problem is not None:
        raise ModelError(problem)


def indefinite_mass(
    compiled: CompiledSystem, t: float, y: np.ndarray, params: np.ndarray
) -> str | None:
    """Why M at (t, y) is not the definite matrix the taylor method needs, or None."""
    n = compiled.n
    mass = np.asarray(compiled.mass_matrix(t, y[:n], y[n:], params), dtype=float)
    if not np.all(np.isfinite(mass)):
        return f"the mass matrix is not finite at the initial state ({describe_state(compiled, y)})"
    eigenvalues = np.linalg.eigvalsh((mass + mass.T) / 2)
    if eigenvalues[0] > 0 or eigenvalues[-1] < 0:
        return None
    return (
        "method 'taylor' solves M q'' = f without pivoting, which needs a definite mass "
        f"matrix M (as a kinetic energy gives), and M at the initial state is not "
        f"(eigenvalues from {eigenvalues[0]:.3g} to {eigenvalues[-1]:.3g}): use dop853"
    )

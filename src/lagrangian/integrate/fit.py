"""Least-squares fit of parameters and initial values to a measured time series.

Minimises sum over columns c and times t_i of ((h_c(t_i, y(t_i; w), p) - d_ci) / sigma_c)^2
over the names w varied (parameters, or coordinates and velocities for their initial
values at t = 0) with SciPy's ``least_squares`` (trust region reflective, bounds from the
parameters' signs: a positive parameter stays > 0).  Its Jacobian is exact, not finite
differences: the forward sensitivities dy/dw (:mod:`.sensitivity`, integrated with the
motion) through the observed expressions' gradients (:mod:`.observation`),

    dr_ci/dw = (dh_c/dy . dy/dw + dh_c/dp_w)(t_i) / sigma_c.

The sensitivity equations are made (and, on the numba backend, compiled) once, and
solved at every step of every start.  Where the sum of squares has several minima,
``starts`` > 1 tries more starts, log-uniform within a factor :data:`START_SPREAD` of
the guesses (seeded: the same call gives the same answer), and keeps the best.
Defaults (echoed in the result's settings): rtol 1e-9, atol 1e-11 for the motion; the
optimiser's ftol, xtol and gtol 1e-10.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..budget import RUN_SECONDS, checked_seconds, cpu_seconds
from ..errors import ModelError, setting
from .fit_result import FitResult, spread
from .observation import Observation
from .pace import RunTooLong
from .sensitivity import SensitivitySolver

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

DEFAULT_RTOL = 1e-9
DEFAULT_ATOL = 1e-11
#: The optimiser's tolerances (SciPy's ftol, xtol, gtol).
TOLERANCE = 1e-10
#: Starts after the first are the guesses times a factor in [1/START_SPREAD, START_SPREAD].
START_SPREAD = 3.0
#: Two starts reached the same optimum when their sums of squares differ by less than this
#: (relative) and their values by less than :data:`SAME_VALUES` (relative).
SAME_COST, SAME_VALUES = 1e-6, 1e-3
#: More starts than this is a typo, or a search that needs better guesses.
MAX_STARTS = 1000


@dataclass(frozen=True)
class FitProblem:
    """What is fitted: the measured ``times`` (m,), ``data`` (c, m) in the columns' order of
    ``observation``, ``sigma`` (c,) each column's noise (ones without a noise level), and
    the start: ``y0`` and ``p`` (every parameter's value, the varied ones' guesses in)."""

    times: np.ndarray
    data: np.ndarray
    observation: Observation
    sigma: np.ndarray
    noise_given: bool
    y0: np.ndarray
    p: np.ndarray


class _Residuals:
    """r(x) and dr/dx, from one solve of the sensitivity equations per point x (SciPy asks
    for the residuals and then the Jacobian at the same point: the last is kept)."""

    def __init__(
        self,
        solver: SensitivitySolver,
        problem: FitProblem,
        compiled,
        watch: Callable[[float], None] | None = None,
    ):
        self.solver, self.problem, self.watch = solver, problem, watch
        states = solver.state_names
        self.slots = [
            ("y", states.index(w)) if w in states else ("p", compiled.parameter_names.index(w))
            for w in solver.wrt
        ]
        times = problem.times
        self.grid = times if times[0] == 0.0 else np.concatenate(([0.0], times))
        self.skip = self.grid.shape[0] - times.shape[0]
        self.evaluations = 0
        self._last: tuple[np.ndarray, tuple] | None = None

    def point(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        y0, p = self.problem.y0.copy(), self.problem.p.copy()
        for (kind, index), value in zip(self.slots, x, strict=True):
            (y0 if kind == "y" else p)[index] = value
        return y0, p

    def evaluate(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(weighted residuals (c*m,), Jacobian (c*m, k), fitted values (c, m)) at x."""
        if self._last is not None and np.array_equal(self._last[0], x):
            return self._last[1]
        problem = self.problem
        y0, p = self.point(x)
        self.evaluations += 1
        try:
            states, sensitivity = self.solver.solve(y0, p, self.grid, self.watch)
        except ModelError:  # a trial step too far (a motion that blows up): a worse point
            shape = (problem.data.size, len(x))
            found = (np.full(problem.data.size, np.nan), np.full(shape, np.nan), None)
            self._last = (x.copy(), found)
            return found
        states, sensitivity = states[self.skip :], sensitivity[self.skip :]
        h, dh_dy, dh_dp = problem.observation.evaluate(problem.times, states, p)
        jacobian = np.einsum("mcs,msk->mck", dh_dy, sensitivity)
        for column, (kind, index) in enumerate(self.slots):
            if kind == "p":
                jacobian[:, :, column] += dh_dp[:, :, index]
        weights = 1.0 / problem.sigma
        residuals = ((h.T - problem.data) * weights[:, None]).ravel()
        jacobian = (jacobian.transpose(1, 0, 2) * weights[:, None, None]).reshape(-1, len(x))
        found = (residuals, jacobian, h.T)
        self._last = (x.copy(), found)
        return found


def fit_parameters(
    compiled: CompiledSystem,
    problem: FitProblem,
    guesses: Mapping[str, float],
    *,
    starts: int = 1,
    seed: int = 0,
    rtol: float | None = None,
    atol: float | None = None,
    timeout: float | None = RUN_SECONDS,
) -> FitResult:
    """The best fit of the names of ``guesses`` (name -> start value) to ``problem``;
    ``timeout``: CPU seconds the whole search may take (None: no limit), past which it
    stops with :class:`~lagrangian.integrate.pace.RunTooLong` (checked as the motions are
    integrated, so one slow motion cannot outlast it)."""
    from scipy.optimize import least_squares

    starts = whole_number("starts", starts)
    if starts > MAX_STARTS:
        raise ModelError(
            f"at most {MAX_STARTS} starts, not {starts}: a fit that needs more wants better "
            f"guesses ({setting('vary')} NAME=GUESS)",
            field=setting("starts"),
        )
    timeout = None if timeout is None else checked_seconds(timeout, setting("timeout"))
    names = tuple(guesses)
    solver = SensitivitySolver(
        compiled, names, rtol=DEFAULT_RTOL if rtol is None else rtol,
        atol=DEFAULT_ATOL if atol is None else atol,
    )  # fmt: skip
    count = problem.data.size
    if count <= len(names):
        raise ModelError(
            f"{count} measured values cannot fit {len(names)} unknowns: more data are needed"
        )
    residuals = _Residuals(solver, problem, compiled, _deadline(timeout, starts))
    lower, upper = _bounds(compiled, names)
    guess = np.array([guesses[n] for n in names], dtype=float)
    results, failed = [], []
    for x0 in _starts(guess, lower, upper, starts, seed):
        first = residuals.evaluate(x0)[0]
        if not np.all(np.isfinite(first)):
            failed.append(x0)
            continue
        fitted = least_squares(
            lambda x: residuals.evaluate(x)[0], x0, jac=lambda x: residuals.evaluate(x)[1],
            bounds=(lower, upper), method="trf", x_scale="jac", ftol=TOLERANCE, xtol=TOLERANCE,
            gtol=TOLERANCE,
        )  # fmt: skip
        results.append(fitted)
    if not results:
        raise ModelError(
            f"the motion could not be integrated from any of the {starts} start(s) "
            f"(the first: {_values(names, guess)}): give better guesses in {setting('vary')}"
        )
    best = min(results, key=lambda r: r.cost)
    weighted, jacobian, fitted = residuals.evaluate(best.x)
    statistics = spread(names, jacobian, weighted, problem.noise_given, best.x)
    same = sum(1 for r in results if _same(r, best))
    warnings = list(statistics.warnings)
    if best.status == 0:
        warnings.append(
            f"the fit stopped after {best.nfev} evaluations before converging: the values are "
            "not an optimum; try other guesses"
        )
    warnings += _bound_warnings(names, best.x, lower, upper)
    if failed:
        warnings.append(
            f"{len(failed)} of {starts} starts could not be integrated and were skipped"
        )
    columns = problem.observation.names
    data = problem.data
    difference = data - fitted
    return FitResult(
        names=names,
        values=best.x.copy(),
        stderr=statistics.stderr,
        correlation=statistics.correlation,
        rms=float(np.sqrt(np.mean(difference**2))),
        chi2_per_dof=statistics.chi2_per_dof,
        dof=statistics.dof,
        warnings=tuple(warnings),
        starts=starts,
        converged=same,
        iterations=int(best.njev or 0),
        evaluations=residuals.evaluations,
        times=problem.times.copy(),
        observed={c: data[j].copy() for j, c in enumerate(columns)},
        fitted={c: fitted[j].copy() for j, c in enumerate(columns)},
        noise=(
            {c: float(s) for c, s in zip(columns, problem.sigma, strict=True)}
            if problem.noise_given
            else None
        ),
        name=compiled.equations.system.name if compiled.derived else "",
        state_names=solver.state_names,
    )


def _deadline(seconds: float | None, starts: int) -> Callable[[float], None] | None:
    """A watch that raises RunTooLong once ``seconds`` of CPU have passed since it was made."""
    if seconds is None:
        return None
    end = cpu_seconds() + seconds

    def watch(t: float) -> None:
        if cpu_seconds() > end:
            raise RunTooLong(
                f"the fit did not finish within {seconds:g} s of CPU ({starts} start(s)): "
                f"give a larger {setting('timeout')}, fewer {setting('starts')} or better "
                f"guesses ({setting('vary')} NAME=GUESS)"
            )

    return watch


def whole_number(name: str, value: object) -> int:
    """``value`` as an int >= 1; a ModelError naming the setting ``name`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise ModelError(f"{name} must be a whole number >= 1, not {value!r}", field=setting(name))
    return int(value)


def _bounds(compiled: CompiledSystem, names: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """Bounds from the parameters' signs (positive, nonnegative: >= 0; negative: <= 0; the
    optimiser keeps strictly inside them); initial values are free."""
    lower, upper = np.full(len(names), -np.inf), np.full(len(names), np.inf)
    for i, name in enumerate(names):
        sign = compiled.parameter_signs.get(name) if name in compiled.parameter_names else None
        if sign in ("positive", "nonnegative"):
            lower[i] = 0.0
        elif sign == "negative":
            upper[i] = 0.0
    return lower, upper


def _starts(guess, lower, upper, count, seed):
    """The guesses, then ``count`` - 1 starts log-uniform within a factor START_SPREAD of them
    (a zero guess: uniform in [-1, 1]), kept inside the bounds."""
    yield guess.copy()
    rng = np.random.default_rng(seed)
    for _ in range(count - 1):
        factors = np.exp(rng.uniform(-np.log(START_SPREAD), np.log(START_SPREAD), guess.size))
        x = np.where(guess != 0, guess * factors, rng.uniform(-1.0, 1.0, guess.size))
        inside = np.where(np.isfinite(lower), lower + 1e-12 * np.maximum(1, abs(guess)), -np.inf)
        yield np.clip(x, inside, upper)


def _same(result, best) -> bool:
    close_cost = result.cost <= best.cost * (1 + SAME_COST) + 1e-300
    scale = np.maximum(np.abs(best.x), 1e-12)
    return bool(close_cost and np.all(np.abs(result.x - best.x) <= SAME_VALUES * scale))


def _bound_warnings(names, x, lower, upper) -> list[str]:
    warnings = []
    for name, value, low, high in zip(names, x, lower, upper, strict=True):
        for bound in (low, high):
            if np.isfinite(bound) and abs(value - bound) <= 1e-8 * max(1.0, abs(value)):
                warnings.append(
                    f"{name} ended at its bound {bound:g} (its sign): the data may need a "
                    "value the model does not allow; check the model or the data"
                )
    return warnings


def _values(names, x) -> str:
    return ", ".join(f"{n} = {v:g}" for n, v in zip(names, x, strict=True))

r"""The step of a fixed-step method from the motion's own time scale, and the check of a given one.

A fixed step knows nothing of the motion: t_end / 1000 is a step of 1 for an
oscillator run to t = 1000 (rk4 damps it to nothing) and of 10 to t = 10^4
(beyond rk4's stability limit: every state overflows to NaN).  The time scale is
the rate ω of the linearized equations: the largest |λ| of the Jacobian d rhs / dy
(for a mechanical system J = [[0, I], [A, B]], and ω is the fastest angular
frequency, or growth or decay rate, of small motions about the state).  It is
taken at the initial states (of a sample of members for an ensemble) and at the
states of a short probe run from them (``PROBE_STEPS`` rk4 steps), which finds
the rates of states the motion soon reaches (a pendulum let go from its side,
where the linearization is zero, swings through its bottom); the probe raises a
nonzero initial rate at most ``PROBE_GROWTH``-fold (a rate that grows beyond that
belongs to a motion heading for a singularity, which no fixed step resolves and the
run's guards report).  J comes from
central differences of ``compiled.rhs`` on the whole sample at once, so any
compiled backend serves and nothing more is compiled.

Then, for a method of class ``cls``:

- no dt given: dt = ``cls.default_omega_dt`` / ω (rk4 0.05: a phase error of
  about (ω dt)^4 / 120 = 5e-8 per radian of motion; variational, of order 2,
  0.02: (ω dt)^2 / 24 = 2e-5 per radian), never more than t_end / 1000 (the
  output's resolution, the step of a slow motion) and, to bound the work, not
  less than t_end / ``MAX_DEFAULT_STEPS`` unless that step would be unstable
  (then a coarse step is warned about, as a given one);
- a dt with ω dt at or beyond ``cls.stability_limit`` at the start (rk4: 2.8,
  the edge of its stability region on the imaginary axis, 2 sqrt 2; the
  Störmer-Verlet / midpoint scheme: 2): refused, one line naming dt, ω and
  the largest stable dt;
- a dt with ω dt above ``COARSE_OMEGA_DT`` (0.1): one
  :class:`~lagrangian.errors.LagrangianWarning` line.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..errors import LagrangianWarning, ModelError, SingularMassMatrixError, setting

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem
    from .fixed_step import AbstractFixedStepIntegrator

#: Members whose states are sampled for ω (evenly over the batch).
SAMPLE_MEMBERS = 64
#: rk4 steps of the probe run, and every how many of them J is taken again.
PROBE_STEPS = 96
PROBE_EVERY = 8
PROBE_GROWTH = 10.0
#: Relative accuracy of ω (central differences): a step this close to the limit is at it.
RATE_ACCURACY = 1e-6
#: Above this ω dt a given step loses accuracy visibly: one warning.
COARSE_OMEGA_DT = 0.1
#: The largest default step, as a fraction of the time span (the former default).
DEFAULT_STEPS = 1000
#: The smallest default step, as a fraction of the time span: a motion faster than that
#: (a long span, a start next to a singularity) gets this step and a warning when coarse.
MAX_DEFAULT_STEPS = 100_000


class CoarseStepWarning(LagrangianWarning):
    """A given fixed step is coarse for the motion's time scale (ω dt > 0.1)."""


def fixed_step_for(
    cls: type[AbstractFixedStepIntegrator],
    compiled: CompiledSystem,
    t_span: tuple[float, float],
    dt: float | None,
    y0: np.ndarray,
    params: np.ndarray,
) -> AbstractFixedStepIntegrator:
    """``cls`` configured for the motion from ``y0`` ((2n,) or (2n, B)) with ``params``
    ((P,) or (P, B)): dt chosen, or checked, against the rate ω (see the module)."""
    t0, t1 = t_span
    integrator = cls.configure(t_span=t_span, dt=dt)  # the settings checked first
    longest, shortest = (t1 - t0) / DEFAULT_STEPS, (t1 - t0) / MAX_DEFAULT_STEPS
    initial, omega = motion_rate(
        compiled, t0, y0, params, probe_step=longest, target=cls.default_omega_dt
    )
    if dt is None and omega > 0 and cls.default_omega_dt / omega < longest:
        step = max(cls.default_omega_dt / omega, shortest)
        if initial * step >= cls.stability_limit:  # never an unstable default: a long run
            step = cls.default_omega_dt / initial
        integrator = cls.configure(t_span=t_span, dt=step)
    check_step(cls, integrator.dt, initial, omega, given=dt is not None)
    return integrator


def check_step(
    cls: type[AbstractFixedStepIntegrator],
    dt: float,
    initial: float,
    omega: float,
    *,
    given: bool = True,
) -> None:
    """ModelError when ``dt`` is past ``cls``'s stability limit at the initial rate, a
    warning when it is above ``COARSE_OMEGA_DT`` at the probed rate ``omega``."""
    product = omega * dt
    rate = f"ω = {_short(omega)}, the fastest rate of the linearized motion"
    if initial * dt >= cls.stability_limit * (1 - RATE_ACCURACY):
        stable = cls.stability_limit / initial
        raise ModelError(
            f"{cls.name} with dt = {_short(dt)} is unstable for this motion: ω·dt = "
            f"{_short(initial * dt)} reaches the stability limit {cls.stability_limit:g} of "
            f"{cls.name} (ω = {_short(initial)}, the fastest rate of the linearized motion at "
            f"the start); give a {setting('dt')} below {_short(stable)}, or leave "
            f"{setting('dt')} out to have it chosen"
        )
    if product > COARSE_OMEGA_DT and not given:
        warnings.warn(
            CoarseStepWarning(
                f"the default dt = {_short(dt)} (t_end / {MAX_DEFAULT_STEPS:,}) is coarse for this "
                f"motion: ω·dt = {_short(product)} > {COARSE_OMEGA_DT:g} ({rate}); the results "
                f"lose accuracy (give {setting('dt')} {_short(cls.default_omega_dt / omega)} "
                "for accuracy)"
            ),
            stacklevel=3,
        )
    elif product > COARSE_OMEGA_DT:
        warnings.warn(
            CoarseStepWarning(
                f"dt = {_short(dt)} is coarse for this motion: ω·dt = {_short(product)} > "
                f"{COARSE_OMEGA_DT:g} ({rate}); the results lose accuracy "
                f"(the default dt would be {_short(cls.default_omega_dt / omega)})"
            ),
            stacklevel=3,
        )


def motion_rate(
    compiled: CompiledSystem,
    t0: float,
    y0: np.ndarray,
    params: np.ndarray,
    *,
    probe_step: float,
    target: float,
) -> tuple[float, float]:
    """(ω at the start, ω probed): the largest |eigenvalue| of d rhs / dy at the sampled
    initial states, and that or larger along a probe run of ``PROBE_STEPS`` rk4 steps (of
    ``target``/ω, at most ``probe_step``); 0 when every eigenvalue is 0 or none is finite,
    or when M is singular at a start (the run's own first step reports that state)."""
    y, p = _sample(np.asarray(y0, dtype=float), np.asarray(params, dtype=float))
    with np.errstate(all="ignore"):
        try:
            initial = omega = _rate(compiled, t0, y, p)
        except SingularMassMatrixError:
            return 0.0, 0.0
        h = probe_step if omega == 0 else min(probe_step, target / omega)
        t = t0
        for k in range(1, PROBE_STEPS + 1):
            try:
                y = _rk4_step(compiled, t, h, y, p)
            except SingularMassMatrixError:  # the probe reached a singular state: ω so far
                break
            t += h
            alive = np.all(np.isfinite(y), axis=0)
            if not np.any(alive):
                break
            if k % PROBE_EVERY == 0:
                try:
                    omega = max(omega, _rate(compiled, t, y[:, alive], _members(p, alive)))
                except SingularMassMatrixError:
                    break
    return initial, (min(omega, PROBE_GROWTH * initial) if initial > 0 else omega)


def _sample(y: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """At most ``SAMPLE_MEMBERS`` members, evenly spread; y (2n, S), p (P,) or (P, S)."""
    if y.ndim == 1:
        return y[:, None], p
    count = y.shape[1]
    chosen = np.unique(np.linspace(0, count - 1, min(count, SAMPLE_MEMBERS)).round().astype(int))
    return y[:, chosen], p[:, chosen] if p.ndim == 2 else p


def _members(p: np.ndarray, keep: np.ndarray) -> np.ndarray:
    return p[:, keep] if p.ndim == 2 else p


def _rate(compiled: CompiledSystem, t: float, y: np.ndarray, p: np.ndarray) -> float:
    """max |λ(J)| over the members y (2n, S); J by central differences of rhs."""
    size = y.shape[0]
    step = 1e-6 * np.maximum(1.0, np.abs(y))  # (2n, S)
    columns = []
    for j in range(size):
        shift = np.zeros_like(y)
        shift[j] = step[j]
        forward = np.asarray(compiled.rhs(t, y + shift, p), dtype=float)
        backward = np.asarray(compiled.rhs(t, y - shift, p), dtype=float)
        columns.append((forward - backward) / (2 * step[j]))  # (2n, S): column j of each J
    jacobians = np.stack(columns, axis=1).transpose(2, 0, 1)  # (S, 2n, 2n)
    finite = np.all(np.isfinite(jacobians), axis=(1, 2))
    if not np.any(finite):
        return 0.0
    eigenvalues = np.linalg.eigvals(jacobians[finite])
    return float(np.max(np.abs(eigenvalues)))


def _rk4_step(compiled: CompiledSystem, t: float, h: float, y: np.ndarray, p) -> np.ndarray:
    k1 = np.asarray(compiled.rhs(t, y, p), dtype=float)
    k2 = np.asarray(compiled.rhs(t + h / 2, y + h / 2 * k1, p), dtype=float)
    k3 = np.asarray(compiled.rhs(t + h / 2, y + h / 2 * k2, p), dtype=float)
    k4 = np.asarray(compiled.rhs(t + h, y + h * k3, p), dtype=float)
    return y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def _short(value: float) -> str:
    """A number in a few characters: 0.05, 3.2e-05, 1e+300."""
    return f"{value:.3g}"

"""Checks that a run still describes the motion: finite values, and the energy balance kept.

Where the equations have no finite value (the square root of a negative
number, a division by zero) an adaptive method shrinks its step without end
(SciPy's first step size is NaN) and a fixed-step method carries NaN on; where
the motion reaches a singularity (V = -k/x at x = 0) a fixed-step method steps
over it onto a finite but meaningless state.  The drivers of every method ask
this module, and end the run with status ``failed`` and the message it gives:

- :func:`parameter_problem`: L and M at the start are finite, unless a parameter's
  value is the reason (``m = 0`` in ``x_dot^2/(2*m)``: y' = 0/inf is finite, so the
  run would "succeed" with the energy NaN);
- :func:`start_problem`: the state and y' = rhs(t0, y0) at the start are finite;
- :func:`state_problem`: the state after a step is finite (every accepted step);
- :func:`energy_jump`: on the steps of a fixed-step run of an unconstrained
  system whose L does not depend on t explicitly, the energy function
  h = q' . dL/dq' - L changes only by the work of the non-conservative forces,
  dh/dt = q' . (Q - dF/dq') (so not at all when they vanish).  A step whose
  change of h differs from that work (trapezoidal rule) by more than
  ``ENERGY_JUMP`` times the energy scale of the step, max |h| and |L| at its
  two ends (T + |V| for L = T - V), has not followed the motion: an accurate
  step changes h by a small fraction of that scale (O(h^5) for rk4), a step
  across a singularity by about all of it.  Energy constants added to V make
  the test less sensitive, never falsely strict.

Checks evaluate the compiled functions outside the method's work counts.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import setting

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: A step whose energy balance is off by more than this fraction of the step's energy
#: scale max(|h|, |L|) failed (the ratio of a step across a singularity is about 1).
ENERGY_JUMP = 0.5

UNDEFINED = (
    "the equations of motion are undefined or infinite there "
    "(e.g. the square root of a negative number, a division by zero)"
)


def describe_state(compiled: CompiledSystem, y: np.ndarray) -> str:
    """``x = -1, x_dot = 0`` for a state (2n,), or for the first non-finite member of a batch."""
    y = np.asarray(y, dtype=float)
    if y.ndim == 2:
        bad = ~np.all(np.isfinite(y), axis=0)
        y = y[:, int(np.argmax(bad))]
    names = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    return ", ".join(f"{name} = {value:.6g}" for name, value in zip(names, y.tolist(), strict=True))


#: Where L or M is not finite at the start, each parameter in turn is given this value (a
#: generic one: no division by it is zero, no root of it negative) to find the culprit.
_GENERIC_VALUE = 1.2345


def parameter_problem(
    compiled: CompiledSystem, t: float, y: np.ndarray, params: np.ndarray
) -> str | None:
    """Why the parameters' values leave L or M without a finite value at the start (t, y),
    naming the parameter whose value is the cause, or None (also where the state is)."""

    def finite(values: np.ndarray) -> bool:
        n = compiled.n
        q, v = y[:n], y[n:]
        with np.errstate(all="ignore"):
            lagrangian = np.asarray(compiled.lagrangian(t, q, v, values), dtype=float)
            mass = np.asarray(compiled.mass_matrix(t, q, v, values), dtype=float)
        return bool(np.all(np.isfinite(lagrangian)) and np.all(np.isfinite(mass)))

    params = np.asarray(params, dtype=float)
    if params.ndim != 1 or finite(params):
        return None
    for j, name in enumerate(compiled.parameter_names):
        changed = params.copy()
        changed[j] = _GENERIC_VALUE
        if finite(changed):
            return (
                f"parameter {name} = {params[j]:g} leaves the Lagrangian or the mass matrix "
                f"undefined or infinite at the initial state ({describe_state(compiled, y)}), "
                f"e.g. by a division by zero: give {name} another value"
            )
    return None


def start_problem(
    compiled: CompiledSystem, t: float, y: np.ndarray, params: np.ndarray
) -> str | None:
    """Why the run cannot start at (t, y) (a state or y' = rhs that is not finite), or None."""
    with np.errstate(all="ignore"):
        slope = np.asarray(compiled.rhs(t, y, params), dtype=float)
    if np.all(np.isfinite(y)) and np.all(np.isfinite(slope)):
        return None
    where = f"t = {t:.6g} ({describe_state(compiled, y)})"
    return f"the right-hand side is not finite at {where}: {UNDEFINED}"


def state_problem(
    compiled: CompiledSystem, t: float, y: np.ndarray, y_new: np.ndarray
) -> str | None:
    """Why the state ``y_new`` reached from (t, y) ends the run (it is not finite), or None."""
    if np.all(np.isfinite(y_new)):
        return None
    return (
        f"the state is not finite after t = {t:.6g} ({describe_state(compiled, y)}): "
        f"{UNDEFINED}, or the motion reaches a singularity"
    )


def energy_jump(
    compiled: CompiledSystem, t: np.ndarray, y: np.ndarray, params: np.ndarray
) -> tuple[int, str] | None:
    """(k, message) for the first step k -> k+1 of ``(t (T,), y (2n, T))`` that breaks the
    energy balance (see the module docstring), or None (also where it does not apply)."""
    if t.shape[0] < 2 or y.ndim != 2 or not _balance_applies(compiled):
        return None
    n = compiled.n
    q, v = y[:n], y[n:]
    with np.errstate(all="ignore"):
        h = _along(compiled.energy(t, y, params), t)
        lagrangian = _along(compiled.lagrangian(t, q, v, params), t)
        forces = np.asarray(compiled.nonconservative_forces(t, q, v, params), dtype=float)
        power = np.sum(v * np.broadcast_to(forces, v.shape), axis=0)
        work = np.diff(t) * (power[:-1] + power[1:]) / 2
        imbalance = np.abs(np.diff(h) - work)
        size = np.maximum(np.abs(h), np.abs(lagrangian))
        scale = np.maximum(size[:-1], size[1:])
        broken = ~(imbalance <= ENERGY_JUMP * scale)  # NaN counts as broken
    if not broken.any():
        return None
    k = int(np.argmax(broken))
    return k, (
        f"the energy jumped from {h[k]:.6g} to {h[k + 1]:.6g} in the step from t = {t[k]:.6g} "
        f"({describe_state(compiled, y[:, k])}): the motion passes a singularity "
        f"there (or the step is far too large: give a smaller {setting('dt')}, or use dop853)"
    )


def _balance_applies(compiled: CompiledSystem) -> bool:
    """dh/dt = q' . (Q - dF/dq') holds: no constraints, L without explicit t."""
    return compiled.autonomous_lagrangian and not compiled.has_constraints


def _along(values, t: np.ndarray) -> np.ndarray:
    """A compiled scalar function's values over the batch of times, shape (T,)."""
    return np.broadcast_to(np.asarray(values, dtype=float), t.shape)

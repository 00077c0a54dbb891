"""The initial state of a constrained run: moved onto the constraints, and said so.

A state given off the constraints (``--set x=0.5 --set y=0`` for a pendulum of length 1 in
Cartesian coordinates) is moved to the nearest one on them in the kinetic metric
(:meth:`~lagrangian.numeric.projection.ConstraintFunctions.project`) before a run starts:
the run is then of another state than the one given, so a warning says which values
changed and by how much (a change within rounding, :data:`MOVED_TOLERANCE`, is none).  A
state the projection cannot move (a singular point of the constraints, where their
gradients vanish or are dependent: x = y = 0 for x^2 + y^2 = l^2) is refused in one
line, where NumPy's LinAlgError ended the run before.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from ..errors import LagrangianWarning, ModelError
from .guard import describe_state

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: A value that moves by less than this, relative to 1 + |value|, has not moved (rounding).
MOVED_TOLERANCE = 1e-9
#: The constraints' residual after the projection, relative to 1 + |q|, above which the
#: projection failed (it converges quadratically to rounding level where it can).
RESIDUAL_TOLERANCE = 1e-8


def constrained_start(
    compiled: CompiledSystem, t: float, y0: np.ndarray, params: np.ndarray
) -> np.ndarray:
    """``y0`` (2n,) or a batch (2n, N) moved onto the constraints of ``compiled`` at time t;
    a warning says how far where it moved, a ModelError where it cannot be moved."""
    y0 = np.asarray(y0, dtype=float)
    if y0.ndim == 2 and y0.shape[1] == 1:  # one motion: said as one
        return constrained_start(compiled, t, y0[:, 0], params)[:, None]
    y0 = _linkage_assembled(compiled, t, y0, params)
    with np.errstate(all="ignore"):
        try:
            moved = np.asarray(compiled.project(t, y0, params), dtype=float)
        except np.linalg.LinAlgError:
            if y0.ndim == 1:
                raise ModelError(_singular(compiled, y0)) from None
            _refuse_first_singular(compiled, t, y0, params)  # which member: one by one
            raise
        residual = np.asarray(compiled.constraint_residual(t, moved, params), dtype=float)
    size = 1.0 + np.max(np.abs(moved[: compiled.n]), axis=0)
    failed = ~np.all(np.isfinite(moved), axis=0) | ~(
        np.max(np.abs(residual), axis=0) <= RESIDUAL_TOLERANCE * size
    )
    if np.any(failed):
        if y0.ndim == 1:
            raise ModelError(_singular(compiled, y0))
        first = int(np.argmax(failed))
        raise ModelError(_singular(compiled, y0[:, first], f" of motion {first}"))
    _warn_moved(compiled, y0, moved)
    return moved


def _linkage_assembled(
    compiled: CompiledSystem, t: float, y0: np.ndarray, params: np.ndarray
) -> np.ndarray:
    """``y0`` with a linkage's dependent coordinates solved onto its loops, its held ones
    kept (:mod:`lagrangian.model.linkage_assembly`): what the linkage says is no move, and
    the projection that follows finds it on the constraints."""
    system = getattr(compiled.equations, "system", None)
    if getattr(system, "linkage", None) is None:
        return y0
    from ..model.linkage_assembly import assembled

    order = [compiled.parameter_names.index(name) for name in system.parameter_names]
    positions = [compiled.coordinate_names.index(name) for name in system.coordinate_names]
    n = compiled.n
    moved = np.array(y0, dtype=float)
    columns = [moved] if moved.ndim == 1 else [moved[:, k] for k in range(moved.shape[1])]
    for k, y in enumerate(columns):
        p = params if np.ndim(params) == 1 else params[:, k]
        q, v = assembled(system, t, y[:n][positions], y[n:][positions], np.asarray(p)[order])
        y[:n][positions], y[n:][positions] = q, v
        if moved.ndim == 2:
            moved[:, k] = y
    return moved


def _refuse_first_singular(
    compiled: CompiledSystem, t: float, y0: np.ndarray, params: np.ndarray
) -> None:
    for k in range(y0.shape[1]):
        p = params[:, k] if np.ndim(params) == 2 else params
        try:
            compiled.project(t, y0[:, k], p)
        except np.linalg.LinAlgError:
            raise ModelError(_singular(compiled, y0[:, k], f" of motion {k}")) from None


def _singular(compiled: CompiledSystem, y0: np.ndarray, which: str = "") -> str:
    return (
        f"the initial state{which} ({describe_state(compiled, y0)}) cannot be moved onto the "
        "constraints: it is a singular point of theirs (their gradients vanish or are "
        "dependent there) or too far from them; give a state on the constraints"
    )


def _warn_moved(compiled: CompiledSystem, y0: np.ndarray, moved: np.ndarray) -> None:
    change = np.abs(moved - y0)
    changed = change > MOVED_TOLERANCE * (1.0 + np.abs(y0))
    if not changed.any():
        return
    names = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    distance = float(np.max(change))
    if y0.ndim == 1:
        values = ", ".join(
            f"{name} {y0[k]:.6g} -> {moved[k]:.6g}" for k, name in enumerate(names) if changed[k]
        )
        text = (
            f"the initial state was moved onto the constraints (values changed by up to "
            f"{distance:.3g}): {values}"
        )
    else:
        members = np.flatnonzero(changed.any(axis=0))
        text = (
            f"the initial states of {members.size} of {y0.shape[1]} motions were moved onto "
            f"the constraints (values changed by up to {distance:.3g}; the first, number "
            f"{members[0]}: {describe_state(compiled, y0[:, members[0]])})"
        )
    warnings.warn(
        LagrangianWarning(f"{text}; give a state on the constraints to start from it"),
        stacklevel=3,
    )

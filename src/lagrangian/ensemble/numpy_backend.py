"""The numpy backend: the single-run integrator stepping a batch of states (2n, B).

:func:`integrate_chunk` takes the steps of the fixed-step driver
(:func:`~lagrangian.integrate.fixed_step.step_grid`) with the method's own
``init``/``step`` on a batch, exactly as
:meth:`~lagrangian.integrate.fixed_step.AbstractFixedStepIntegrator.solve`
does for one state (the compiled functions are vectorised over the trailing
batch axis), and records the observables along the way.  When only
``flip_time`` is asked for, members that have flipped leave the batch (an
explicit method keeps no state of its own, so the batch can shrink) and the
run stops when all have.  For ``lyapunov`` the method steps the state with one
displacement (:class:`~lagrangian.integrate.lyapunov.TangentFlow`, explicit
Runge-Kutta methods only), renormalised after every step.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..integrate.base import Work
from ..integrate.explicit_rk import AbstractExplicitRungeKutta
from ..integrate.fixed_step import StepFailure, step_grid
from ..integrate.lyapunov import TangentFlow
from .observables import finish, flipped, stops_early

if TYPE_CHECKING:
    from ..integrate.fixed_step import AbstractFixedStepIntegrator
    from ..numeric.compiled import CompiledSystem


def integrate_chunk(
    compiled: CompiledSystem,
    integrator: AbstractFixedStepIntegrator,
    y0: np.ndarray,
    params: np.ndarray,
    t_end: float,
    names: tuple[str, ...],
    *,
    save_every: int | None = None,
    progress: Callable[[float], None] | None = None,
) -> dict[str, np.ndarray]:
    """Observables (each (B,)) and, with ``save_every``, ``paths`` (2n, B, T) of one chunk.

    ``y0`` is (2n, B); ``params`` is (P,) (shared) or (P, B) (per member).
    """
    n = compiled.n
    y_start = np.array(y0, dtype=float)
    count = y_start.shape[1]
    grid = step_grid(0.0, float(t_end), integrator.dt)
    per_member = params.ndim == 2
    project = compiled.project if compiled.has_constraints else None
    work = Work()
    track_flips = "flip_time" in names
    flip_time = np.full(count, np.nan)
    active = np.arange(count)
    y = y_start
    p = params
    if track_flips:
        flip_time[flipped(y, n)] = grid[0]
    shrink = stops_early(names) and save_every is None
    tangent = None
    if "lyapunov" in names:
        if not isinstance(integrator, AbstractExplicitRungeKutta):
            raise ModelError(
                f"the lyapunov observable needs an explicit method (rk4), not {integrator.name}"
            )
        tangent = TangentFlow(compiled)
        z, stretch = tangent.start(y), np.zeros(count)
    state = integrator.init(compiled, grid[0], y, p, work)
    if shrink and state is None:
        keep = np.isnan(flip_time)
        active, y = active[keep], y[:, keep]
        p = p[:, keep] if per_member else p
    saved = [y_start.copy()] if save_every else []
    final = y_start.copy()
    steps = len(grid) - 1
    for k, (ta, tb) in enumerate(itertools.pairwise(grid), start=1):
        if active.size == 0:
            break
        try:
            if tangent is not None:  # the same step of the state with its displacement
                z, state = integrator.step(tangent, ta, tb - ta, z, state, p, work)
                z, logarithm = tangent.renormalised(z)
                stretch += logarithm
                y = z[: 2 * n]
            else:
                y, state = integrator.step(compiled, ta, tb - ta, y, state, p, work)
        except StepFailure as failure:
            raise ModelError(
                f"the ensemble integration failed: {failure} at t = {ta:.17g}"
            ) from None
        if project is not None:
            y = project(tb, y, p)
        if track_flips:
            new = flipped(y, n) & np.isnan(flip_time[active])
            flip_time[active[new]] = tb
            if shrink and state is None and np.any(new):
                final[:, active[new]] = y[:, new]
                keep = ~new
                active, y = active[keep], y[:, keep]
                p = p[:, keep] if per_member else p
        if save_every and k % save_every == 0:
            snapshot = final.copy()
            snapshot[:, active] = y
            saved.append(snapshot)
        if progress is not None:
            progress(k / steps)
    final[:, active] = y
    values = finish(
        compiled, names, t0=grid[0], y0=y_start, t1=grid[-1], y1=final, params=params,
        flip_time=flip_time,
    )  # fmt: skip
    if tangent is not None:
        values["lyapunov"] = stretch / (grid[-1] - grid[0])
    if save_every:
        values["paths"] = np.stack(saved, axis=-1)
    values["steps"] = np.array(steps)
    return values

"""The numpy backend: the single-run integrator stepping a batch of states (2n, B).

:class:`NumpyBackend` takes the steps of the fixed-step driver
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
from typing import ClassVar

import numpy as np

from ..errors import ModelError
from ..integrate.base import Work
from ..integrate.explicit_rk import AbstractExplicitRungeKutta
from ..integrate.fixed_step import StepFailure
from ..integrate.indicators import SALI_BELOW, TangentFlows, sali
from ..integrate.lyapunov import TangentFlow
from .chunk import AbstractEnsembleBackend, Chunk, Outputs, Progress
from .observables import flipped, indicator_values, indicator_vectors


class NumpyBackend(AbstractEnsembleBackend):
    """The single-run integrator stepping each chunk as one batch (see the module)."""

    name: ClassVar[str] = "numpy"

    def integrate(self, chunk: Chunk, progress: Progress | None = None) -> Outputs:
        compiled, integrator, grid = chunk.compiled, chunk.integrator, chunk.grid
        params = p = chunk.params
        n, count, per_member = compiled.n, chunk.count, params.ndim == 2
        y_start = np.array(chunk.y0, dtype=float)
        project = compiled.project if compiled.has_constraints else None
        work = Work()
        flip_time = np.full(count, np.nan)
        active = np.arange(count)
        y = y_start
        if chunk.track:
            flip_time[flipped(y, n)] = grid[0]
        shrink = chunk.stop
        tangent = None
        vectors = indicator_vectors(chunk.names)
        watch = "sali" in chunk.names  # SALI's first crossing, every step
        sali_time = np.full(count, np.nan)
        if "lyapunov" in chunk.names or vectors:
            if not isinstance(integrator, AbstractExplicitRungeKutta):
                name = "lyapunov" if "lyapunov" in chunk.names else "chaos indicator"
                raise ModelError(
                    f"the {name} observable needs an explicit method (rk4), not {integrator.name}"
                )
            # with indicators, w_1 is the lyapunov observable's displacement
            tangent = TangentFlows(compiled, vectors) if vectors else TangentFlow(compiled)
            z, stretch = tangent.start(y), np.zeros(count)
            ends = z.copy()  # each member's z where it stopped
        state = integrator.init(compiled, grid[0], y, p, work)
        if shrink and state is None and not watch:
            keep = np.isnan(flip_time)
            active, y = active[keep], y[:, keep]
            p = p[:, keep] if per_member else p
        saved = [y_start.copy()] if chunk.every else []
        final = y_start.copy()
        steps = chunk.steps
        for k, (ta, tb) in enumerate(itertools.pairwise(grid), start=1):
            if active.size == 0:
                break
            try:
                if tangent is not None:  # the same step of the state with its displacement
                    z, state = integrator.step(tangent, ta, tb - ta, z, state, p, work)
                    z, logarithm = tangent.renormalised(z)
                    stretch[active] += logarithm
                    y = z[: 2 * n]
                else:
                    y, state = integrator.step(compiled, ta, tb - ta, y, state, p, work)
            except StepFailure as failure:
                raise ModelError(
                    f"the ensemble integration failed: {failure} at t = {ta:.17g}"
                ) from None
            if project is not None:
                y = project(tb, y, p)
            if chunk.track:
                new = flipped(y, n) & np.isnan(flip_time[active])
                flip_time[active[new]] = tb
            if watch:
                new = (sali(tangent.vectors(z)) < SALI_BELOW) & np.isnan(sali_time[active])
                sali_time[active[new]] = tb
            if shrink and state is None:
                done = np.ones(active.size, dtype=bool)
                for times in [flip_time] * chunk.track + [sali_time] * watch:
                    done &= ~np.isnan(times[active])
                if np.any(done):
                    final[:, active[done]] = y[:, done]
                    keep = ~done
                    if tangent is not None:
                        ends[:, active[done]] = z[:, done]
                        z = z[:, keep]
                    active, y = active[keep], y[:, keep]
                    p = p[:, keep] if per_member else p
            if chunk.every and k % chunk.every == 0:
                snapshot = final.copy()
                snapshot[:, active] = y
                saved.append(snapshot)
            if progress is not None:
                progress(k / steps)
        final[:, active] = y
        values = chunk.result(final, flip_time, np.stack(saved, axis=-1) if saved else None)
        if tangent is not None and "lyapunov" in chunk.names:
            values["lyapunov"] = stretch / (grid[-1] - grid[0])
        if vectors:
            ends[:, active] = z
            values.update(indicator_values(tangent.vectors(ends), chunk.names, sali_time))
        return values

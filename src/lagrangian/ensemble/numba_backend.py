"""The numba backend: a parallel fixed-step RK4 loop around a numba-compiled rhs.

The right-hand side comes from the same symbolic equations as the numpy one
(:func:`~lagrangian.numeric.forms.symbolic_forms` of ``compiled.equations``):
M and f are filled by the generated kernel of the numba backend
(:mod:`lagrangian.numeric.numba_source`, cached on disk) and q'' solves
M q'' = f by Gaussian elimination with partial pivoting
(:func:`lagrangian.numeric.numba_linalg.solve_into`).  The RK4 loop uses the same tableau and
step grid as :class:`~lagrangian.integrate.explicit_rk.RK4`, so results agree
with the numpy backend to rounding.  One member per ``prange`` iteration; a
member asking only for ``flip_time`` stops when it has flipped.

numba is imported here only (``pip install 'lagrangian[numba]'``).
Constrained systems are not handled (use the numpy backend).
"""

from __future__ import annotations

import math
import weakref
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..integrate import tableaus
from ..integrate.fixed_step import step_grid
from .observables import finish, stops_early

if TYPE_CHECKING:
    from ..integrate.fixed_step import AbstractFixedStepIntegrator
    from ..numeric.compiled import CompiledSystem

_KERNELS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _numba():
    try:
        import numba
    except ImportError:  # pragma: no cover - depends on the environment
        raise ModelError("backend 'numba' needs numba: pip install 'lagrangian[numba]'") from None
    return numba


def fill_kernel(compiled: CompiledSystem):
    """The jitted ``fill(t, y, p, M, f)`` of ``compiled`` (generated code, cached on disk)."""
    from ..numeric.definitions import function_definitions
    from ..numeric.forms import symbolic_forms
    from ..numeric.numba_source import load_module

    if compiled.has_constraints:
        raise ModelError("backend 'numba' does not handle constraints (use backend numpy)")
    _numba()
    system = compiled.equations.system
    forms = symbolic_forms(
        compiled.equations, function_definitions(system, dict(compiled.definitions))
    )
    return load_module(forms).fill


def kernel(compiled: CompiledSystem):
    """The jitted ensemble loop of ``compiled`` (built once per compiled system)."""
    found = _KERNELS.get(compiled)
    if found is None:
        found = _KERNELS[compiled] = _build(fill_kernel(compiled), compiled.n)
    return found


def _build(fill, n: int):
    from ..numeric.numba_linalg import solve_into

    numba = _numba()
    njit, prange = numba.njit, numba.prange
    a21, a32, a43 = (float(tableaus.RK4.a[i, i - 1]) for i in (1, 2, 3))
    b1, b2, b3, b4 = (float(b) for b in tableaus.RK4.b)
    c2, c3, c4 = (float(c) for c in tableaus.RK4.c[1:])
    limit = math.pi

    @njit(inline="always")
    def derivative(t, y, p, matrix, force, out):
        fill(t, y, p, matrix, force)
        solve_into(matrix, force, out, n)
        for i in range(n):
            out[i] = y[n + i]

    @njit(parallel=True)
    def run(y0, params, grid, track, stop, save_every, final, flips, paths):
        count, m = y0.shape
        steps = grid.shape[0] - 1
        for b in prange(count):
            y = y0[b].copy()
            p = params[b]
            k1, k2, k3, k4 = np.empty(m), np.empty(m), np.empty(m), np.empty(m)
            stage = np.empty(m)
            matrix, force = np.empty((n, n)), np.empty(n)
            flip = np.nan
            if track:
                for i in range(n):
                    if abs(y[i]) > limit:
                        flip = grid[0]
            if save_every > 0:
                for i in range(m):
                    paths[b, i, 0] = y[i]
            if not (stop and flip == flip):
                for s in range(steps):
                    ta = grid[s]
                    h = grid[s + 1] - ta
                    derivative(ta, y, p, matrix, force, k1)
                    for i in range(m):
                        stage[i] = y[i] + (h * a21) * k1[i]
                    derivative(ta + c2 * h, stage, p, matrix, force, k2)
                    for i in range(m):
                        stage[i] = y[i] + (h * a32) * k2[i]
                    derivative(ta + c3 * h, stage, p, matrix, force, k3)
                    for i in range(m):
                        stage[i] = y[i] + (h * a43) * k3[i]
                    derivative(ta + c4 * h, stage, p, matrix, force, k4)
                    for i in range(m):
                        y[i] = y[i] + h * (b1 * k1[i] + b2 * k2[i] + b3 * k3[i] + b4 * k4[i])
                    if save_every > 0 and (s + 1) % save_every == 0:
                        for i in range(m):
                            paths[b, i, (s + 1) // save_every] = y[i]
                    if track and flip != flip:
                        for i in range(n):
                            if abs(y[i]) > limit:
                                flip = grid[s + 1]
                        if stop and flip == flip:
                            break
            flips[b] = flip
            for i in range(m):
                final[b, i] = y[i]

    return run


def integrate_numba(
    compiled: CompiledSystem,
    integrator: AbstractFixedStepIntegrator,
    y0: np.ndarray,
    params: np.ndarray,
    t_end: float,
    names: tuple[str, ...],
    *,
    save_every: int | None = None,
) -> dict[str, np.ndarray]:
    """One chunk, as :func:`~lagrangian.ensemble.numpy_backend.integrate_chunk` returns it."""
    run = kernel(compiled)
    grid = step_grid(0.0, float(t_end), integrator.dt)
    count = y0.shape[1]
    states = np.ascontiguousarray(np.asarray(y0, dtype=float).T)
    p = np.asarray(params, dtype=float)
    per_member = np.ascontiguousarray(p.T if p.ndim == 2 else np.broadcast_to(p, (count, p.size)))
    every = int(save_every or 0)
    saved = (len(grid) - 1) // every + 1 if every else 1
    final = np.empty_like(states)
    flips = np.empty(count)
    paths = np.empty((count, states.shape[1], saved) if every else (1, 1, 1))
    track = "flip_time" in names
    stop = stops_early(names) and not every
    run(states, per_member, grid, track, stop, every, final, flips, paths)
    values = finish(
        compiled, names, t0=grid[0], y0=np.asarray(y0, float), t1=grid[-1], y1=final.T,
        params=params, flip_time=flips,
    )  # fmt: skip
    if every:
        values["paths"] = np.transpose(paths, (1, 0, 2))
    values["steps"] = np.array(len(grid) - 1)
    return values

"""The numba backend: a parallel fixed-step loop around numba-compiled expressions.

The expressions come from the same symbolic equations as the numpy backend
(``compiled.forms``, :mod:`lagrangian.codegen.forms`),
printed as generated kernels cached on disk (:mod:`lagrangian.codegen.numba`):
M and f of M q'' = f for ``rk4``; the momenta, forces, M and the Newton
Jacobian of :mod:`lagrangian.codegen.schemes` for ``variational`` (the midpoint
scheme, or Stormer-Verlet when the system is separable, as
:class:`~lagrangian.integrate.variational.Variational` picks).  The schemes
(:mod:`lagrangian.codegen.numba_loop`, a template written out per system and scheme
so that numba caches the loop's machine code on disk too) follow the numpy backend step
for step on the same step grid, so results agree with it to rounding.  One member per ``prange``
iteration; a member asking only for ``flip_time`` stops when it has flipped.

numba is imported here only (``pip install ".[numba]"``).
Constrained systems are not handled (use the numpy backend).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import MissingDependencyError, ModelError
from ..integrate.fixed_step import step_grid
from .observables import finish, stops_early

if TYPE_CHECKING:
    from ..codegen.forms import SymbolicForms
    from ..integrate.fixed_step import AbstractFixedStepIntegrator
    from ..numeric.compiled import CompiledSystem


def _numba():
    try:
        import numba
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingDependencyError("backend 'numba'", "numba", "numba") from None
    return numba


def _forms(compiled: CompiledSystem) -> SymbolicForms:
    if compiled.has_constraints:
        raise ModelError("backend 'numba' does not handle constraints (use backend numpy)")
    _numba()
    if compiled.forms is None:
        raise ModelError(
            "backend 'numba' generates code from derived equations, not given functions"
        )
    return compiled.forms


def kernel(compiled: CompiledSystem, scheme: str = "rk4"):
    """The jitted ensemble loop of ``compiled`` and ``scheme`` (built once per equations)."""
    from ..codegen.loops import numba_loop
    from ..integrate import tableaus
    from ..integrate.variational import STALL_RATIO

    forms = _forms(compiled)
    return numba_loop(forms, scheme, tableau=tableaus.RK4, stall=STALL_RATIO).run


def _scheme(compiled: CompiledSystem, integrator: AbstractFixedStepIntegrator) -> str:
    scheme = integrator.printed_scheme(compiled)
    if scheme is None:
        raise ModelError(
            f"backend 'numba' integrates with rk4 or variational, not {integrator.name}"
        )
    return scheme


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
    run = kernel(compiled, _scheme(compiled, integrator))
    grid = step_grid(0.0, float(t_end), integrator.dt)
    count = y0.shape[1]
    states = np.ascontiguousarray(np.asarray(y0, dtype=float).T)
    p = np.asarray(params, dtype=float)
    per_member = np.ascontiguousarray(p.T if p.ndim == 2 else np.broadcast_to(p, (count, p.size)))
    every = int(save_every or 0)
    saved = (len(grid) - 1) // every + 1 if every else 1
    final = np.empty_like(states)
    flips = np.empty(count)
    failures = np.empty(count, dtype=np.int64)
    paths = np.empty((count, states.shape[1], saved) if every else (1, 1, 1))
    track = "flip_time" in names
    stop = stops_early(names) and not every
    newton = integrator.newton_settings()
    options = (newton.tol, newton.floor, newton.iterations)
    run(states, per_member, grid, track, stop, every, *options, final, flips, failures, paths)
    if np.any(failures >= 0):
        raise ModelError(
            "the ensemble integration failed: Newton's method of the variational step did "
            f"not converge in {newton.iterations} iterations at t = "
            f"{grid[failures[failures >= 0].min()]:.17g}"
        )
    values = finish(
        compiled, names, t0=grid[0], y0=np.asarray(y0, float), t1=grid[-1], y1=final.T,
        params=params, flip_time=flips,
    )  # fmt: skip
    if every:
        values["paths"] = np.transpose(paths, (1, 0, 2))
    values["steps"] = np.array(len(grid) - 1)
    return values

"""The numba backend: a parallel fixed-step loop around numba-compiled expressions.

The expressions come from the same symbolic equations as the numpy backend
(:func:`~lagrangian.numeric.forms.symbolic_forms` of ``compiled.equations``),
printed as generated kernels cached on disk (:mod:`lagrangian.numeric.numba_source`):
M and f of M q'' = f for ``rk4``; the momenta, forces, M and the Newton
Jacobian of :mod:`.scheme_expressions` for ``variational`` (the midpoint
scheme, or Stormer-Verlet when the system is separable, as
:class:`~lagrangian.integrate.variational.Variational` picks).  The schemes
(:mod:`.numba_schemes`) follow the numpy backend step for step on the same
step grid, so results agree with it to rounding.  One member per ``prange``
iteration; a member asking only for ``flip_time`` stops when it has flipped.

numba is imported here only (``pip install 'lagrangian[numba]'``).
Constrained systems are not handled (use the numpy backend).
"""

from __future__ import annotations

import math
import weakref
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..integrate.fixed_step import step_grid
from ..integrate.variational import ROUNDING_FLOOR
from .observables import finish, stops_early

if TYPE_CHECKING:
    from ..integrate.fixed_step import AbstractFixedStepIntegrator
    from ..numeric.compiled import CompiledSystem
    from ..numeric.forms import SymbolicForms

#: The built loops, per compiled system and scheme (compiling one takes seconds).
_KERNELS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _numba():
    try:
        import numba
    except ImportError:  # pragma: no cover - depends on the environment
        raise ModelError("backend 'numba' needs numba: pip install 'lagrangian[numba]'") from None
    return numba


def _forms(compiled: CompiledSystem) -> SymbolicForms:
    from ..numeric.definitions import function_definitions
    from ..numeric.forms import symbolic_forms

    if compiled.has_constraints:
        raise ModelError("backend 'numba' does not handle constraints (use backend numpy)")
    _numba()
    system = compiled.equations.system
    return symbolic_forms(
        compiled.equations, function_definitions(system, dict(compiled.definitions))
    )


def fill_kernel(compiled: CompiledSystem):
    """The jitted ``fill(t, y, p, M, f)`` of ``compiled`` (generated code, cached on disk)."""
    from ..numeric.numba_source import load_module

    return load_module(_forms(compiled)).fill


def scheme_functions(compiled: CompiledSystem, scheme: str):
    """The module of jitted fillers of a variational ``scheme`` (generated, cached on disk)."""
    from ..numeric.numba_source import load_functions
    from .scheme_expressions import MATRICES, SCALARS, scheme_expressions

    forms = _forms(compiled)
    expressions = scheme_expressions(forms, scheme)
    return load_functions(forms, scheme, expressions, scalars=SCALARS, matrices=MATRICES)


def kernel(compiled: CompiledSystem, scheme: str = "rk4"):
    """The jitted ensemble loop of ``compiled`` and ``scheme`` (built once per system)."""
    built = _KERNELS.setdefault(compiled, {})
    if scheme not in built:
        from . import numba_schemes

        generated = fill_kernel(compiled) if scheme == "rk4" else scheme_functions(compiled, scheme)
        built[scheme] = _build(numba_schemes.SCHEMES[scheme](generated, compiled.n), compiled.n)
    return built[scheme]


def _build(scheme, n: int):
    """The parallel loop over members around one member's ``scheme`` (numba_schemes.Scheme)."""
    numba = _numba()
    workspace, init, step = scheme
    limit = math.pi

    @numba.njit(parallel=True)
    def run(
        y0, params, grid, track, stop, save_every, tol, floor, iterations,
        final, flips, failures, paths,
    ):  # pragma: no cover - compiled by numba  # fmt: skip
        count, m = y0.shape
        steps = grid.shape[0] - 1
        for b in numba.prange(count):
            y = y0[b].copy()
            p = params[b]
            work = workspace()
            flip = np.nan
            failure = -1
            if track:
                for i in range(n):
                    if abs(y[i]) > limit:
                        flip = grid[0]
            if save_every > 0:
                for i in range(m):
                    paths[b, i, 0] = y[i]
            if not (stop and flip == flip):
                init(grid[0], y, p, work)
                for s in range(steps):
                    ta = grid[s]
                    if not step(ta, grid[s + 1] - ta, y, p, work, tol, floor, iterations):
                        failure = s
                        break
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
            failures[b] = failure
            for i in range(m):
                final[b, i] = y[i]

    return run


def _scheme(compiled: CompiledSystem, integrator: AbstractFixedStepIntegrator) -> str:
    if integrator.name == "rk4":
        return "rk4"
    if integrator.name == "variational":
        return integrator.scheme(compiled)
    raise ModelError(f"backend 'numba' integrates with rk4 or variational, not {integrator.name}")


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
    newton = (
        float(getattr(integrator, "newton_tol", 1e-14)), ROUNDING_FLOOR,
        int(getattr(integrator, "max_newton", 30)),
    )  # fmt: skip
    run(states, per_member, grid, track, stop, every, *newton, final, flips, failures, paths)
    if np.any(failures >= 0):
        raise ModelError(
            "the ensemble integration failed: Newton's method of the variational step did "
            f"not converge in {newton[2]} iterations at t = "
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

"""The numba backend: a parallel fixed-step loop around numba-compiled expressions.

The expressions come from the same symbolic equations as the numpy backend
(``compiled.forms``, :mod:`lagrangian.codegen.forms`),
printed as generated kernels cached on disk (:mod:`lagrangian.codegen.numba`):
M and f of M q'' = f for ``rk4``; the momenta, forces, M and the Newton
Jacobian of :mod:`lagrangian.codegen.schemes` for ``variational`` (the midpoint
scheme, or Stormer-Verlet when the system is separable, as
:class:`~lagrangian.integrate.variational.Variational` picks).  The schemes
(:mod:`.numba_loop`, a template written out per system and scheme so that
numba caches the loop's machine code on disk too) follow the numpy backend step
for step on the same step grid, so results agree with it to rounding.  One member per ``prange``
iteration; a member asking only for ``flip_time`` stops when it has flipped.

numba is imported here only (``pip install ".[numba]"``).
Constrained systems are not handled (use the numpy backend).
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..codegen.cache import built
from ..errors import MissingDependencyError, ModelError
from ..integrate.fixed_step import step_grid
from ..integrate.variational import ROUNDING_FLOOR
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


def scheme_functions(compiled: CompiledSystem, scheme: str):
    """The module of jitted fillers of a variational ``scheme`` (generated, cached on disk)."""
    from ..codegen.numba import load_functions
    from ..codegen.schemes import MATRICES, SCALARS, scheme_expressions

    forms = _forms(compiled)
    expressions = scheme_expressions(forms, scheme)
    return load_functions(forms, scheme, expressions, scalars=SCALARS, matrices=MATRICES)


def kernel(compiled: CompiledSystem, scheme: str = "rk4"):
    """The jitted ensemble loop of ``compiled`` and ``scheme`` (built once per equations)."""
    _numba()
    forms = _forms(compiled)
    build = lambda: _loop_module(compiled, scheme).run  # noqa: E731
    return built(forms.fingerprint, "numba-ensemble", build, scheme)


#: The generated fillers each scheme's loop calls (see numba_loop's globals).
_FILLERS = {
    "rk4": ("fill as mass_force",),
    "midpoint": ("momenta", "momenta_force", "mass", "jacobian"),
    "stormer-verlet": ("mass", "gradient"),
}
_SELECTED = {"rk4": "rk4", "midpoint": "midpoint", "stormer-verlet": "verlet"}
_BEGIN, _END = "# -- generated: begin", "# -- generated: end"
_SCHEME_BEGIN, _SCHEME_END = "# -- scheme: begin", "# -- scheme: end"
_SELECTION = "workspace, init, step = rk4_workspace, rk4_init, rk4_step"


def _loop_module(compiled: CompiledSystem, scheme: str):
    """The loop of :mod:`.numba_loop` for this system and scheme, as a generated module.

    The template's globals get the system's values, and the module is written to
    the code cache under a hash of its text, so numba keeps its machine code there.
    """
    from ..codegen.numba import load_module, load_text
    from ..codegen.steps import NumbaStepPrinter, scheme_program
    from ..integrate import tableaus
    from ..integrate.variational import STALL_RATIO

    _numba()
    if scheme == "rk4":
        fillers = load_module(_forms(compiled))
    else:
        fillers = scheme_functions(compiled, scheme)
    generated = [
        f"N = {compiled.n}",
        f"from {fillers.__name__} import {', '.join(_FILLERS[scheme])}",
    ]
    program = scheme_program(scheme, compiled.n, tableau=tableaus.RK4, stall=STALL_RATIO)
    template = Path(__file__).with_name("numba_loop.py").read_text(encoding="utf-8")
    head, rest = template.split(_BEGIN, 1)
    tail = rest.split(_END, 1)[1].split("\n", 1)[1]
    before, rest = tail.split(_SCHEME_BEGIN, 1)
    after = rest.split(_SCHEME_END, 1)[1].split("\n", 1)[1]
    printed = NumbaStepPrinter(compiled.n).scheme(program)
    tail = "\n".join([before.rstrip("\n"), "", "", printed, "", after.lstrip("\n")])
    chosen = _SELECTED[scheme]
    selection = f"workspace, init, step = {chosen}_workspace, {chosen}_init, {chosen}_step"
    tail = tail.replace(_SELECTION, selection)
    text = "\n".join([head.rstrip("\n"), "", *generated, "", tail])
    return load_text(hashlib.sha256(text.encode()).hexdigest(), text)


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

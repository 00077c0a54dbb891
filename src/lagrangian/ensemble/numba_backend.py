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
iteration; a member asking only for ``flip_time`` stops when it has flipped.  Without
``flip_time`` and the tangent observables, rk4 runs the tabulated loop
(:func:`tabulated_members`): what depends on t and the parameters every member shares
(a drive) is computed once per stage into a table, and the step reads it.  For the
``lyapunov`` observable the loop is the scheme ``rk4-tangent``: rk4 of the state with one
displacement from the generated variational equations, renormalised after every step,
as the numpy backend's :class:`~lagrangian.integrate.lyapunov.TangentFlow`; for the chaos
indicators (``sali``, ``gali<k>``) it carries k displacements, each renormalised after
every step, from the numpy backend's starting vectors
(:class:`~lagrangian.integrate.indicators.TangentFlows`), and the indicators are computed
here from the unit vectors at t_end, as there.

A constrained system runs rk4 in the loop of :mod:`lagrangian.integrate.numba_projected`
instead: its generated y' (the augmented system) and projection, those of the compiled DOP853 loop
(:func:`lagrangian.integrate.compiled_dop853.compiled_loop`), each member projected onto
the constraints after every step, as the numpy backend projects.

numba is imported here only (``pip install ".[numba]"``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..errors import MissingDependencyError, ModelError
from ..integrate.indicators import SALI_BELOW, starting_vectors
from .chunk import AbstractEnsembleBackend, Chunk, Outputs, Progress, generated_forms
from .observables import indicator_values, indicator_vectors

if TYPE_CHECKING:
    from ..codegen.forms import SymbolicForms
    from ..numeric.compiled import CompiledSystem


def _numba():
    try:
        import numba
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingDependencyError("backend 'numba'", "numba", "numba") from None
    return numba


def _forms(compiled: CompiledSystem) -> SymbolicForms:
    forms = generated_forms(compiled, "numba")
    _numba()
    return forms


def kernel(compiled: CompiledSystem, scheme: str = "rk4", vectors: int = 1):
    """The jitted loops of ``compiled`` and ``scheme`` (built once per equations), with
    ``vectors`` displacements for rk4-tangent: ``run`` is the ensemble's
    (:class:`~lagrangian.codegen.loops.SteppingLoop`)."""
    from ..codegen.loops import numba_loop
    from ..integrate import tableaus
    from ..integrate.variational import STALL_RATIO

    forms = _forms(compiled)
    return numba_loop(forms, scheme, tableau=tableaus.RK4, stall=STALL_RATIO, vectors=vectors)


def tabulated_kernel(compiled: CompiledSystem, shared):
    """The rk4 loop of ``compiled`` whose time-only terms (over t and the parameters
    numbered ``shared``) are read from a table (:mod:`lagrangian.codegen.time_terms`)."""
    from ..codegen.time_terms import tabulated_loop
    from ..integrate import tableaus

    return tabulated_loop(_forms(compiled), shared, tableau=tableaus.RK4)


class NumbaBackend(AbstractEnsembleBackend):
    """The generated parallel loop (see the module); numba is needed."""

    name: ClassVar[str] = "numba"

    def integrate(self, chunk: Chunk, progress: Progress | None = None) -> Outputs:
        if chunk.compiled.has_constraints:
            return projected_members(chunk)
        scheme = chunk.scheme(self.name)
        lyapunov = "lyapunov" in chunk.names
        vectors = indicator_vectors(chunk.names)
        if scheme == "rk4" and not (lyapunov or vectors or chunk.track):
            return tabulated_members(chunk)
        if lyapunov or vectors:
            scheme = tangent_scheme(scheme, chunk.integrator.name, chunk.names)
        run = kernel(chunk.compiled, scheme, max(vectors, 1)).run
        grid, count = chunk.grid, chunk.count
        states = np.ascontiguousarray(np.asarray(chunk.y0, dtype=float).T)
        m = states.shape[1]
        if lyapunov or vectors:  # the displacements' starting values after the state's
            states = np.hstack(
                [states, np.broadcast_to(displacements(m, vectors), (count, m * max(vectors, 1)))]
            )
        p = np.asarray(chunk.params, dtype=float)
        per_member = np.ascontiguousarray(
            p.T if p.ndim == 2 else np.broadcast_to(p, (count, p.size))
        )
        final = np.empty_like(states)
        flips = np.empty(count)
        failures = np.empty(count, dtype=np.int64)
        exponents = np.empty(count)
        paths = np.empty((count, states.shape[1], chunk.saved) if chunk.every else (1, 1, 1))
        newton = chunk.newton
        crossings = np.full(count, np.nan)
        run(
            states, per_member, grid, chunk.track, chunk.stop, chunk.every,
            newton.tol, newton.floor, newton.iterations, final, flips, failures, paths, exponents,
            below=SALI_BELOW if "sali" in chunk.names else 0.0, crossings=crossings,
        )  # fmt: skip
        chunk.check_newton(failures)
        values = chunk.result(final[:, :m].T, flips, np.transpose(paths, (1, 0, 2)))
        if lyapunov:
            values["lyapunov"] = exponents
        if vectors:
            unit = final[:, m:].reshape(count, vectors, m).transpose(1, 2, 0)  # (k, 2n, B)
            values.update(indicator_values(unit, chunk.names, crossings))
        return values


def tabulated_members(chunk: Chunk) -> Outputs:
    """The chunk by rk4 with what depends on t and the parameters every member shares (a
    drive) computed once per stage into a table (:mod:`lagrangian.codegen.time_terms`): a
    strobe map's or a bifurcation diagram's members all step at the same times."""
    from ..codegen.time_terms import shared_parameters

    count = chunk.count
    states = np.ascontiguousarray(np.asarray(chunk.y0, dtype=float).T)
    p = np.asarray(chunk.params, dtype=float)
    per_member = np.ascontiguousarray(p.T if p.ndim == 2 else np.broadcast_to(p, (count, p.size)))
    loop = tabulated_kernel(chunk.compiled, shared_parameters(per_member))
    grid = np.ascontiguousarray(chunk.grid, dtype=float)
    table = loop.table(grid, per_member[0])
    final = np.empty_like(states)
    paths = np.empty((count, states.shape[1], chunk.saved) if chunk.every else (1, 1, 1))
    loop.run(states, per_member, grid, table, chunk.every, final, paths)
    flips = np.full(count, np.nan)  # flip_time is tracked by the plain loop
    return chunk.result(final.T, flips, np.transpose(paths, (1, 0, 2)))


def displacements(size: int, vectors: int) -> np.ndarray:
    """The starting displacements, one after the other: the numpy backend's, (1, ..., 1) /
    sqrt(2n) for ``lyapunov`` alone (TangentFlow) and the orthonormal
    :func:`~lagrangian.integrate.indicators.starting_vectors` with indicators."""
    if not vectors:
        return np.full(size, 1.0 / np.sqrt(size))
    return starting_vectors(size, vectors).T.ravel()


def tangent_scheme(scheme: str, method: str, names: tuple[str, ...] = ("lyapunov",)) -> str:
    """The scheme that carries displacements with the state: rk4's (``rk4-tangent``);
    the other methods are refused, as by the numpy backend."""
    if scheme != "rk4":
        name = "lyapunov" if "lyapunov" in names else "chaos indicator"
        raise ModelError(f"the {name} observable needs an explicit method (rk4), not {method}")
    return "rk4-tangent"


def projected_members(chunk: Chunk) -> Outputs:
    """The chunk of a constrained system: rk4 and a projection every step, per member, in
    the shared loop of :mod:`lagrangian.integrate.numba_projected` (see the module docstring)."""
    from ..integrate import tableaus
    from ..integrate.compiled_dop853 import compiled_loop
    from ..integrate.compiled_loop import projected_module

    compiled = chunk.compiled
    if chunk.scheme("numba") != "rk4":
        raise ModelError(
            f"backend 'numba' integrates a constrained system with rk4, not {chunk.integrator.name}"
        )
    if "lyapunov" in chunk.names:
        raise ModelError("the lyapunov observable does not take constrained systems")
    if compiled.forms is None:
        raise ModelError(
            "backend 'numba' generates code from derived equations, not given functions"
        )
    _numba()
    loop = compiled_loop(compiled)
    module = projected_module()
    count = chunk.count
    states = np.ascontiguousarray(np.asarray(chunk.y0, dtype=float).T)
    p = np.asarray(chunk.params, dtype=float)
    per_member = np.ascontiguousarray(p.T if p.ndim == 2 else np.broadcast_to(p, (count, p.size)))
    final, flips = np.empty_like(states), np.empty(count)
    paths = np.empty((count, states.shape[1], chunk.saved) if chunk.every else (1, 1, 1))
    tableau = tableaus.RK4
    module.run(
        loop.y_prime, loop.n, states, per_member, chunk.grid, np.ascontiguousarray(tableau.a),
        np.ascontiguousarray(tableau.b), np.ascontiguousarray(tableau.c), chunk.track,
        chunk.stop, chunk.every, final, flips, paths,
    )  # fmt: skip
    return chunk.result(final.T, flips, np.transpose(paths, (1, 0, 2)))

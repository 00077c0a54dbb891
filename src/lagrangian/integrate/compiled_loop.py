"""Fixed-step single runs in compiled code: the numba loop, a stretch of steps at a time.

On the numba backend a single run of rk4 or variational (unconstrained, from derived
equations) takes its steps in the generated loop of :mod:`lagrangian.codegen.loops`,
the module whose ``run`` is the numba ensemble's loop, with the same printed step:
``advance`` takes a stretch (a chunk) of steps in one call and keeps every state in
one array.  Between chunks Python tells ``watch`` (progress, a time budget) the time
reached; the fixed-step driver then checks events and the energy balance on the kept
states as for any run.  A chunk lasts about :data:`CHUNK_SECONDS`: the first has
:data:`FIRST_CHUNK` steps and the next ones double while they take less (the chunk
sizes change how often Python looks, never the states).

The step's failures come back as codes and become the messages of the Python loop's
(Newton did not converge, a state that is not finite).  Where a generated function
raises instead (numba's ``ZeroDivisionError`` for 1/x at x = 0, where NumPy gives inf),
:meth:`CompiledLoop.march` raises :class:`Unavailable` and the driver runs the whole
span again step by step in Python, which reports the inf or NaN as it does.

A constrained system's rk4 runs in :class:`ProjectedLoop` instead: the loop of
:mod:`.numba_projected` (the numba ensemble's, for one member), each state projected onto
the constraints after every step as the Python loop projects it.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from .base import Work

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Seconds of stepping between two looks from Python (progress, time budget, events).
CHUNK_SECONDS = 0.05
#: Steps of the first chunk (then doubled while a chunk takes less than CHUNK_SECONDS).
FIRST_CHUNK = 256


class Unavailable(Exception):
    """Generated code could not evaluate a value (numba and ``math`` raise where NumPy gives
    inf or NaN): the caller takes the step, or the run, with the NumPy functions."""


class Newton(NamedTuple):
    """The settings of a scheme's Newton iterations (see :mod:`.variational`)."""

    tol: float
    floor: float  # ROUNDING_FLOOR
    stall: float  # STALL_RATIO
    iterations: int


class Marched(NamedTuple):
    """What :meth:`CompiledLoop.march` reached: ``states[k]`` is the state at ``grid[k]`` for
    k <= ``reached``; ``failed``: 0, or the failure code of step ``reached`` (1, 2: the
    scheme's Newton iterations; 3: the state after it is not finite, ``last``)."""

    states: np.ndarray
    reached: int
    failed: int
    last: np.ndarray


class CompiledLoop:
    """The generated loop module of one system and scheme (see the module docstring)."""

    def __init__(self, module, newton: Newton):
        self.module = module
        self.newton = newton

    def march(
        self,
        grid: np.ndarray,
        y0: np.ndarray,
        params: np.ndarray,
        work: Work,
        chunk: Callable[[np.ndarray, int, int], bool] | None = None,
    ) -> Marched:
        """Step ``y0`` along ``grid`` until its end, the first failure, or until
        ``chunk(states, start, stop)``, told of each chunk of steps just taken, says stop."""
        module, newton = self.module, self.newton
        steps = grid.shape[0] - 1
        y = np.array(y0, dtype=float)
        p = np.ascontiguousarray(params, dtype=float)
        states = np.empty((steps + 1, y.shape[0]))
        states[0] = y
        counts = np.zeros(3, dtype=np.int64)
        reached, failed, size = 0, 0, FIRST_CHUNK
        try:
            workspace = module.workspace()
            _generated(module.init, float(grid[0]), y, p, workspace, counts)
            while reached < steps and not failed:
                start, stop = reached, min(steps, reached + size)
                began = time.perf_counter()
                reached, failed = _generated(
                    module.advance, y, p, workspace, grid, start, stop, newton.tol,
                    newton.floor, newton.iterations, states, counts,
                )  # fmt: skip
                if time.perf_counter() - began < CHUNK_SECONDS / 2:
                    size *= 2
                if chunk is not None and chunk(states, start, reached):
                    break
        finally:
            work.rhs_evaluations += int(counts[0])
            work.jacobian_evaluations += int(counts[1])
            work.newton_iterations += int(counts[2])
            work.steps += int(reached)
        return Marched(states, int(reached), int(failed), y)

    def prepare(self, y0: np.ndarray, params: np.ndarray) -> None:
        """Make (or load from numba's cache) the loop's code for a run from ``y0`` by calls
        that take no step (numba compiles a function at its first call), so that its cost
        is paid, and measured, before the run (its ``compile_time``); an error of
        evaluation at ``y0`` is left to the run, which reports it."""
        y = np.array(y0, dtype=float)
        p = np.ascontiguousarray(params, dtype=float)
        counts = np.zeros(3, dtype=np.int64)
        states, grid, newton = np.empty((1, y.shape[0])), np.zeros(1), self.newton
        workspace = self.module.workspace()
        with contextlib.suppress(Unavailable):
            _generated(self.module.init, 0.0, y, p, workspace, counts)
            _generated(
                self.module.advance, y, p, workspace, grid, 0, 0, newton.tol, newton.floor,
                newton.iterations, states, counts,
            )  # fmt: skip


def _generated(function, *arguments):
    """``function(*arguments)`` of the generated module; its errors of evaluation (numba
    raises where NumPy gives inf or NaN) become :class:`Unavailable`."""
    try:
        return function(*arguments)
    except (ZeroDivisionError, ValueError, OverflowError):
        raise Unavailable from None


class ProjectedLoop:
    """rk4 of a constrained system in compiled code, every state projected onto the
    constraints (:mod:`.numba_projected`, one member), marched as :class:`CompiledLoop`."""

    def __init__(self, module, y_prime, size: int):
        self.module, self.y_prime, self.size = module, y_prime, size

    def march(self, grid, y0, params, work: Work, chunk=None) -> Marched:
        """As :meth:`CompiledLoop.march` (a state that is not finite fails with code 3)."""
        from .tableaus import RK4

        a, b, c = (np.ascontiguousarray(x, dtype=float) for x in (RK4.a, RK4.b, RK4.c))
        steps = grid.shape[0] - 1
        y = np.array(y0, dtype=float)
        p = np.ascontiguousarray(params, dtype=float)[None, :]
        states = np.empty((steps + 1, y.shape[0]))
        states[0] = y
        final, flips = np.empty((1, y.shape[0])), np.empty(1)
        reached, failed, size = 0, 0, FIRST_CHUNK
        try:
            while reached < steps and not failed:
                start, stop = reached, min(steps, reached + size)
                paths = np.empty((1, y.shape[0], stop - start + 1))
                began = time.perf_counter()
                _generated(
                    self.module.run, self.y_prime, self.size, y[None, :], p,
                    grid[start : stop + 1], a, b, c, False, False, 1, final, flips, paths,
                )  # fmt: skip
                taken = paths[0].T[1:]
                bad = ~np.all(np.isfinite(taken), axis=1)
                if bad.any():  # the step into the first state that is not finite failed
                    k = int(np.argmax(bad))
                    states[start + 1 : start + k + 1] = taken[:k]
                    reached, failed, y = start + k, 3, taken[k].copy()
                    break
                states[start + 1 : stop + 1] = taken
                reached, y = stop, taken[-1].copy()
                if time.perf_counter() - began < CHUNK_SECONDS / 2:
                    size *= 2
                if chunk is not None and chunk(states, start, reached):
                    break
        finally:
            work.rhs_evaluations += 4 * int(reached)
            work.steps += int(reached)
        return Marched(states, int(reached), int(failed), y)


def projected_module():
    """:mod:`.numba_projected` in the code cache (one module for every constrained system:
    numba compiles its loop once on a machine)."""
    from pathlib import Path

    from ..codegen.cache import load_text, package_text

    return load_text(*package_text(Path(__file__).with_name("numba_projected.py")))


def compiled_loop(
    compiled: CompiledSystem, scheme: str | None, newton: Newton
) -> CompiledLoop | ProjectedLoop | None:
    """The :class:`CompiledLoop` of ``compiled`` for ``scheme`` (None: the method has no
    printed scheme; with constraints, the :class:`ProjectedLoop` of rk4), or None where the
    run is not compiled: a backend other than numba, or functions given by hand instead of
    derived equations."""
    if scheme is None or compiled.backend != "numba" or compiled.forms is None:
        return None
    if compiled.has_constraints:
        if scheme != "rk4":
            return None
        from .compiled_dop853 import compiled_loop as dop853_loop

        loop = dop853_loop(compiled)  # its y' and projection, generated for n + m
        if loop is None:
            return None
        return ProjectedLoop(projected_module(), loop.y_prime, loop.n)
    from ..codegen.loops import numba_loop
    from . import tableaus

    module = numba_loop(compiled.forms, scheme, tableau=tableaus.RK4, stall=newton.stall)
    return CompiledLoop(module, newton)

"""The ``numba`` backend: the single-state functions as numba-jitted generated code.

``rhs``, ``accelerations``, ``mass_matrix``, ``forcing`` and ``energy`` of one
state (``y`` of shape ``(2n,)``, ``params`` ``(P,)``, scalar ``t``) call the
kernels of :mod:`lagrangian.codegen.numba`, generated from the same
symbolic forms as the NumPy functions: M and f from common-subexpression-
eliminated scalar code, q'' from M q'' = f by Gaussian elimination inside the
kernel.  Everything else, and any batched call (a trailing batch axis), uses
the NumPy backend's functions, so results agree to rounding either way.  The
code is generated and jitted on the first call (then cached on disk).  Where a
kernel divides by zero (numba raises ZeroDivisionError: a zero pivot of M, or
1/x at x = 0) the NumPy function answers instead, with the NumPy backend's
result: inf or NaN, which the integrators report, or its singular-matrix error.

A constrained system keeps the NumPy functions of one state (its y' solves the augmented
system, see :mod:`lagrangian.numeric.dynamics`): on this backend its ``dop853`` runs in the
compiled loop, which generates the constrained y' and the projection itself
(:mod:`lagrangian.integrate.compiled_dop853`).
numba is imported only when a numba function is first called with one state,
or by :meth:`~lagrangian.codegen.numba.NumbaTarget.check` (``pip install ".[numba]"``).
"""

from __future__ import annotations

import dataclasses
import threading
from collections.abc import Callable
from typing import Any

import numpy as np

from ..codegen.numba import NumbaTarget
from ..codegen.program import Program
from .compiled import CompiledSystem

#: The CompiledSystem fields the numba kernels provide, with their argument form.
STATE_FUNCTIONS = ("rhs", "energy")  # (t, y, params)
SPLIT_FUNCTIONS = ("accelerations", "mass_matrix", "forcing")  # (t, q, v, params)
SCALAR_FUNCTIONS = ("energy",)
SCALARS = (
    float,
    int,
    np.float64,
)  # types of t taken without a look at np.ndim  # the kernel returns a float


def with_numba_functions(compiled: CompiledSystem) -> CompiledSystem:
    """``compiled`` (NumPy functions) with the numba kernels of its program put in.

    A constrained system keeps the NumPy functions (see the module docstring).
    """
    if compiled.has_constraints:
        return dataclasses.replace(compiled, backend="numba")
    names = (*STATE_FUNCTIONS, *SPLIT_FUNCTIONS)
    fallbacks = {name: getattr(compiled, name) for name in names}
    functions = NumbaFunctions(compiled.program, fallbacks).functions()
    return dataclasses.replace(compiled, backend="numba", **functions)


class NumbaFunctions:
    """The jitted functions of one system, built on first use, with NumPy fallbacks."""

    def __init__(self, program: Program, fallbacks: dict[str, Callable[..., Any]]):
        self._program = program
        self._fallbacks = fallbacks
        self._n = program.n
        self._p = len(program.forms.parameters)
        self._module = None
        self._lock = threading.Lock()

    def module(self):
        """The generated module (generated or read from the disk cache on first use)."""
        if self._module is None:
            with self._lock:
                if self._module is None:
                    target = NumbaTarget()
                    target.check()
                    self._module = target.load(self._program)
        return self._module

    def functions(self) -> dict[str, Callable[..., Any]]:
        """CompiledSystem field name -> function."""
        result = {name: self._state_function(name) for name in STATE_FUNCTIONS}
        result.update({name: self._split_function(name) for name in SPLIT_FUNCTIONS})
        return result

    def _state_function(self, name: str) -> Callable[..., Any]:
        fallback, state_shape, parameter_shape = self._fallbacks[name], (2 * self._n,), (self._p,)
        kernel = None

        def jitted(t: Any, y: Any, params: Any) -> Any:
            nonlocal kernel
            if type(y) is not np.ndarray or y.dtype != np.float64:  # the fast path: SciPy's y
                y = np.asarray(y, dtype=float)
            if type(params) is not np.ndarray or params.dtype != np.float64:
                params = np.asarray(params, dtype=float)
            if (
                y.shape != state_shape
                or params.shape != parameter_shape
                or (type(t) not in SCALARS and np.ndim(t))
            ):
                return fallback(t, y, params)  # a batch, or an error to report
            if kernel is None:
                kernel = getattr(self.module(), name)
            try:
                return kernel(float(t), y, params)
            except ZeroDivisionError:  # numba raises where NumPy gives inf, or names M singular
                return fallback(t, y, params)

        def scalar_function(t: Any, y: Any, params: Any) -> Any:
            return np.asarray(jitted(t, y, params))  # a 0-d array, as the NumPy backend's

        function = scalar_function if name in SCALAR_FUNCTIONS else jitted
        function.__name__ = function.__qualname__ = name
        return function

    def _split_function(self, name: str) -> Callable[..., Any]:
        fallback, shape, parameter_shape = self._fallbacks[name], (self._n,), (self._p,)
        kernel = None

        def function(t: Any, q: Any, v: Any, params: Any) -> Any:
            nonlocal kernel
            q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
            p = np.asarray(params, dtype=float)
            if q.shape != shape or v.shape != shape or p.shape != parameter_shape or np.ndim(t):
                return fallback(t, q, v, p)
            if kernel is None:
                kernel = getattr(self.module(), name)
            try:
                return kernel(float(t), np.concatenate((q, v)), p)
            except ZeroDivisionError:  # as above
                return fallback(t, q, v, p)

        function.__name__ = function.__qualname__ = name
        return function

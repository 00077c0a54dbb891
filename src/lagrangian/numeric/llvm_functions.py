"""The ``llvm`` backend: the right-hand side of one state as SymEngine's LLVM-compiled code.

``rhs``, ``accelerations`` and ``rhs_jacobian`` of one state (``y`` of shape
``(2n,)``, ``params`` ``(P,)``, scalar ``t``) evaluate the entries of M and f of M q'' = f with
:class:`symengine.Lambdify` (``backend="llvm"``, common subexpressions
eliminated), then solve M q'' = f (LAPACK's ``dgesv``);
the Jacobian solves M X = G for G = d(f - M a)/d(q, q') at a = q''
(:func:`lagrangian.codegen.llvm.load_jacobian`, a second function).  The
code is made on the first call, in milliseconds (a 10-link chain: about 0.05 s,
where numba compiles for seconds), which is why a single run starts fastest here.
Everything else, any batched call and any system whose equations SymEngine cannot
hold (declared functions, floating-point numbers in the equations: see
:func:`lagrangian.algebra.to_symengine`) use the NumPy backend's functions, as do
constrained systems; results agree with them to rounding.  A singular M is
reported by the NumPy function, as with the NumPy backend.
"""

from __future__ import annotations

import dataclasses
import math
import threading
from collections.abc import Callable
from typing import Any

import numpy as np

from ..codegen.llvm import llvm_blocks, load_jacobian
from ..codegen.program import Program
from .backends import solve_one
from .compiled import CompiledSystem

SCALARS = (float, int, np.float64)


def with_llvm_functions(compiled: CompiledSystem) -> CompiledSystem:
    """``compiled`` (NumPy functions) with ``rhs`` and ``accelerations`` of one state from LLVM."""
    if compiled.has_constraints:
        return dataclasses.replace(compiled, backend="llvm")
    kernel = _Kernel(compiled.program)
    functions = {
        "rhs": kernel.rhs_function(compiled.rhs),
        "accelerations": kernel.accelerations_function(compiled.accelerations),
        "rhs_jacobian": kernel.jacobian_function(compiled.rhs_jacobian),
    }
    return dataclasses.replace(compiled, backend="llvm", **functions)


class _Kernel:
    """M and f of one state as one LLVM function (made on first use, None where impossible)."""

    def __init__(self, program: Program):
        self._program = program
        self._n = program.n
        self._p = len(program.forms.parameters)
        self._built: dict[str, object] = {}
        self._lock = threading.Lock()

    def _loaded(self, name: str, load: Callable[[Program], Any]):
        if name not in self._built:
            with self._lock:
                if name not in self._built:
                    self._built[name] = load(self._program)
        return self._built[name]

    def function(self):
        """[M, f] over [t, q, q', params] (None where LLVM cannot hold it)."""
        return self._loaded("blocks", llvm_blocks)

    def jacobian(self):
        """G = d(f - M a)/d(q, q') over [t, q, q', a, params] (None where LLVM cannot)."""
        return self._loaded("jacobian", load_jacobian)

    def _evaluate(self, t: Any, y: np.ndarray, params: np.ndarray):
        """(M, f) at one state, or None where the LLVM code is not there or not usable."""
        function = self.function()
        if function is None:
            return None
        n = self._n
        values = np.concatenate(((float(t),), y, params))
        out = np.empty(n * n + n)
        function.unsafe_real(values, out)
        return out[: n * n].reshape(n, n), out[n * n :]

    def _one_state(self, t: Any, y: Any, params: Any):
        """(y, params) as float arrays when they are one state, else None."""
        if type(y) is not np.ndarray or y.dtype != np.float64:
            y = np.asarray(y, dtype=float)
        if type(params) is not np.ndarray or params.dtype != np.float64:
            params = np.asarray(params, dtype=float)
        if y.shape != (2 * self._n,) or params.shape != (self._p,):
            return None
        if type(t) not in SCALARS and np.ndim(t):
            return None
        return y, params

    def rhs_function(self, fallback: Callable[..., Any]) -> Callable[..., Any]:
        n = self._n

        def rhs(t: Any, y: Any, params: Any) -> Any:
            one = self._one_state(t, y, params)
            parts = None if one is None else self._evaluate(t, *one)
            accelerations = None if parts is None else _solve(*parts)
            if accelerations is None:
                return fallback(t, y, params)  # a batch, an error to report, or no LLVM code
            return np.concatenate((one[0][n:], accelerations))

        return rhs

    def accelerations_function(self, fallback: Callable[..., Any]) -> Callable[..., Any]:
        def accelerations(t: Any, q: Any, v: Any, params: Any) -> Any:
            q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
            one = None
            if q.ndim == 1 and v.ndim == 1:
                one = self._one_state(t, np.concatenate((q, v)), params)
            parts = None if one is None else self._evaluate(t, *one)
            result = None if parts is None else _solve(*parts)
            return fallback(t, q, v, params) if result is None else result

        return accelerations

    def jacobian_function(self, fallback: Callable[..., Any]) -> Callable[..., Any]:
        n = self._n
        upper = np.hstack((np.zeros((n, n)), np.eye(n)))

        def rhs_jacobian(t: Any, y: Any, params: Any) -> Any:
            one = self._one_state(t, y, params)
            parts = None if one is None else self._evaluate(t, *one)
            accelerations = None if parts is None else _solve(*parts)
            function = None if accelerations is None else self.jacobian()
            if function is None:
                return fallback(t, y, params)
            y, params = one
            values = np.concatenate(((float(t),), y, accelerations, params))
            derivative = np.empty(2 * n * n)
            function.unsafe_real(values, derivative)
            lower = solve_one(parts[0], derivative.reshape(n, 2 * n))
            if lower is None or not math.isfinite(lower.sum()):
                return fallback(t, y, params)
            return np.vstack((upper, lower))

        return rhs_jacobian


def _solve(matrix: np.ndarray, force: np.ndarray) -> np.ndarray | None:
    """q'' with M q'' = f; None where M is singular or the values are not finite."""
    result = solve_one(matrix, force)
    if result is None or not math.isfinite(result.sum()):
        return None  # the NumPy function gives its own inf, NaN or error (or a huge sum)
    return result

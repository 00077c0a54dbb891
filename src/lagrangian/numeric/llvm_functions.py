"""The ``llvm`` backend: the right-hand side of one state as SymEngine's LLVM-compiled code.

``rhs`` and ``accelerations`` of one state (``y`` of shape ``(2n,)``, ``params``
``(P,)``, scalar ``t``) evaluate the entries of M and f of M q'' = f with
:class:`symengine.Lambdify` (``backend="llvm"``, common subexpressions
eliminated), then solve M q'' = f (closed forms up to n = 2, else LAPACK's ``dgesv``).  The
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
import functools
import math
import threading
from collections.abc import Callable
from typing import Any

import numpy as np

from ..algebra import to_symengine
from ..codegen.forms import SymbolicForms
from ..distributions import without_distributions
from ..errors import MissingDependencyError
from .backends import solve_one
from .compiled import CompiledSystem

SCALARS = (float, int, np.float64)


@functools.cache
def llvm_available() -> bool:
    """Whether SymEngine's Lambdify can compile with LLVM here."""
    try:
        import symengine as se

        x = se.Symbol("x")
        se.Lambdify([x], [x + 1], backend="llvm")
    except (ImportError, RuntimeError, ValueError, TypeError):
        return False
    return True


def check_llvm() -> None:
    """A MissingDependencyError naming what is missing when SymEngine has no LLVM."""
    if not llvm_available():
        raise MissingDependencyError(
            "backend 'llvm'", "SymEngine built with LLVM (the symengine wheels are)"
        )


def with_llvm_functions(forms: SymbolicForms, compiled: CompiledSystem) -> CompiledSystem:
    """``compiled`` (NumPy functions) with ``rhs`` and ``accelerations`` of one state from LLVM."""
    if compiled.has_constraints:
        return dataclasses.replace(compiled, backend="llvm")
    kernel = _Kernel(forms)
    functions = {
        "rhs": kernel.rhs_function(compiled.rhs),
        "accelerations": kernel.accelerations_function(compiled.accelerations),
    }
    return dataclasses.replace(compiled, backend="llvm", **functions)


class _Kernel:
    """M and f of one state as one LLVM function (made on first use, None where impossible)."""

    def __init__(self, forms: SymbolicForms):
        self._forms = forms
        self._n = forms.n
        self._p = len(forms.parameters)
        self._built = False
        self._function = None
        self._lock = threading.Lock()

    def function(self):
        if not self._built:
            with self._lock:
                if not self._built:
                    self._function = _compile(self._forms)
                    self._built = True
        return self._function

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


def _compile(forms: SymbolicForms):
    """symengine.Lambdify of [M row by row, f] over [t, q, q', params], or None."""
    import symengine as se

    if not llvm_available():
        return None
    n = forms.n
    cache: dict = {}
    entries = [forms.mass_matrix[i, j] for i in range(n) for j in range(n)]
    entries += [forms.forcing[i, 0] for i in range(n)]
    converted = [to_symengine(without_distributions(entry), cache) for entry in entries]
    arguments = (forms.time, *forms.coordinates, *forms.velocities, *forms.parameters)
    symbols = [to_symengine(symbol, cache) for symbol in arguments]
    if any(x is None for x in converted):
        return None  # something SymEngine cannot hold: the NumPy functions answer
    known = set(symbols)
    if any(not (x.free_symbols <= known) for x in converted):
        return None
    try:
        return se.Lambdify(symbols, converted, backend="llvm", cse=True)
    except (RuntimeError, ValueError, TypeError, NotImplementedError):
        return None


def _solve(matrix: np.ndarray, force: np.ndarray) -> np.ndarray | None:
    """q'' with M q'' = f; None where M is singular or the values are not finite."""
    result = solve_one(matrix, force)
    if result is None or not math.isfinite(result.sum()):
        return None  # the NumPy function gives its own inf, NaN or error (or a huge sum)
    return result

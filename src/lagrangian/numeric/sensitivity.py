"""The right-hand side of the forward sensitivity equations, for one state.

See :mod:`lagrangian.codegen.sensitivity` for the equations: with y = [q, q'] and the
solved accelerations a (``compiled.rhs``), the block dR/d(q, q', p_wrt) of
R = f - M a is evaluated at (t, q, q', a, p) and solved with M once, which gives
dF/dy (the same matrix as ``compiled.rhs_jacobian``) and dF/dp_wrt together.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..codegen.sensitivity import sensitivity_forms
from ..errors import ModelError
from .backends import array_backend
from .compiled import CompiledSystem
from .kernels import Kernel


class SensitivityFunctions:
    """dF/dy and dF/dp_wrt of one compiled system, for one state (NumPy arrays)."""

    def __init__(self, compiled: CompiledSystem, wrt: Sequence[str]):
        forms = compiled.forms
        if forms is None:
            raise ModelError("sensitivities need equations derived from a model")
        self._compiled = compiled
        self._n = compiled.n
        self._sensitivity = sensitivity_forms(forms, wrt)
        block = self._sensitivity.residual_jacobian
        self._kernel = Kernel(array_backend("numpy"), self._sensitivity.arguments, lambda: [block])

    @property
    def wrt(self) -> tuple[str, ...]:
        return self._sensitivity.wrt

    def derivatives(
        self, t: float, y: np.ndarray, params: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(F (2n,), dF/dy (2n, 2n), dF/dp_wrt (2n, k)) at (t, y)."""
        n, compiled = self._n, self._compiled
        slope = np.asarray(compiled.rhs(t, y, params), dtype=float)
        mass = np.asarray(compiled.mass_matrix(t, y[:n], y[n:], params), dtype=float)
        _, (residual,) = self._kernel(t, (np.concatenate((y, slope[n:])),), params)
        lower = np.linalg.solve(mass, np.asarray(residual, dtype=float))
        k = lower.shape[1] - 2 * n
        jacobian = np.zeros((2 * n, 2 * n))
        jacobian[:n, n:] = np.eye(n)
        jacobian[n:] = lower[:, : 2 * n]
        forcing = np.zeros((2 * n, k))
        forcing[n:] = lower[:, 2 * n :]
        return slope, jacobian, forcing

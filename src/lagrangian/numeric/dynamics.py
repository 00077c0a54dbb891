"""The accelerations: M(q, t) q'' = f(q, q', t) solved numerically, and their Jacobian.

Without constraints, q'' solves M q'' = f (``linalg.solve``; for a batch, the
stacked solve over matrices (*batch, n, n)).  With constraints
(M q'' = f + A^T lambda, A q'' = beta; see :mod:`lagrangian.derive.constraints`)
q'' and the multipliers solve the augmented system

    [[M, -A^T], [A, 0]] [q''; lambda] = [f; beta - 2 alpha (A q' + a0) - alpha^2 c],

where the last two terms are Baumgarte's stabilisation (the alpha^2 term for
holonomic constraints c(q, t) = 0 only): a residual then decays like
exp(-alpha t) instead of drifting (J. Baumgarte, Comput. Methods Appl. Mech.
Eng. 1 (1972) 1-16).  With the residuals zero the solution is exact.

The Jacobian of the right-hand side is compiled, not differenced.  Write the
dynamics as R(z, x) = 0 with z = (q, q'), x = (q'', lambda) and
R = [f + A^T lambda - M q''; b - A q''].  Differentiating along the solution,
K dx/dz = dR/dz at fixed x (K the matrix above, or M), so

    d q''/dz = M^-1 (df/dz - dM/dz q'')            (unconstrained),

with dR/dz a lambdified symbolic derivative evaluated at the solved x.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy

from ..codegen.forms import SymbolicForms
from ..errors import SingularMassMatrixError
from .backends import Array
from .kernels import Kernel, Signature, to_trailing, with_batch


class Dynamics:
    """Solved accelerations (and multipliers) of one system, for one state or a batch."""

    def __init__(self, forms: SymbolicForms, signature: Signature, baumgarte: float):
        backend = signature.backend
        self._signature = signature
        self._backend = backend
        self._xp = backend.xp
        self._n = forms.n
        constraints = forms.constraints
        self._m = constraints.count if constraints is not None else 0
        multipliers = constraints.multipliers if constraints is not None else ()
        time, q, v, p = forms.time, forms.coordinates, forms.velocities, forms.parameters

        def blocks():
            result = [forms.mass_matrix, list(forms.forcing)]
            if constraints is not None:
                result += [constraints.matrix, list(constraints.stabilised_bias(baumgarte))]
            return result

        def jacobian_blocks():
            accelerations = sympy.Matrix(forms.accelerations)
            residual = sympy.Matrix(forms.forcing) - forms.mass_matrix * accelerations
            if constraints is not None:
                matrix = sympy.Matrix(constraints.matrix)
                residual += matrix.T * sympy.Matrix(multipliers)
                bias = sympy.Matrix(constraints.stabilised_bias(baumgarte))
                residual = sympy.Matrix.vstack(residual, bias - matrix * accelerations)
            return [residual.jacobian([*q, *v])]

        self._kernel = Kernel(backend, (time, *q, *v, *p), blocks)
        self._jacobian_kernel = Kernel(
            backend, (time, *q, *v, *forms.accelerations, *multipliers, *p), jacobian_blocks
        )

    # -- the solve -----------------------------------------------------------------
    def _augmented(self, mass: Array, matrix: Array) -> Array:
        """[[M, -A^T], [A, 0]], batch-first."""
        xp = self._xp
        zeros = xp.zeros((*matrix.shape[:-1], self._m), dtype=matrix.dtype)
        top = xp.concatenate([mass, -self._backend.transpose(matrix)], axis=-1)
        bottom = xp.concatenate([matrix, zeros], axis=-1)
        return xp.concatenate([top, bottom], axis=-2)

    def _solve(self, t: Any, parts: tuple[Array, ...], params: Array):
        """(batch, K, q'', lambda): K is M or the augmented matrix; arrays batch-first."""
        batch, blocks = self._kernel(t, parts, params)
        mass, forcing = blocks[:2]
        if not self._m:
            return batch, mass, self._solved(mass, forcing, t, parts), None
        matrix, bias = blocks[2:]
        system = self._augmented(mass, matrix)
        right = self._xp.concatenate([forcing, bias], axis=-1)
        solution = self._solved(system, right, t, parts)
        return batch, system, solution[..., : self._n], solution[..., self._n :]

    def _solved(self, matrix: Array, rhs: Array, t: Any, parts: tuple[Array, ...]) -> Array:
        try:
            return self._backend.solve(matrix, rhs)
        except np.linalg.LinAlgError:
            q = np.asarray(parts[0])[: self._n]
            single = q.ndim == 1 and np.ndim(t) == 0
            raise SingularMassMatrixError.at_state(
                float(t) if single else None, self._signature.coordinate_names, q.tolist(),
                constrained=bool(self._m),
            ) from None  # fmt: skip

    def _state(self, y: Any, params: Any) -> tuple[Array, Array]:
        return self._signature.state(y), self._signature.parameters(params)

    # -- the public functions ---------------------------------------------------------
    def rhs(self, t: Any, y: Any, params: Any) -> Array:
        """y' = [q', q'']."""
        y, params = self._state(y, params)
        batch, _, accelerations, _ = self._solve(t, (y,), params)
        accelerations = to_trailing(accelerations, batch, self._xp)
        velocities = with_batch(y[self._n :], batch, self._xp)
        return self._xp.concatenate([velocities, accelerations], axis=0)

    def accelerations(self, t: Any, q: Any, v: Any, params: Any) -> Array:
        """q''."""
        parts = (self._signature.coordinates(q), self._signature.coordinates(v, "q_dot"))
        batch, _, accelerations, _ = self._solve(t, parts, self._signature.parameters(params))
        return to_trailing(accelerations, batch, self._xp)

    def multipliers(self, t: Any, y: Any, params: Any) -> Array:
        """lambda of M q'' = f + A^T lambda (with the stabilised constraint rows)."""
        y, params = self._state(y, params)
        batch, _, _, multipliers = self._solve(t, (y,), params)
        return to_trailing(multipliers, batch, self._xp)

    def mass_matrix(self, t: Any, q: Any, v: Any, params: Any) -> Array:
        """M, (n, n[, batch])."""
        return self._block(0, t, q, v, params)

    def forcing(self, t: Any, q: Any, v: Any, params: Any) -> Array:
        """f (without constraint forces), (n[, batch])."""
        return self._block(1, t, q, v, params)

    def _block(self, index: int, t: Any, q: Any, v: Any, params: Any) -> Array:
        parts = (self._signature.coordinates(q), self._signature.coordinates(v, "q_dot"))
        return self._kernel.trailing(t, parts, self._signature.parameters(params))[index]

    def rhs_jacobian(self, t: Any, y: Any, params: Any) -> Array:
        """d rhs / d y = [[0, I], [dq''/dq, dq''/dq']], (2n, 2n[, batch])."""
        xp, n = self._xp, self._n
        y, params = self._state(y, params)
        batch, system, accelerations, multipliers = self._solve(t, (y,), params)
        parts = [y, to_trailing(accelerations, batch, xp)]
        if self._m:
            parts.append(to_trailing(multipliers, batch, xp))
        _, (derivative,) = self._jacobian_kernel(t, tuple(parts), params)
        lower = self._backend.solve_matrix(system, derivative)[..., :n, :]
        upper = xp.concatenate(
            [
                xp.zeros((*batch, n, n), dtype=lower.dtype),
                xp.broadcast_to(xp.eye(n, dtype=lower.dtype), (*batch, n, n)),
            ],
            axis=-1,
        )
        return to_trailing(xp.concatenate([upper, lower], axis=-2), batch, xp)

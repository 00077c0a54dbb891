"""Constraint residuals and the projection of a state onto the constraint manifold.

An integrator of the (Baumgarte-stabilised) equations keeps the constraints
only approximately; :meth:`ConstraintFunctions.project` moves a state back:

1. positions, for the holonomic constraints c(q, t) = 0, by Gauss-Newton steps
   with the M-weighted minimum-norm correction (the smallest change in kinetic
   metric),

       dq = -M^-1 C^T (C M^-1 C^T)^-1 c(q),   C = dc/dq,

   which converge quadratically near the manifold;
2. velocities, onto A(q, t) q' + a0(q, t) = 0 for every constraint, by the same
   correction (exact in one step, the condition being linear in q').

The residual reported is position-level, c(q, t), for a holonomic constraint
and velocity-level, A q' + a0, for the others (nonholonomic ones have no
position level); ``velocity_residual`` gives A q' + a0 for all of them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..codegen.forms import SymbolicForms
from .backends import Array
from .kernels import Kernel, Signature, batch_shape, to_trailing, with_batch

#: Gauss-Newton steps at most (NumPy stops when converged).
MAX_ITERATIONS = 50
#: Gauss-Newton steps taken by a backend that cannot stop early (JAX, traced): from a
#: residual of 1e-2 quadratic convergence reaches rounding level in about 4.
FIXED_ITERATIONS = 10
#: A step smaller than this (relative to 1 + |q|) ends the iteration: the next
#: residual is of the order of its square.
STEP_TOLERANCE = 1e-13


class ConstraintFunctions:
    """Residuals and projection of one constrained system, for one state or a batch."""

    def __init__(self, forms: SymbolicForms, signature: Signature):
        constraints = forms.constraints
        if constraints is None:
            raise ValueError("the system has no constraints")
        self._signature = signature
        self._backend = signature.backend
        self._xp = signature.backend.xp
        self._n = forms.n
        self._holonomic = np.flatnonzero(constraints.holonomic)  # an index array (JAX too)
        arguments = (forms.time, *forms.coordinates, *forms.velocities, *forms.parameters)
        self._residual = Kernel(self._backend, arguments, lambda: [constraints.residual])
        self._velocity_residual = Kernel(
            self._backend, arguments, lambda: [list(constraints.velocity)]
        )
        positions = [constraints.position[j] for j in self._holonomic]
        self._projection = Kernel(
            self._backend,
            arguments,
            lambda: [forms.mass_matrix, constraints.matrix, positions, list(constraints.velocity)],
        )

    def residual(self, t: Any, y: Any, params: Any) -> Array:
        """c(q, t) (holonomic) or A q' + a0 (nonholonomic), one row per constraint."""
        return self._evaluate(self._residual, t, y, params)

    def velocity_residual(self, t: Any, y: Any, params: Any) -> Array:
        """A q' + a0 of every constraint (for a holonomic one, dc/dt along the motion)."""
        return self._evaluate(self._velocity_residual, t, y, params)

    def _evaluate(self, kernel: Kernel, t: Any, y: Any, params: Any) -> Array:
        y, params = self._signature.state(y), self._signature.parameters(params)
        batch, (value,) = kernel(t, (y,), params)
        return to_trailing(value, batch, self._xp)

    def project(self, t: Any, y: Any, params: Any) -> Array:
        """The state moved onto the constraint manifold (positions, then velocities)."""
        xp = self._xp
        y, params = self._signature.state(y), self._signature.parameters(params)
        q, v = self._signature.split(y)
        if self._holonomic.size:
            q = self._project_positions(t, q, v, params)
        v = self._project_velocities(t, q, v, params)
        batch = xp.broadcast_shapes(q.shape[1:], v.shape[1:])
        return xp.concatenate([with_batch(q, batch, xp), with_batch(v, batch, xp)], axis=0)

    def _correction(self, mass: Array, matrix: Array, residual: Array) -> Array:
        """-M^-1 C^T (C M^-1 C^T)^-1 r, batch-first: the M-weighted minimum-norm step."""
        response = self._backend.solve_matrix(mass, self._backend.transpose(matrix))
        schur = matrix @ response
        return -(response @ self._backend.solve(schur, residual)[..., None])[..., 0]

    def _project_positions(self, t: Any, q: Array, v: Array, params: Array) -> Array:
        xp = self._xp
        q = with_batch(q, batch_shape(t, (q, v), params), xp)  # the shape the loop keeps

        def step(q: Array) -> tuple[Array, Array]:
            batch, (mass, matrix, residual, _) = self._projection(t, (q, v), params)
            correction = self._correction(mass, matrix[..., self._holonomic, :], residual)
            q = q + to_trailing(correction, batch, xp)
            return q, xp.max(xp.abs(correction)) / (1 + xp.max(xp.abs(q)))

        iterations = MAX_ITERATIONS if self._backend.eager else FIXED_ITERATIONS
        return self._backend.iterate(step, q, iterations, STEP_TOLERANCE)

    def _project_velocities(self, t: Any, q: Array, v: Array, params: Array) -> Array:
        batch, (mass, matrix, _, residual) = self._projection(t, (q, v), params)
        step = to_trailing(self._correction(mass, matrix, residual), batch, self._xp)
        return with_batch(v, batch, self._xp) + step

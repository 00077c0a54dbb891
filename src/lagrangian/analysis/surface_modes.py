"""Small oscillations about a rest point on a constraint surface, in the coordinates q.

With N a basis of the null space of A(q0) = dc/dq (the tangent directions), q = q0 + N s
and N^T M0 N s'' + N^T C0 N s' + N^T K N s = 0 with K = -dG/dq - sum_j lambda_j
d^2 c_j/dq^2 (see :mod:`.constrained`); the modes of s are those of the existing
normal-mode analysis, their shapes mapped back to q (N s, first non-zero entry 1).  At a
numerical point every matrix is numbers (the parameters at their values) and N comes from
the SVD of A.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np
import sympy

from ..algebra import tidy
from ..derive import EquationsOfMotion
from .conditions import StabilityVerdict, stability_verdict
from .linear import LinearizedSystem, NormalModes

#: Singular values of A below this (relative to the largest) count as zero.
NULL_TOLERANCE = 1e-8
#: Entries of a numerical K below this (relative to the largest of its parts) count as zero.
CANCELLED = 1e-12


class SurfaceModes:
    """M, C and K = -dG/dq - lambda . d^2c/dq^2 of ``eom``, projected at each point asked."""

    def __init__(self, eom: EquationsOfMotion):
        self.eom = eom
        system = eom.system
        self.q = [c.q for c in system.coordinates]
        self.at_rest = {c.q_dot: sympy.Integer(0) for c in system.coordinates}
        self.gradients = eom.constraints.matrix.xreplace(self.at_rest)
        self.force_jacobian = eom.forcing.jacobian(self.q)
        self.hessians = [sympy.hessian(c, self.q) for c in system.constraints]
        self.damping = -eom.forcing.jacobian([c.q_dot for c in system.coordinates])

    def at(
        self, point: Mapping[str, sympy.Expr], multipliers: list, *, numeric: bool = False
    ) -> tuple[NormalModes, StabilityVerdict]:
        """The modes about ``point`` held by ``multipliers`` (numbers throughout where
        ``numeric``) and the stability verdict."""
        system = self.eom.system
        here = {c.q: point[c.name] for c in system.coordinates} | self.at_rest
        if numeric:
            values = system.parameter_values
            here |= {p.symbol: sympy.Float(values[p.name]) for p in system.parameters}
        curvature = sympy.zeros(len(self.q), len(self.q))
        for lam, hessian in zip(multipliers, self.hessians, strict=True):
            curvature += lam * hessian
        stiffness = -self.force_jacobian - curvature
        if numeric:  # the force's and the curvature's parts cancel to rounding: zero them
            parts = (self.force_jacobian.xreplace(here), curvature.xreplace(here))
            stiffness = _cancelled(stiffness.xreplace(here), parts)
        gradient = self.gradients.xreplace(here)
        if numeric:
            basis = _numeric_null_space(np.array(gradient.evalf(), dtype=float))
        else:
            tangent = gradient.nullspace()
            basis = sympy.Matrix.hstack(*tangent) if tangent else sympy.zeros(len(self.q), 0)

        def reduced(matrix: sympy.Matrix) -> sympy.ImmutableMatrix:
            product = basis.T * matrix.xreplace(here) * basis
            return sympy.ImmutableMatrix(product.applyfunc(lambda e: tidy(e, trig=True)))

        linear = LinearizedSystem(
            system,
            point,
            reduced(self.eom.mass_matrix),
            reduced(self.damping),
            reduced(stiffness),
            dict(system.parameter_values),
        )
        if basis.cols:
            modes = _in_coordinates(linear.normal_modes(), basis)
        else:
            modes = NormalModes.undetermined("no free direction")
        return modes, stability_verdict(modes, damped=not linear.dissipative.is_zero_matrix)


def _cancelled(stiffness: sympy.Matrix, parts: tuple[sympy.Matrix, ...]) -> sympy.Matrix:
    """K (numbers) with entries that are rounding beside its parts (dG/dq, lambda . d^2c/dq^2)
    set to 0: where the constraint's curvature balances the force's exactly (a bead held on
    a circle by a spring from its centre), 3 - 3 left -1.3e-15, an omega^2 < 0 that said
    'unstable'."""
    scale = max((abs(float(x)) for part in parts for x in part), default=0.0)
    return stiffness.applyfunc(
        lambda x: sympy.Integer(0) if abs(float(x)) <= CANCELLED * scale else x
    )


def _numeric_null_space(gradient: np.ndarray) -> sympy.Matrix:
    """An orthonormal basis of the null space of ``gradient`` (by its SVD), as Floats."""
    n = gradient.shape[1]
    _, singular, vh = np.linalg.svd(gradient)
    largest = singular.max(initial=0.0)
    rank = int(np.sum(singular > NULL_TOLERANCE * largest)) if largest > 0 else 0
    null = vh[rank:].T
    return sympy.Matrix(n, null.shape[1], [sympy.Float(x) for x in null.ravel()])


def _in_coordinates(modes: NormalModes, basis: sympy.Matrix) -> NormalModes:
    """``modes`` with shapes N s in the coordinates q (first non-zero entry 1)."""
    shapes = []
    for shape in modes.shapes:
        vector = [tidy(x, trig=True) for x in basis * sympy.Matrix(shape)]
        vector = [sympy.Integer(0) if _negligible(x, vector) else x for x in vector]
        lead = next((x for x in vector if x != 0), None)
        if lead is None:
            return dataclasses.replace(modes, shapes=())
        shapes.append(sympy.ImmutableMatrix([tidy(x / lead, trig=True) for x in vector]))
    return dataclasses.replace(modes, shapes=tuple(shapes))


def _negligible(x: sympy.Expr, vector: list) -> bool:
    """Zero, or a float zero up to rounding beside the vector's largest number (the SVD's
    basis gives 1e-17 where the exact entry is 0)."""
    if x == 0:
        return True
    if not x.is_Number:
        return False
    largest = max(abs(float(y)) for y in vector if y.is_Number)
    return abs(float(x)) <= 1e-10 * largest

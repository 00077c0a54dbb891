"""The forward sensitivity equations of M(q, t) q'' = f(q, q', t; p), symbolically.

Along a motion y = [q, q'] of y' = F(t, y, p), the sensitivities S = dy/d(p, y0) obey

    S' = J S + [dF/dp | 0],   S(0) = [0 | I],

with J = dF/dy the Jacobian of the variational equations (those of
:mod:`lagrangian.integrate.lyapunov`) and one column per parameter (zero at the start)
or initial value (a unit vector).  F = [q', a] with a = q'' solving M a = f, so, as for
the Jacobian (:mod:`lagrangian.numeric.dynamics`), differentiating the residual
R = f - M a at fixed a gives

    da/dz = M^-1 dR/dz  for z in (q, q', p),

and nothing is inverted symbolically.  This module makes the one block both need,
dR/d(q, q', p_wrt), over (t, q, q', a, p); :mod:`lagrangian.numeric.sensitivity`
evaluates it and solves with M.  (Constrained systems are refused: their flow lives on
the constraint manifold, and the stabilised equations add directions of their own.)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy

from ..errors import ModelError
from .forms import SymbolicForms


@dataclass(frozen=True)
class SensitivityForms:
    """dR/d(q, q', p_wrt) of R = f - M a: an n x (2n + k) matrix over (t, q, q', a, p).

    ``wrt`` are the k parameters differentiated by, in the order of the columns after
    the first 2n; ``arguments`` every symbol of the block in call order (t first, the
    parameters last, as :class:`~lagrangian.numeric.kernels.Kernel` takes them).
    """

    forms: SymbolicForms
    wrt: tuple[str, ...]
    residual_jacobian: sympy.ImmutableMatrix

    @property
    def arguments(self) -> tuple[sympy.Symbol, ...]:
        forms = self.forms
        return (
            forms.time,
            *forms.coordinates,
            *forms.velocities,
            *forms.accelerations,
            *forms.parameters,
        )


def sensitivity_forms(forms: SymbolicForms, wrt: Sequence[str]) -> SensitivityForms:
    """The :class:`SensitivityForms` of ``forms`` for the parameters named in ``wrt``
    (each one of the model's parameters; an unknown name is an error listing them)."""
    if forms.constraints is not None:
        raise ModelError("sensitivities of constrained systems are not supported")
    by_name = {p.name: p for p in forms.parameters}
    unknown = [name for name in wrt if name not in by_name]
    if unknown:
        known = ", ".join(by_name) or "none"
        raise ModelError(f"'{unknown[0]}' is not a parameter of the model (parameters: {known})")
    accelerations = sympy.Matrix(forms.accelerations)
    residual = sympy.Matrix(forms.forcing) - sympy.Matrix(forms.mass_matrix) * accelerations
    variables = [*forms.coordinates, *forms.velocities, *(by_name[name] for name in wrt)]
    return SensitivityForms(forms, tuple(wrt), sympy.ImmutableMatrix(residual.jacobian(variables)))

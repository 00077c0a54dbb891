r"""The expressions a compiled ensemble loop evaluates, per fixed-step scheme.

The backends that generate a whole loop (CUDA C in
:mod:`lagrangian.ensemble.cuda_source`, numba in :mod:`lagrangian.ensemble.numba_backend`)
and the compiled midpoint step of one state (:mod:`lagrangian.integrate.midpoint_step`)
print the same entries, built here once from the symbolic forms
(:mod:`lagrangian.codegen.forms`).  Each scheme needs a few
functions of (t, y = [q, q'], p), each filling named output arrays:

- ``rk4``: ``mass_force`` (M, f of M q'' = f);
- ``rk4-tangent`` (rk4 of the state with one displacement, the ensemble's ``lyapunov``
  observable): ``mass_force`` and ``tangent``, the n x 2n matrix
  D = d(f - M a)/d[q, q'] at given accelerations a (the scalars :func:`accelerations`,
  D row by row), so that the displacement w = [w_q, w_q'] moves by
  w_q'' = M^-1 D w, the variational equations of :class:`~lagrangian.integrate.lyapunov.
  TangentFlow` (da/dy = M^-1 d(f - M a)/dy, a held at q'' = M^-1 f);
- ``stormer-verlet``: ``mass`` (M) and ``gradient`` (L_q);
- ``midpoint``: ``momenta`` (L_q'), ``momenta_force`` (L_q' and L_q + Q),
  ``mass`` (M) and ``jacobian``, the Newton Jacobian of the midpoint step

      J = M + (h/2)(P_q - P_q^T) - (h^2/4)(L_qq + Q_q) - (h/2) Q_q',

  which depends on the step h as well (the symbol :data:`STEP`); see
  :mod:`lagrangian.integrate.variational` for the schemes themselves.

Matrices (the arrays named in :data:`MATRICES`) are listed row by row.
"""

from __future__ import annotations

import sympy

from .forms import SymbolicForms

#: The step width in the Jacobian of the midpoint scheme.
STEP = sympy.Symbol("_h")
#: Scalar arguments of a function beyond (t, y, p): the step of the Jacobian.
SCALARS = {"jacobian": (STEP,)}
#: Output arrays that hold an n x n matrix (entries row by row).
MATRICES = ("M", "J")
SCHEMES = ("rk4", "midpoint", "stormer-verlet", "rk4-tangent")


def accelerations(n: int) -> tuple[sympy.Symbol, ...]:
    """The accelerations a_i given to ``tangent`` (scalars ``_a<i>``, passed as ``a<i>``)."""
    return tuple(sympy.Symbol(f"_a{i}") for i in range(n))


def scheme_scalars(n: int) -> dict[str, tuple[sympy.Symbol, ...]]:
    """The scalar arguments beyond (t, y, p) of each function of the schemes."""
    return {**SCALARS, "tangent": accelerations(n)}


#: [(function name, [(output array, entries)])]
Functions = list[tuple[str, list[tuple[str, list[sympy.Expr]]]]]


def scheme_expressions(forms: SymbolicForms, method: str) -> Functions:
    """The functions ``method`` (one of :data:`SCHEMES`) evaluates; see the module."""
    n = forms.n
    q, v = sympy.Matrix(forms.coordinates), sympy.Matrix(forms.velocities)
    mass = [forms.mass_matrix[i, j] for i in range(n) for j in range(n)]
    if method in ("rk4", "rk4-tangent"):
        functions = [("mass_force", [("M", mass), ("f", list(forms.forcing))])]
        if method == "rk4":
            return functions
        given = dict(zip(forms.accelerations, accelerations(n), strict=True))
        residual = sympy.Matrix(forms.forcing) - forms.mass_matrix * sympy.Matrix(
            forms.accelerations
        )
        derivative = residual.jacobian([*q, *v]).xreplace(given)
        entries = [derivative[i, j] for i in range(n) for j in range(2 * n)]
        return [*functions, ("tangent", [("D", entries)])]
    gradient = sympy.Matrix([sympy.diff(forms.lagrangian, coordinate) for coordinate in q])
    if method == "stormer-verlet":
        return [("mass", [("M", mass)]), ("gradient", [("out", list(gradient))])]
    momenta = sympy.Matrix(forms.momenta)
    forces = sympy.Matrix(forms.nonconservative_forces)
    h = STEP
    p_q = momenta.jacobian(q)
    jacobian = (
        sympy.Matrix(forms.mass_matrix)
        + (h / 2) * (p_q - p_q.T)
        - (h * h / 4) * (gradient.jacobian(q) + forces.jacobian(q))
        - (h / 2) * forces.jacobian(v)
    )
    return [
        ("momenta", [("out", list(momenta))]),
        ("momenta_force", [("momenta", list(momenta)), ("force", list(gradient + forces))]),
        ("mass", [("M", mass)]),
        ("jacobian", [("J", [jacobian[i, j] for i in range(n) for j in range(n)])]),
    ]

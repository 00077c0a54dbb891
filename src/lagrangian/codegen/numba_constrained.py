"""The generated fillers of a constrained system's compiled loop: three saddle-point systems.

A system with constraints (M q'' = f + A^T lambda, A q'' = beta; see
:mod:`lagrangian.derive.constraints`) needs, in the compiled DOP853 loop, three linear
systems of the same shape, size n + m (m constraints), each filled by one generated
function ``name(t, y, p, K, r)`` (K the (n + m) x (n + m) matrix, r the right-hand side)
and solved by the printed Gaussian elimination for n + m
(:func:`lagrangian.codegen.numba.linear_module`, partial pivoting: the zero block needs it):

``augmented``, the dynamics (as :mod:`lagrangian.numeric.dynamics` solves them)::

    [[M, -A^T], [A, 0]] [q''; lambda] = [f; beta - 2 alpha (A q' + a0) - alpha^2 c]

with Baumgarte's rate alpha (0: none), so that the loop integrates the equations SciPy's
loop integrates;

``positions``, one Gauss-Newton step of the projection onto c(q, t) = 0 in the mass
metric (:mod:`lagrangian.numeric.projection`: dq = -M^-1 C^T (C M^-1 C^T)^-1 c)::

    [[M, -C^T], [C, 0]] [dq; mu] = [0; -c]

where C = dc/dq is A's row of a holonomic constraint; a nonholonomic constraint has no
position level, and its row is mu_j = 0 (a 1 on the diagonal), which leaves dq as if the
row were not there;

``velocities``, the exact projection of q' onto A q' + a0 = 0::

    [[M, -A^T], [A, 0]] [dv; mu] = [0; -(A q' + a0)].

The text is written and cached on disk by :func:`lagrangian.codegen.numba.load_functions`
(keyed by the expressions, alpha included), so a second process compiles nothing.
"""

from __future__ import annotations

from types import ModuleType

import sympy

from .forms import SymbolicForms
from .numba import load_functions

#: The fillers, in the order the module defines them.
FILLERS = ("augmented", "positions", "velocities")


def saddle(mass: sympy.MatrixBase, rows: sympy.MatrixBase, free: list[bool]) -> list:
    """The entries, row by row, of [[M, -R^T], [R, D]] with D diagonal: 1 where ``free``
    (a row without a multiplier), else 0."""
    n, m = mass.rows, rows.rows
    matrix = sympy.zeros(n + m, n + m)
    matrix[:n, :n] = mass
    matrix[:n, n:] = -rows.T
    matrix[n:, :n] = rows
    for j in range(m):
        matrix[n + j, n + j] = sympy.Integer(1 if free[j] else 0)
    return list(matrix)


def constrained_fillers(forms: SymbolicForms, baumgarte: float) -> ModuleType:
    """The generated module of :data:`FILLERS` for ``forms`` (with constraints) and
    Baumgarte's rate ``baumgarte`` (see the module docstring)."""
    constraints = forms.constraints
    if constraints is None:
        raise ValueError("the system has no constraints")
    n, m = forms.n, constraints.count
    mass, matrix = sympy.Matrix(forms.mass_matrix), sympy.Matrix(constraints.matrix)
    holonomic = list(constraints.holonomic)
    positions = sympy.Matrix(
        [[matrix[j, k] if holonomic[j] else 0 for k in range(n)] for j in range(m)]
    )
    zeros = [sympy.Integer(0)] * n
    bias = list(constraints.stabilised_bias(baumgarte))
    residual = [-constraints.position[j] if holonomic[j] else sympy.Integer(0) for j in range(m)]
    velocity = [-entry for entry in constraints.velocity]
    functions = [
        ("augmented", [("K", saddle(mass, matrix, [False] * m)), ("r", [*forms.forcing, *bias])]),
        ("positions", [("K", saddle(mass, positions, [not h for h in holonomic])),
                       ("r", [*zeros, *residual])]),
        ("velocities", [("K", saddle(mass, matrix, [False] * m)), ("r", [*zeros, *velocity])]),
    ]  # fmt: skip
    return load_functions(forms, "constrained", functions, matrices=("K",))

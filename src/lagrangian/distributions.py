"""Dropping the distributions that derivatives of |u| and sign(u) bring in.

d/du |u| = sign(u) and d/du sign(u) = 2 delta(u): a spring with a rest length
(V = k (|x - a| - L)^2 / 2) or a user's Abs gives Jacobians with DiracDelta
terms.  They vanish except where u = 0 exactly, a set of measure zero where
the force is not differentiable anyway, so numerical functions drop them
(NumPy has no delta function; lambdify would fail on it).
"""

from __future__ import annotations

import sympy


def without_distributions(expr: sympy.Basic) -> sympy.Basic:
    """``expr`` with every DiracDelta(...) replaced by 0 (matrices entry by entry)."""
    if isinstance(expr, sympy.MatrixBase):
        return expr.applyfunc(without_distributions)
    if not expr.has(sympy.DiracDelta):
        return expr
    return expr.replace(lambda e: isinstance(e, sympy.DiracDelta), lambda e: sympy.Integer(0))

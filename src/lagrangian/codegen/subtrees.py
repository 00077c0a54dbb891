"""The largest subtrees of an expression that a set of symbols alone fixes, replaced.

Two generated forms take such subtrees out of the expressions a step evaluates: heyoka's
ODE (:mod:`.heyoka`) makes each product or sum of parameters one more runtime
parameter, and the tabulated rk4 (:mod:`.time_terms`) reads the terms over t and the
shared parameters from a table.  Both walk the tree the same way (:func:`hoisted`); they
differ in which subtrees count as fixed and in which of those get a name.
"""

from __future__ import annotations

from collections.abc import Callable

import sympy


def hoisted(
    expression: sympy.Expr,
    fixed: Callable[[sympy.Basic], bool],
    entry: Callable[[sympy.Expr], sympy.Expr | None],
) -> sympy.Expr:
    """``expression`` with each largest subtree that ``fixed`` accepts replaced by
    ``entry`` of it, and in a sum or product the terms or factors it accepts grouped
    first, (fixed part) + (the rest), the group replaced by ``entry`` of it unless it is
    a single atom.  ``entry`` returns None for a subtree that stays as it is (its
    branches are walked then)."""

    def walk(part: sympy.Expr) -> sympy.Expr:
        if part.is_Atom:
            return part
        if fixed(part):
            named = entry(part)
            if named is not None:
                return named
        if part.is_Add or part.is_Mul:
            inside = [arg for arg in part.args if fixed(arg)]
            rest = [walk(arg) for arg in part.args if not fixed(arg)]
            if len(inside) > 1 or (inside and not inside[0].is_Atom):
                named = entry(part.func(*inside))
                if named is not None:
                    return part.func(named, *rest)
            return part.func(*inside, *rest)
        return part.func(*(walk(arg) for arg in part.args))

    return walk(expression)

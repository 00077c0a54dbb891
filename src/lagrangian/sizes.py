"""Size budgets for the symbolic stages: how large an expression is, asked cheaply.

Sizes are measured with :func:`exceeds`, which stops counting at the limit, so
asking whether a million-node expression is "too large" costs as much as a small
one (SymPy's ``count_ops`` walks the whole tree, shared parts again and again).
SymEngine's expand runs in C++, where no deadline of :mod:`lagrangian.budget`
reaches: :func:`expanded_terms` counts the terms an expansion would make, before it
is made.
"""

from __future__ import annotations

import math
from fractions import Fraction

import sympy


def exceeds(expr: sympy.Basic, limit: int) -> bool:
    """Whether the expression tree of ``expr`` has more than ``limit`` nodes.

    Stops at the limit, so the answer costs O(limit) however large ``expr`` is.
    """
    nodes = enumerate(sympy.preorder_traversal(expr), start=1)
    return any(count > limit for count, _ in nodes)


def ops_exceed(expr: sympy.Basic, max_ops: int) -> bool:
    """``count_ops(expr) > max_ops``, answered without walking a huge tree.

    A tree has at most about three nodes per operation (x/2 is Mul(1/2, x): one
    operation, three nodes), so one with more than 4 max_ops + 4 nodes is over;
    otherwise ``count_ops`` decides, on a tree small enough to walk.
    """
    if exceeds(expr, 4 * max_ops + 4):
        return True
    return sympy.count_ops(expr) > max_ops


#: Most terms that the expansions of one derivation may make together.  SymEngine's
#: expand runs in C++, where no deadline reaches, at about 1 KB and 10 microseconds a
#: term: (q0' + ... + q19')^20 would make C(39, 20) = 6.9e10 of them (hours, and memory
#: without end).  The 100-link chain makes fewer than 100,000.
MAX_EXPANDED_TERMS = 2_000_000


def expanded_terms(
    expr, limit: int = MAX_EXPANDED_TERMS, *, powers: bool = True, kinds: set | None = None
) -> int:
    """An upper bound of how many terms the full expansion of ``expr`` makes, counting
    every sum expanded on the way (a power of a sum inside a function, a denominator);
    any number above ``limit`` once it is clearly over.  SymPy or SymEngine alike.
    Without ``powers``, for an expansion of products alone: (a + b)^k stays one term.

    A sum of terms adds their counts, a product multiplies them, and a power of a sum
    of n terms to the k has C(n + k - 1, k) (the multinomial's); shared subtrees are
    counted once, so the answer costs a walk of the distinct nodes, not the expansion.
    ``kinds``, where given, gains the type of every node walked (all of them unless the
    count is over ``limit``), so that a caller asking which functions occur walks once.
    """
    over = limit + 1
    counts: dict = {}  # node -> terms of its own expansion
    shapes: dict = {}  # node's type -> "add", "mul", "pow" or "" (asked once per type)
    worst = [0]  # the largest expansion made on the way, of any node

    def count(node, depth: int) -> int:  # a call per distinct node: a third faster
        args = node.args  # each read once: SymEngine makes them anew
        shape = shapes.get(type(node))
        if shape is None:
            shape = shapes[type(node)] = _shape(node)
        if not args:  # a symbol, a number
            terms = 1
        else:
            if depth > _RECURSION_DEPTH:
                raise _TooDeep
            inner = []
            for arg in args:
                found = counts.get(arg)
                inner.append(count(arg, depth + 1) if found is None else found)
            if shape == "add":
                terms = min(sum(inner), over)
            elif shape == "mul":  # every count is at least 1: the product only grows
                terms = min(math.prod(inner), over)
            elif powers and shape == "pow" and args[1].is_Rational:  # SymPy expands (a + b)^(5/2)
                exponent = Fraction(str(args[1]))
                expanded = _multinomial_terms(inner[0], abs(math.trunc(exponent)), over)
                if expanded > worst[0]:  # a denominator is expanded, but is one term
                    worst[0] = expanded
                terms = expanded if exponent > 0 else 1
            else:  # a function: one term (its arguments counted in worst)
                terms = 1
        counts[node] = terms
        if terms > worst[0]:
            worst[0] = terms
        if worst[0] > limit:
            raise _Over
        return terms

    try:
        count(expr, 0)
    except _Over:
        worst[0] = over
    except (_TooDeep, RecursionError):  # too deep a tree, or called deep in the stack:
        return _expanded_terms_walk(expr, limit, powers, kinds)  # walked by its own stack
    if kinds is not None:
        kinds.update(shapes)
    return worst[0]


class _Over(Exception):
    """The count passed its limit: the walk stops."""


class _TooDeep(Exception):
    """A tree nested deeper than ``_RECURSION_DEPTH``."""


#: Nodes nested deeper than this are counted by ``_expanded_terms_walk`` (no recursion).
_RECURSION_DEPTH = 200


def _expanded_terms_walk(expr, limit: int, powers: bool, kinds: set | None) -> int:
    """``expanded_terms`` by a walk with its own stack, for trees of any depth."""
    over = limit + 1
    counts: dict = {}  # node -> terms of its own expansion
    worst = 0  # the largest expansion made on the way, of any node
    shapes: dict = {}  # node's type -> "add", "mul", "pow" or "" (asked once per type)
    pending: list = [(expr, None)]  # (node, its args once its args are pending)
    while pending:
        node, args = pending.pop()
        if args is None:
            if node in counts:
                continue
            args = node.args  # each read once: SymEngine makes them anew
            if args:
                missing = [(arg, None) for arg in args if arg not in counts]
                if missing:  # the args first, then the node again
                    pending.append((node, args))
                    pending += missing
                    continue
        shape = shapes.get(type(node))
        if shape is None:
            shape = shapes[type(node)] = _shape(node)
        if not args:  # a symbol, a number
            terms = 1
        elif shape == "add":
            terms = min(sum([counts[arg] for arg in args]), over)
        elif shape == "mul":
            terms = 1
            for arg in args:
                terms = min(terms * counts[arg], over)
        elif powers and shape == "pow" and args[1].is_Rational:  # SymPy expands (a + b)^(5/2)
            exponent = Fraction(str(args[1]))
            expanded = _multinomial_terms(counts[args[0]], abs(math.trunc(exponent)), over)
            worst = max(worst, expanded)  # a denominator is expanded, but is one term
            terms = expanded if exponent > 0 else 1
        else:  # a function: one term (its arguments counted in worst)
            terms = 1
        counts[node] = terms
        if terms > worst:
            worst = terms
        if worst > limit:
            if kinds is not None:
                kinds.update(shapes)
            return over
    if kinds is not None:
        kinds.update(shapes)
    return worst


def _shape(node) -> str:
    """How ``expanded_terms`` counts a node of this type (SymPy's and SymEngine's alike)."""
    return "add" if node.is_Add else "mul" if node.is_Mul else "pow" if node.is_Pow else ""


def _multinomial_terms(n: int, k: int, over: int) -> int:
    """C(n + k - 1, k), the terms of (a sum of n terms)^k, or ``over`` once it passes."""
    if n <= 1 or k <= 1:
        return n if k == 1 else 1
    count = 1
    for j in range(1, min(k, n - 1) + 1):  # C(N, j) from C(N, j - 1), N = n + k - 1
        count = count * (n + k - j) // j
        if count >= over:
            return over
    return count

"""``Terms``: the terms of top-level sums a model's texts share, each built once.

The builder (:mod:`.builder`, ``_Builder.top_sum``) keeps them here and charges again,
at each use, what a term's build charged against the text's limits.
"""

from __future__ import annotations

import bisect
import functools
from collections.abc import Callable

import sympy
from sympy.core.parameters import global_parameters

from lagrangian.algebra import applied_unevaluated

_CANONICAL = functools.cmp_to_key(sympy.Basic.compare)  # the key of SymPy's Add's sort


class Terms:
    """Terms of top-level sums already built, by their text: {(text, latex): (value, charges)}.

    A chain's positions repeat the same n terms n times.  A term is the same text between
    two top-level ``+``/``-``, so it makes the same tokens, tree and value; what its build
    charged against the text's limits (arguments' nodes, roots) is recorded with positions
    relative to the term and charged again at each later use, in the same order, so a
    text is refused exactly where building it afresh would refuse it.
    """

    def __init__(self, latex: bool = False):
        self.latex = latex  # of the text now parsed: LaTeX tokenizes the same slice otherwise
        self.built: dict = {}
        self.negated: dict = {}  # {(text, latex): -value} of the terms written after a minus
        self.tokens: dict = {}  # {text: its token count} of the terms split without a parse
        self.parts: dict = {}  # {what: {id(term): (term, what(term))}} (see union)
        self.number_sizes: dict = {}  # {term: (numeric size, denominators)} (builder's)
        self.plain_parts: dict = {}  # {id(term): (term, its part)} (sorted_sum's)
        self._ordered: list = []  # the distinct terms met, in SymPy's canonical order
        self._rank: dict = {}  # term -> its place in _ordered

    def union(self, expr: sympy.Basic, what: Callable[[sympy.Basic], set]) -> set:
        """``what(expr)`` for a ``what`` that is the union of its values on a sum's terms
        (``atoms``, ``free_symbols``), each distinct term looked at once for these texts:
        a chain's positions are sums of the same terms, met O(n^2) times."""
        if type(expr) is not sympy.Add:
            return what(expr)
        # by identity (the terms are built once): a SymPy hash is a Python call; the entry
        # keeps its term alive, so no other term can have its id
        found = self.parts.setdefault(what, {})
        union: set = set()
        for term in expr.args:
            entry = found.get(id(term))
            if entry is None:
                entry = found[id(term)] = (term, what(term))
            union |= entry[1]
        return union

    def in_canonical_order(self, values: list) -> list:
        """``values`` sorted as SymPy's ``Add`` sorts its terms (``Basic.compare``).

        ``Add`` sorts the terms of each sum it makes, about n log n comparisons of
        expressions; given them in order, its sort makes n - 1.  Each distinct term is
        placed once among those met before (log n comparisons), so a model's sums of
        the same terms are sorted by numbers.  Only the work changes: ``Add`` still
        sorts, so the sum is the same whatever the order given.
        """
        rank = self._rank
        new = {value for value in values if value not in rank}
        if new:
            ordered = self._ordered
            for value in new:
                bisect.insort(ordered, value, key=_CANONICAL)
            self._rank = rank = {value: place for place, value in enumerate(ordered)}
        return sorted(values, key=rank.__getitem__)


#: What a term of a sum may be for :func:`sorted_sum` (a number, a sum, an infinity, an
#: order term, a matrix or tensor expression, is left to ``Add``'s own rules).
_PLAIN_TERMS = (sympy.Symbol, sympy.Mul, sympy.Pow, sympy.Function)


def sorted_sum(ordered: list, known: dict | None = None) -> sympy.Expr | None:
    """``sympy.Add(*ordered)`` for terms already in ``Add``'s order that it would only
    keep, made without ``Add``'s evaluation; None where that would do more.

    ``Add.flatten`` combines numbers, like terms (x and 2 x), nested sums and the special
    values, then sorts; with none of these, its result is the terms in their order, the
    zeros dropped.  The first evaluated sum of a process also imports sympy.tensor and
    sympy.combinatorics (0.03 s), which a model of plain terms then never needs.
    ``known`` keeps each term's part without its coefficient (False: not a plain term), by
    identity, for the next sums: a chain's sums share their terms, and ``as_coeff_Mul`` of
    -l cos(q) makes a new product (and its hash) each time.
    """
    terms = [term for term in ordered if term is not sympy.S.Zero]
    if len(terms) < 2 or not global_parameters.evaluate:
        return None
    seen = set()
    for term in terms:
        entry = None if known is None else known.get(id(term))  # by identity, as union
        if entry is None:
            entry = (term, _plain_part(term))
            if known is not None:
                known[id(term)] = entry
        part = entry[1]
        if part is False or part in seen:
            return None  # like terms: Add adds their coefficients
        seen.add(part)
    return sympy.Add._exec_constructor_postprocessors(
        sympy.Add._from_args(terms, is_commutative=True)
    )


def _plain_part(term: sympy.Expr) -> sympy.Expr | bool:
    """``term`` without its numeric coefficient, or False where ``term`` is not plain."""
    if not isinstance(term, _PLAIN_TERMS) or term.is_commutative is not True:
        return False
    if term.is_Pow and term.base.is_Number:
        return False  # 2**(-1/2): Add evaluates it again
    return term.as_coeff_Mul()[1] if term.is_Mul else term


#: The functions :func:`plain_call` makes of a real symbol: their ``eval`` leaves it as is.
_ANGLE_FUNCTIONS = (sympy.sin, sympy.cos)
#: What a factor may be for :func:`plain_product`: each is its own base to the power 1, so
#: ``Mul`` has no powers to merge (``exp``, whose base is E, is not one of them).
_PLAIN_FACTORS = (sympy.Symbol, *_ANGLE_FUNCTIONS)


def plain_call(function, argument: sympy.Expr) -> sympy.Expr | None:
    """``function(argument)`` for sin or cos of a real symbol, made without SymPy's
    ``eval``; None for anything else.

    ``sin(x)`` of a real symbol that is not known to be zero is left as it is by
    ``sin.eval`` (no number, no minus sign to pull out, no multiple of pi or of I), but
    the search for them costs about 0.1 ms per call, once for each term of a model's
    positions.  The value is the one ``function(argument)`` makes: the same type, args,
    equality and hash.
    """
    if function not in _ANGLE_FUNCTIONS or type(argument) is not sympy.Symbol:
        return None
    if argument.is_real is not True or argument.is_zero:
        return None
    if not global_parameters.evaluate:
        return None
    return applied_unevaluated(function, argument)


def plain_product(factors) -> sympy.Expr | None:
    """``sympy.Mul(*factors)`` for distinct commutative symbols and values of sin and cos,
    made as ``Mul`` makes it (its args sorted by ``Basic.compare``) without its
    evaluation; None for anything else (numbers, powers, sums, like factors).
    """
    if len(factors) < 2 or not global_parameters.evaluate:
        return None
    for factor in factors:
        if type(factor) not in _PLAIN_FACTORS or factor.is_commutative is not True:
            return None
    if len(set(factors)) != len(factors):
        return None  # x*x: Mul makes x**2
    return sympy.Mul._exec_constructor_postprocessors(
        sympy.Mul._from_args(sorted(factors, key=_CANONICAL), is_commutative=True)
    )

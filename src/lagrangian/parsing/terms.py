"""``Terms``: the terms of top-level sums a model's texts share, each built once.

The builder (:mod:`.builder`, ``_Builder.top_sum``) keeps them here and charges again,
at each use, what a term's build charged against the text's limits.
"""

from __future__ import annotations

from collections.abc import Callable

import sympy


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
        self.parts: dict = {}  # {what: {term: what(term)}} (see union)

    def union(self, expr: sympy.Basic, what: Callable[[sympy.Basic], set]) -> set:
        """``what(expr)`` for a ``what`` that is the union of its values on a sum's terms
        (``atoms``, ``free_symbols``), each distinct term looked at once for these texts:
        a chain's positions are sums of the same terms, met O(n^2) times."""
        if type(expr) is not sympy.Add:
            return what(expr)
        found = self.parts.setdefault(what, {})
        union: set = set()
        for term in expr.args:
            part = found.get(term)
            if part is None:
                part = found[term] = what(term)
            union |= part
        return union

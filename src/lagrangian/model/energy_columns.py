"""The products of two Jacobian columns for T's large route (:mod:`.energy_large`), each
made by multiplying the columns' monomials, and a product that pairs into one cosine,
c cos a cos b + c sin a sin b = c cos(a - b), made without its sum (a chain's every one).
"""

from __future__ import annotations

from ..algebra import args_of, combine_angles, combine_expanded_angles
from ..sizes import MAX_EXPANDED_TERMS, expanded_terms


class Monomials:
    """A Jacobian column with each component expanded once into its monomials, so that
    the product of two columns is expanded by multiplying monomials.

    ``combine_angles`` of u . v expands the product anew and first counts, by a walk of
    it, the terms that expansion could make; a chain's T takes 5050 such products.  Where
    every monomial is a product of symbols, numbers, functions and powers of them (no sum
    inside a power), two monomials multiply into a monomial, so the expansion of u . v
    is the sum of the products of the components' monomials, and its count is bounded by
    the columns' own counts: :meth:`dot` then makes that sum directly (the same expression
    as the expansion); else, or past the bound, it is ``combine_angles`` of the product.
    """

    def __init__(self, column):
        import symengine as se

        self.column = column
        # bounds of the terms each component's expansion makes, and of those made inside it
        self.counts = [expanded_terms(x) for x in column]
        self.terms = None
        self.shapes = None  # each component's monomials split as _shape does, where all split
        if max(self.counts) <= MAX_EXPANDED_TERMS:
            terms = [args_of(se.expand(x), se.Add) for x in column]
            if all(_is_monomial(term) for component in terms for term in component):
                self.terms = terms
                shapes = [[_shape(x) for x in component if x != 0] for component in terms]
                if all(shape is not None for component in shapes for shape in component):
                    self.shapes = shapes

    def dot(self, other: Monomials):
        import symengine as se

        u, v = self.column, other.column
        if self.terms is not None and other.terms is not None:
            # what expanded_terms would count in u . v: the products' terms, or more inside
            size = sum(a * b for a, b in zip(self.counts, other.counts, strict=True))
            if max(size, *self.counts, *other.counts) <= MAX_EXPANDED_TERMS:
                paired = _paired(self.shapes, other.shapes)
                if paired is not None:
                    return paired
                products = [
                    x * y
                    for a, b in zip(self.terms, other.terms, strict=True)
                    for x in a
                    for y in b
                ]
                return combine_expanded_angles(se.Add(*products))
        return combine_angles(se.Add(*(x * y for x, y in zip(u, v, strict=True))))


def _shape(monomial) -> tuple | None:
    """(the product of its other factors, ((sin or cos, angle), ...)) of a monomial
    (SymEngine), its sines and cosines listed as :func:`~lagrangian.algebra.
    combine_expanded_angles` counts them (a square twice); None where a power of a sine or
    cosine other than the square is a factor (a product could then merge it with another)."""
    import symengine as se

    rest, trig = [], []
    for factor in monomial.args if type(monomial) is se.Mul else (monomial,):
        kind = type(factor)
        if kind is se.sin or kind is se.cos:
            trig.append((kind, factor.args[0]))
            continue
        if kind is se.Pow:
            base, exponent = factor.args
            if type(base) is se.sin or type(base) is se.cos:
                if exponent != 2:
                    return None
                trig += [(type(base), base.args[0])] * 2
                continue
        rest.append(factor)
    return se.Mul(*rest), tuple(trig)


def _paired(left: list | None, right: list | None):
    """u . v for columns whose monomials' products are two, c cos a cos b and c sin a sin b:
    ``combine_expanded_angles`` makes c cos(a - b) of them.  Made here from the shapes
    (:func:`_shape`) without the products, their sum and its walk (a chain's every product
    of columns; 0.011 of 0.018 ms a product); None where any other case."""
    import symengine as se

    if left is None or right is None:
        return None
    # the monomials' nonzero products; their sines and cosines never merge with the rest
    products = [(x, y) for a, b in zip(left, right, strict=True) for x in a for y in b]
    if len(products) != 2:
        return None
    (x1, y1), (x2, y2) = products  # each (the product of the other factors, trig factors)
    one, two = x1[1] + y1[1], x2[1] + y2[1]
    if len(one) != 2 or len(two) != 2:
        return None
    kinds = {one[0][0], one[1][0]}, {two[0][0], two[1][0]}
    if len(kinds[0]) != 1 or len(kinds[1]) != 1 or kinds[0] == kinds[1]:
        return None  # not one product of two cosines and one of two sines
    angles = frozenset((one[0][1], one[1][1]))
    if angles != frozenset((two[0][1], two[1][1])):
        return None
    # combine_expanded_angles keys the pair by the angles of the first term of the sum,
    # whose order is SymEngine's: taken here only where either order iterates alike
    if tuple(angles) != tuple(frozenset((one[1][1], one[0][1]))):
        return None
    coefficient = x1[0] * y1[0]
    if coefficient != x2[0] * y2[0]:
        return None
    a, b = (*angles, *angles)[:2]
    return coefficient * se.cos(a - b)


def _is_monomial(term) -> bool:
    """Whether ``term`` (SymEngine) is a product of factors none of which holds a sum
    outside a function: its product with another such term is again one."""
    import symengine as se

    for factor in term.args if type(term) is se.Mul else (term,):
        base = factor.args[0] if type(factor) is se.Pow else factor
        if type(base) in (se.Add, se.Mul, se.Pow):
            return False
    return True

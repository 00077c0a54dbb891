"""The unknown dimensions of a model's names, solved as linear equations on their exponents.

A :data:`Form` is what the dimension of an expression is when some names' dimensions
are unknown: ``sum_s c_s D_s + k``, a combination of the unknown dimensions ``D_s``
(``coefficients``) plus a known dimension ``k``.  A product adds forms, a power scales
one; that two terms of a sum share a dimension is the equation ``form_a - form_b = 0``,
one equation per base dimension with the same coefficients.  :class:`Solver` takes the
equations one at a time and eliminates (exact fractions, no pivoting needed): an
equation that contradicts those before it is reported, so that the check can name the
term that broke it.
"""

from __future__ import annotations

from fractions import Fraction

from .dimensions import DIMENSIONLESS, Dimension

#: (coefficients {name: c}, known part): the dimension sum_s c * D_s + known; the
#: coefficients and exponents are ints where whole (faster than Fractions), else Fractions.
Form = tuple[dict[str, int | Fraction], Dimension]


def known(value: Dimension) -> Form:
    return {}, value


def unknown(name: str, offset: Dimension = DIMENSIONLESS) -> Form:
    return {name: 1}, offset


def combine(a: Form, b: Form, sign: int = 1) -> Form:
    """``a + sign * b``: the form of a product (sign 1) or a quotient (sign -1)."""
    coefficients = dict(a[0])
    for name, c in b[0].items():
        total = coefficients.get(name, 0) + sign * c
        if total:
            coefficients[name] = total
        else:
            coefficients.pop(name, None)
    return coefficients, tuple(x + sign * y for x, y in zip(a[1], b[1], strict=True))


def scale(a: Form, factor: Fraction) -> Form:
    """``factor * a``: the form of a power."""
    if factor == 1:
        return a
    if factor == 0:
        return {}, DIMENSIONLESS
    return {n: c * factor for n, c in a[0].items()}, tuple(_tidy(x * factor) for x in a[1])


def _tidy(x):
    return x.numerator if isinstance(x, Fraction) and x.denominator == 1 else x


class Solver:
    """Equations ``form = 0`` taken in order; each unknown eliminated once it is pivoted.

    ``pivots[name] = (coefficients, known)`` says ``D_name = sum c * D_other + known``
    over names not pivoted when it was made (so substitution always ends).
    """

    def __init__(self) -> None:
        self.pivots: dict[str, Form] = {}

    def reduce(self, form: Form) -> Form:
        """``form`` with every pivoted unknown replaced by what it equals."""
        coefficients, constant = dict(form[0]), form[1]
        while True:
            pivoted = [name for name in coefficients if name in self.pivots]
            if not pivoted:
                return coefficients, constant
            for name in pivoted:
                c = coefficients.pop(name)
                coefficients, constant = combine(
                    (coefficients, constant), scale(self.pivots[name], c)
                )

    def add(self, form: Form) -> bool:
        """Take the equation ``form = 0``; False when it contradicts the equations before."""
        coefficients, constant = self.reduce(form)
        if not coefficients:
            return all(x == 0 for x in constant)
        name = min(coefficients)
        c = coefficients.pop(name)
        self.pivots[name] = scale((coefficients, constant), Fraction(-1) / c)
        return True

    def value(self, form: Form) -> Dimension | None:
        """The dimension ``form`` has by the equations so far, or None if not yet fixed."""
        coefficients, constant = self.reduce(form)
        return None if coefficients else tuple(_tidy(x) for x in constant)

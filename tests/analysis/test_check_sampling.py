"""The sampling of ``check`` (analysis/check/sampling.py): an expression is compiled once
however often it is evaluated, and the values are the expression's own."""

from __future__ import annotations

import numpy as np
import sympy

from lagrangian.analysis.check import sampling


def test_an_expression_evaluated_again_is_not_compiled_again(monkeypatch):
    # a symbol no other test uses: no earlier test has compiled this expression
    a = sympy.Symbol("a_evaluated_again")
    expr = a * sympy.sin(a) + 1
    made = []
    real = sympy.lambdify

    def counted(symbols, expression, **options):
        made.append(expression)
        return real(symbols, expression, **options)

    monkeypatch.setattr(sampling.sympy, "lambdify", counted)
    points = sampling.points([a], [])
    first = points.evaluate(expr)
    again = sampling.points([a], []).evaluate(expr)  # a new check's points: the same values
    assert made == [expr]
    (values,) = points.values
    np.testing.assert_array_equal(first, values * np.sin(values) + 1)
    np.testing.assert_array_equal(again, first)
    # an expression equal in value but not in form is its own function
    points.evaluate(a * sympy.sin(a) + sympy.Float(1.0))
    assert len(made) == 2

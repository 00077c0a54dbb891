"""The one walker (lagrangian.codegen.subtrees.hoisted) under the two policies that use it:
heyoka's hoisted parameters and the tabulated rk4's time terms, on expressions whose
replacements are worked out by hand."""

from __future__ import annotations

import sympy

from lagrangian.codegen.heyoka import _hoisted
from lagrangian.codegen.subtrees import hoisted

a, b, m, x, v, t, w = sympy.symbols("a b m x v t w", real=True)


def _numbered(found: dict) -> dict:
    def entry(part: sympy.Expr) -> sympy.Symbol:
        if part not in found:
            found[part] = sympy.Symbol(f"d{len(found)}")
        return found[part]

    return entry


def test_a_product_of_parameters_in_a_term_becomes_one_entry():
    table: dict = {}
    result = _hoisted(a * b * m * sympy.cos(x - v) + m * v, (a, b, m), table)
    assert list(table) == [a * b * m]
    assert result == table[a * b * m] * sympy.cos(x - v) + m * v  # a lone parameter stays itself


def test_numbers_alone_stay_for_heyoka_but_are_tabulated_among_time_terms():
    expression = sympy.sqrt(2) * x + sympy.cos(sympy.sqrt(3))
    table: dict = {}
    assert _hoisted(expression, (a,), table) == expression and table == {}
    found: dict = {}
    fixed = lambda part: isinstance(part, sympy.Expr) and part.free_symbols <= {t}  # noqa: E731
    result = hoisted(expression, fixed, _numbered(found))
    assert list(found) == [sympy.sqrt(2), cos_root := sympy.cos(sympy.sqrt(3))]
    assert result == found[sympy.sqrt(2)] * x + found[cos_root]


def test_the_fixed_factors_of_a_product_are_grouped_into_one_entry():
    found: dict = {}
    fixed = lambda part: isinstance(part, sympy.Expr) and part.free_symbols <= {t, w, a}  # noqa: E731
    drive = a * sympy.cos(w * t) * x * v + sympy.Abs(x) * sympy.sin(w * t) + a * x
    result = hoisted(drive, fixed, _numbered(found))
    assert set(found) == {a * sympy.cos(w * t), sympy.sin(w * t)}  # not a alone
    expected = found[a * sympy.cos(w * t)] * x * v + sympy.Abs(x) * found[sympy.sin(w * t)]
    assert result == expected + a * x

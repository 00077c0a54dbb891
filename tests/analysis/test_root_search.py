"""What the root search says when it needs the parameters' default values (the text of
both errors, which name the parameters without one)."""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis.search import RootSearch
from lagrangian.errors import ModelError

#: A double well whose parameters k and m have no default values.
WELL = lg.System.from_lagrangian("m*x_dot**2/2 - k*(x**2 - 1)**2/2", coordinates=["x"])


def _search() -> RootSearch:
    (x,) = WELL.coordinates
    k = sympy.Symbol("k", real=True)
    return RootSearch(WELL, [2 * k * x.q * (x.q**2 - 1)], [x])


def test_no_numerical_search_without_default_values():
    with pytest.raises(ModelError) as caught:
        _search().numeric()
    assert str(caught.value) == (
        "SymPy cannot solve for the equilibria; give default values for k, m to locate them "
        "numerically"
    )


def test_some_roots_found_and_no_default_values_to_look_for_more():
    with pytest.raises(ModelError) as caught:
        _search().confirms([{"x": sympy.Integer(1)}])  # x = 0 and x = -1 are missing
    assert str(caught.value) == (
        "SymPy found only some of the equilibria; give default values for k, m to locate them "
        "numerically"
    )

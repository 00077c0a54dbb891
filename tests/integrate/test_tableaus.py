"""Butcher tableaus: the invariants every tableau must satisfy, checked as data."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from lagrangian.integrate.explicit_rk import AbstractExplicitRungeKutta
from lagrangian.integrate.tableaus import MIDPOINT, RK4, RK38, ButcherTableau, order_conditions

TABLEAUS = [RK4, RK38, MIDPOINT]


@pytest.mark.parametrize("tableau", TABLEAUS, ids=lambda t: t.name)
def test_weights_sum_to_one_and_rows_sum_to_nodes(tableau):
    assert tableau.b.sum() == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(tableau.a.sum(axis=1), tableau.c, atol=1e-15)


@pytest.mark.parametrize("tableau", TABLEAUS, ids=lambda t: t.name)
def test_explicit_tableaus_are_strictly_lower_triangular(tableau):
    assert tableau.explicit
    assert np.all(np.triu(tableau.a) == 0.0)


@pytest.mark.parametrize("tableau", TABLEAUS, ids=lambda t: t.name)
def test_order_conditions_hold_up_to_the_declared_order(tableau):
    for condition, residual in order_conditions(tableau.a, tableau.b, tableau.c, tableau.order):
        assert abs(residual) < 1e-15, condition


def test_rk4_is_not_of_order_five_by_the_quadrature_condition():
    # b.c^4 = 1/5 would be needed for order 5
    assert abs(RK4.b @ RK4.c**4 - 1 / 5) > 1e-3


def test_coefficients_are_read_only():
    with pytest.raises(ValueError):
        RK4.a[1, 0] = 0.0


def test_weights_that_do_not_sum_to_one_are_rejected():
    with pytest.raises(ValueError, match=r"tableau bad: the weights b sum to 1.5, not 1"):
        ButcherTableau("bad", a=[[0]], b=[1.5], c=[0], order=1)


def test_row_sums_that_are_not_the_nodes_are_rejected():
    with pytest.raises(ValueError, match=r"row sums of A \[0.0, 0.5\] are not c"):
        ButcherTableau("bad", a=[[0, 0], [0.5, 0]], b=[0, 1], c=[0, 1], order=1)


def test_shapes_are_checked():
    with pytest.raises(ValueError, match=r"A must be s x s"):
        ButcherTableau("bad", a=[[0, 0]], b=[0.5, 0.5], c=[0, 1], order=1)


def test_a_declared_order_the_coefficients_do_not_reach_is_rejected():
    heun = {"a": [[0, 0], [1, 0]], "b": [0.5, 0.5], "c": [0, 1]}
    assert ButcherTableau("heun", **heun, order=2).order == 2
    with pytest.raises(ValueError, match=r"order condition b.c\^2 = 1/3 fails"):
        ButcherTableau("heun", **heun, order=3)


def test_an_implicit_tableau_is_valid_but_not_explicit_and_cannot_drive_explicit_rk():
    implicit_midpoint = ButcherTableau("implicit midpoint", a=[[0.5]], b=[1], c=[0.5], order=2)
    assert not implicit_midpoint.explicit
    with pytest.raises(TypeError, match="is not explicit"):

        @dataclass(frozen=True)
        class Broken(AbstractExplicitRungeKutta):
            name: ClassVar[str] = "broken"
            order: ClassVar[int] = 2
            tableau: ClassVar[ButcherTableau] = implicit_midpoint

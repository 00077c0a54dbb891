"""A constrained run's initial state: moved onto the constraints and said so, or refused
where it cannot be moved (issue 37 item 6: x = y = 0 for the Cartesian pendulum raised
LinAlgError; x = 0.5, y = 0 was moved to x = 1 and reported "success" with nothing said)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import LagrangianWarning, ModelError

SINGULAR = (
    r"^the initial state{which} \(x = 0, y = 0, x_dot = 0, y_dot = 0\) cannot be moved onto "
    r"the constraints: it is a singular point of theirs"
)


@pytest.fixture(scope="module")
def pendulum():
    return lg.load("cartesian_pendulum")  # x^2 + y^2 = l^2, l = 1, M = m I


@pytest.mark.parametrize("method", ["dop853", "rk4", "radau"])
def test_a_singular_point_of_the_constraint_is_refused(pendulum, method):
    with pytest.raises(ModelError, match=SINGULAR.format(which="")):
        pendulum.simulate(t_end=0.1, initial={"x": 0.0, "y": 0.0}, method=method)


@pytest.mark.slow
def test_a_state_off_the_circle_is_moved_to_the_nearest_point_and_said(pendulum):
    # M = m I: the nearest point in the kinetic metric is the radial one, (0.3, -0.4) / 0.5;
    # the velocity (1, 0) keeps its part along the tangent (0.8, 0.6): 0.8 (0.8, 0.6)
    with pytest.warns(LagrangianWarning) as caught:
        run = pendulum.simulate(
            t_end=0.1, initial={"x": 0.3, "y": -0.4, "x_dot": 1.0}, method="rk4"
        )
    start = [run[name][0] for name in ("x", "y", "x_dot", "y_dot")]
    np.testing.assert_allclose(start, [0.6, -0.8, 0.64, 0.48], atol=1e-12)
    assert [str(w.message) for w in caught] == [
        "the initial state was moved onto the constraints (values changed by up to 0.48): "
        "x 0.3 -> 0.6, "
        "y -0.4 -> -0.8, x_dot 1 -> 0.64, y_dot 0 -> 0.48; give a state on the constraints "
        "to start from it"
    ]


def test_a_state_on_the_constraint_is_not_moved_and_nothing_is_said(pendulum):
    with warnings.catch_warnings():
        warnings.simplefilter("error", LagrangianWarning)
        run = pendulum.simulate(t_end=0.1, method="rk4")
    np.testing.assert_array_equal(
        [run["x"][0], run["y"][0]], [0.8414709848078965, -0.5403023058681398]
    )


def test_an_ensemble_names_the_member_it_cannot_move(pendulum):
    with pytest.raises(ModelError, match=SINGULAR.format(which=" of motion 1")):
        pendulum.ensemble(initial={"x": [1.0, 0.0], "y": 0.0}, t_end=0.01, dt=0.001)


def test_an_ensemble_says_how_many_members_it_moved(pendulum):
    with pytest.warns(LagrangianWarning) as caught:
        result = pendulum.ensemble(
            initial={"x": [1.0, 0.5, 0.0], "y": [0.0, 0.0, -2.0]}, t_end=0.01, dt=0.001
        )
    assert result.shape == (3,)
    assert [str(w.message) for w in caught] == [
        "the initial states of 2 of 3 motions were moved onto the constraints (values "
        "changed by up to 1; the first, number 1: x = 0.5, y = 0, x_dot = 0, y_dot = 0); "
        "give a state on the constraints to start from it"
    ]

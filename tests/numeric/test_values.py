"""Parameter and initial values the equations cannot take are refused, naming them: a value
that breaks a parameter's assumed sign (the equations were derived with it), or any value
that is not finite; in a single run and in every member of an ensemble."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.ensemble import run_ensemble
from lagrangian.errors import ModelError
from lagrangian.integrate import simulate
from lagrangian.numeric import compile_equations


@pytest.fixture(scope="module")
def oscillator():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 - k*x**2/2 + b*x", coordinates=["x"],
        parameters={"m": 1.0, "k": 1.0, "b": {"value": -1.0, "sign": "real"}},
    )  # fmt: skip
    return compile_equations(system.equations_of_motion())


def positive_message(name: str, value: str) -> str:
    return (
        f"parameter {name} = {value} breaks the model's assumption that {name} is positive "
        f"(the equations were derived with it): give a value > 0, or declare {name} = "
        '{value = ..., sign = "real"} in the model'
    )


@pytest.mark.parametrize("value, shown", [(-1.0, "-1"), (0.0, "0")])
def test_a_value_breaking_the_assumed_sign_is_refused(oscillator, value, shown):
    with pytest.raises(ModelError) as error:
        simulate(oscillator, t_end=1.0, params={"m": value})
    assert str(error.value) == positive_message("m", shown)


@pytest.mark.parametrize("value", [np.inf, -np.inf, np.nan])
def test_a_parameter_that_is_not_finite_is_refused(oscillator, value):
    with pytest.raises(ModelError, match=rf"^parameter m = {value:g} is not a finite number$"):
        simulate(oscillator, t_end=1.0, params={"m": value})


def test_a_real_parameter_takes_any_finite_value(oscillator):
    assert simulate(oscillator, t_end=0.1, params={"b": -3.0}).status == "success"
    with pytest.raises(ModelError, match=r"^parameter b = inf is not a finite number$"):
        simulate(oscillator, t_end=0.1, params={"b": np.inf})


@pytest.mark.parametrize("name", ["x", "x_dot"])
def test_an_initial_value_that_is_not_finite_is_refused(oscillator, name):
    with pytest.raises(ModelError, match=rf"^initial {name} = nan is not a finite number$"):
        simulate(oscillator, t_end=1.0, initial={name: np.nan})


def test_every_member_of_an_ensemble_is_checked(oscillator):
    with pytest.raises(ModelError) as error:
        run_ensemble(oscillator, t_end=1.0, params={"m": np.linspace(-1, 1, 5)})
    assert str(error.value) == positive_message("m", "-1")
    with pytest.raises(ModelError) as error:
        run_ensemble(oscillator, t_end=1.0, params={"m": [1.0, 2.0, 0.0]})
    assert str(error.value) == positive_message("m", "0")
    with pytest.raises(ModelError, match=r"^initial x = inf is not a finite number$"):
        run_ensemble(oscillator, t_end=1.0, initial={"x": [0.0, np.inf]})


def test_system_simulate_refuses_them_too():
    system = lg.load("simple_pendulum")
    with pytest.raises(ModelError, match=r"^parameter l = -1 breaks"):
        system.simulate(t_end=1.0, params={"l": -1.0})

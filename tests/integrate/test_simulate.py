"""`simulate`: the registry, settings and their defaults, outputs, constraints, work."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.errors import ModelError
from lagrangian.integrate import (
    METHODS,
    RK4,
    AbstractIntegrator,
    Dop853,
    Radau,
    Variational,
    method_class,
    simulate,
)

from . import systems


# -- the registry ------------------------------------------------------------------------
def test_the_registry_holds_the_five_methods_by_name():
    assert list(METHODS) == ["dop853", "radau", "rk4", "variational", "taylor"]
    for name, cls in METHODS.items():
        assert cls.name == name
        assert issubclass(cls, AbstractIntegrator)
        assert cls.needs in ("first_order", "lagrangian")


def test_an_unknown_method_lists_the_valid_ones():
    message = "unknown method 'euler' (methods: dop853, radau, rk4, variational, taylor)"
    with pytest.raises(ModelError) as error:
        method_class("euler")
    assert str(error.value) == message
    with pytest.raises(ModelError) as error:
        simulate(systems.oscillator(), t_end=1.0, method="euler")
    assert str(error.value) == message


@pytest.mark.parametrize(
    ("cls", "order", "symplectic", "adaptive"),
    [(Dop853, 8, False, True), (Radau, 5, False, True), (RK4, 4, False, False),
     (Variational, 2, True, False)],
)  # fmt: skip
def test_capabilities_are_class_constants(cls, order, symplectic, adaptive):
    assert (cls.order, cls.symplectic, cls.adaptive) == (order, symplectic, adaptive)


# -- settings: what applies, defaults, echo -----------------------------------------------
def test_default_tolerances_are_documented_and_echoed():
    trajectory = simulate(systems.oscillator(), t_end=1.0)
    attrs = trajectory.dataset.attrs
    assert (attrs["method"], attrs["rtol"], attrs["atol"]) == ("dop853", 1e-10, 1e-12)
    assert "dt" not in attrs
    radau = simulate(systems.oscillator(), t_end=1.0, method="radau").dataset.attrs
    assert (radau["rtol"], radau["atol"]) == (1e-8, 1e-10)
    assert radau["jacobian_evaluations"] >= 1  # the analytic Jacobian is used


def test_default_step_of_fixed_step_methods_is_a_thousandth_of_the_span():
    trajectory = simulate(systems.oscillator(), t_end=2.0, method="rk4")
    attrs = trajectory.dataset.attrs
    assert attrs["dt"] == 2e-3
    assert attrs["steps"] == 1000
    assert attrs["rhs_evaluations"] == 4000
    assert "rtol" not in attrs
    assert trajectory.t.shape == (1001,)  # every step is an output


def test_settings_that_do_not_apply_are_errors():
    compiled = systems.oscillator()
    with pytest.raises(ModelError) as error:
        simulate(compiled, t_end=1.0, method="dop853", dt=0.1)
    assert str(error.value) == (
        "dt does not apply to method 'dop853' (an adaptive method: give rtol/atol)"
    )
    with pytest.raises(ModelError) as error:
        simulate(compiled, t_end=1.0, method="rk4", rtol=1e-6, atol=1e-8)
    assert str(error.value) == (
        "rtol and atol does not apply to method 'rk4' (a fixed-step method: give dt)"
    )


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"t_end": 0.0}, "the end time must be finite and after the start time 0, not 0.0"),
        ({"t_end": 1.0, "method": "rk4", "dt": -0.1}, "dt must be a finite number > 0, not -0.1"),
        ({"t_end": 1.0, "rtol": 0.0}, "rtol must be a finite number > 0, not 0.0"),
        ({"t_end": 1.0, "n_out": 1}, "n_out must be a whole number >= 2, not 1"),
        ({"t_end": 1.0, "t_eval": [0.0, 2.0]}, "t_eval must lie between 0 and t_end = 1"),
        ({"t_end": 1.0, "t_eval": [0.5, 0.2]}, "t_eval must be a non-empty increasing sequence"),
        ({"t_end": 1.0, "n_out": 3, "t_eval": [0.5]}, "give n_out or t_eval, not both"),
        ({"t_end": 1.0, "n_out": 3, "dt_out": 0.1}, "give n_out or dt_out, not both"),
        ({"t_end": 1.0, "dt_out": 0.0}, "dt_out must be a time step > 0, not 0.0"),
        ({"t_end": 1.0, "dt_out": float("nan")}, "dt_out must be a time step > 0, not nan"),
        ({"t_end": 1.0, "n_out": float("nan")}, "n_out must be a whole number >= 2, not nan"),
        ({"t_end": 1.0, "params": {"c": 1.0}}, "unknown parameter 'c' (parameters: m, k, b)"),
        ({"t_end": 1.0, "initial": {"z": 1.0}}, "not a coordinate or velocity: z"),
        ({"t_end": 1.0, "method": Dop853(), "rtol": 1e-3}, "give dt/rtol/atol to the integr"),
    ],
)
def test_bad_input_is_one_clear_error(options, message):
    with pytest.raises(ModelError) as error:
        simulate(systems.oscillator(), **options)
    assert str(error.value).startswith(message)


def test_a_configured_integrator_instance_can_be_given():
    method = Variational(dt=0.01, newton_tol=1e-13, explicit_when_separable=False)
    trajectory = simulate(systems.oscillator(), t_end=0.5, method=method)
    attrs = trajectory.dataset.attrs
    assert (attrs["dt"], attrs["newton_tol"], attrs["scheme"]) == (0.01, 1e-13, "midpoint")


# -- outputs ---------------------------------------------------------------------------------
@pytest.mark.parametrize("method", ["dop853", "radau", "rk4", "variational"])
def test_n_out_gives_equally_spaced_outputs_ending_at_t_end(method):
    trajectory = simulate(systems.oscillator(), t_end=3.0, method=method, n_out=7)
    np.testing.assert_array_equal(trajectory.t, np.linspace(0.0, 3.0, 7))
    exact = systems.oscillator_exact(3.0)  # default settings; variational: dt = 3e-3, O(dt^2)
    assert trajectory.final_state["x"] == pytest.approx(exact[0], abs=1e-4)
    assert trajectory.final_state["x_dot"] == pytest.approx(exact[1], abs=1e-4)


def test_fixed_step_outputs_between_steps_come_from_the_hermite_interpolant():
    compiled = systems.oscillator()
    coarse = simulate(compiled, t_end=1.0, method="rk4", dt=0.1, t_eval=[0.05, 0.55, 1.0])
    exact = systems.oscillator_exact(coarse.t)
    # O(dt^4) like the steps themselves (measured 5e-6, 7e-6 between steps, 2.7e-5 at t = 1)
    np.testing.assert_allclose(coarse["x"], exact[0], atol=5e-5)


def test_initial_state_and_parameters_come_from_the_arguments_then_the_model():
    trajectory = simulate(
        systems.oscillator(), t_end=1.0, initial={"x_dot": 0.0}, params={"k": 1.0}, n_out=3
    )
    # x(0) = 1 from the model's [initial] table, x'(0) overridden; omega = 1
    assert trajectory["x"][0] == 1.0
    assert trajectory["x_dot"][0] == 0.0
    assert trajectory.final_state["x"] == pytest.approx(np.cos(1.0), abs=1e-9)
    assert trajectory.parameters == {"m": 1.0, "k": 1.0, "b": 0.0}
    assert trajectory.dataset.attrs["model"] == "Oscillator"


def test_energy_and_invariants_are_evaluated_along_the_outputs():
    trajectory = simulate(systems.kepler(), t_end=1.0, n_out=11)
    assert trajectory.invariants == ("angular_momentum",)
    assert trajectory["energy"] == pytest.approx(np.full(11, -0.5), abs=1e-9)  # -mu/(2a)
    assert trajectory.drift("angular_momentum") < 1e-9
    assert trajectory.dataset.attrs["wall_time"] >= 0.0


# -- constraints -------------------------------------------------------------------------------
@pytest.mark.parametrize("method", ["rk4", "dop853"])
def test_constrained_motion_stays_on_the_constraint(method):
    compiled = systems.constrained_pendulum()
    start = {"x": 0.9, "y": -0.5}  # off the circle: projected first
    settings = {"dt": 0.01} if method == "rk4" else {}
    trajectory = simulate(compiled, t_end=10.0, method=method, initial=start, **settings)
    states = np.array([trajectory[name] for name in ("x", "y", "x_dot", "y_dot")])
    residual = compiled.constraint_residual(0.0, states, compiled.parameter_vector())
    assert np.max(np.abs(residual)) < 1e-8
    assert trajectory.multipliers == ("lambda1",)
    assert np.all(trajectory["lambda1"] < 0)  # the rod pulls the bob inwards
    assert trajectory.drift("energy") < 1e-4  # measured 1.5e-5 (rk4, projected), 1e-12 (dop853)


# -- work, counted ---------------------------------------------------------------------------
def test_dop853_work_shrinks_with_looser_tolerances():
    compiled = systems.pendulum()
    tight = simulate(compiled, t_end=10.0, rtol=1e-12, atol=1e-12).dataset.attrs
    loose = simulate(compiled, t_end=10.0, rtol=1e-6, atol=1e-8).dataset.attrs
    assert loose["rhs_evaluations"] < tight["rhs_evaluations"] / 3
    assert tight["steps"] < 400  # an 8th-order method on a smooth motion

"""System.fit against data made without lagrangian: systems that are not among the
project's examples, integrated by SciPy's solve_ivp from hand-written right-hand sides,
with 1 % noise (seeded).  The fitted values must be within 1 % of the truth and within
two of their reported standard errors; a pair the data cannot separate is named; the
Jacobian is the finite-difference one."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.integrate.fit import FitProblem, _Residuals
from lagrangian.integrate.observation import observation, observed_expressions
from lagrangian.integrate.pace import RunTooLong
from lagrangian.integrate.sensitivity import SensitivitySolver
from lagrangian.numeric import compile_equations


def measured(rhs, y0, t_end, points, columns, seed, noise=0.01):
    """solve_ivp's run at ``points`` times, ``columns(t, y)`` -> {name: values}, each with
    Gaussian noise of ``noise`` times its largest size."""
    t = np.linspace(0.0, t_end, points)
    run = solve_ivp(rhs, (0.0, t_end), y0, t_eval=t, rtol=1e-12, atol=1e-12, method="DOP853")
    rng = np.random.default_rng(seed)
    data = {"t": t}
    for name, values in columns(t, run.y).items():
        data[name] = values + noise * np.max(np.abs(values)) * rng.standard_normal(t.size)
    return data


def assert_recovered(result, truth):
    for name, value in truth.items():
        fitted, error = result.parameters[name]
        assert abs(fitted - value) <= 0.01 * abs(value), (name, fitted, value)
        assert abs(fitted - value) <= 2 * error, (name, fitted, value, error)


@pytest.mark.slow
def test_damped_spring_with_cubic_stiffness():
    # m x'' + c x' + k x + a x^3 = 0 (a Duffing oscillator without drive)
    m, c, k, a = 1.0, 0.3, 4.0, 2.0
    data = measured(
        lambda t, y: [y[1], -(c * y[1] + k * y[0] + a * y[0] ** 3) / m],
        [1.0, 0.0], 10.0, 201, lambda t, y: {"x": y[0]}, seed=1,
    )  # fmt: skip
    spring = lg.System.from_lagrangian(
        "m*x_dot**2/2 - k*x**2/2 - a*x**4/4", coordinates=["x"], dissipation="c*x_dot**2/2"
    )
    result = spring.fit(
        data, ["k=3", "c=0.5", "a=1"], params={"m": m}, initial={"x": 1.0}, backend="llvm"
    )
    assert_recovered(result, {"k": k, "c": c, "a": a})
    assert result.warnings == ()
    assert result.chi2_per_dof is None and result.converged == 1 and result.starts == 1
    assert abs(result.rms - 0.01) < 0.002  # the noise added: 1 % of |x| <= 1
    assert np.allclose(result.residuals["x"], data["x"] - result.fitted["x"])


def test_charged_particle_field_and_initial_velocity_from_two_columns():
    # m r'' = q r' x B: x'' = w y', y'' = -w x' with w = q B / m
    m, q, field, speed = 2.0, 0.5, 3.0, 1.2
    w = q * field / m
    data = measured(
        lambda t, y: [y[2], y[3], w * y[3], -w * y[2]],
        [0.0, 0.0, speed, 0.0], 8.0, 161, lambda t, y: {"x": y[0], "y": y[1]}, seed=2,
    )  # fmt: skip
    particle = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2)/2 + q*B*(x*y_dot - y*x_dot)/2", coordinates=["x", "y"]
    )
    radius = speed / w  # x = R sin(w t) and y = R (cos(w t) - 1): noise 1 % of R and of 2 R
    result = particle.fit(
        data, {"B": 2.0, "x_dot": 1.0}, params={"m": m, "q": q},
        noise={"x": 0.01 * radius, "y": 0.02 * radius}, backend="llvm",
    )  # fmt: skip
    assert_recovered(result, {"B": field, "x_dot": speed})
    assert 0.7 < result.chi2_per_dof < 1.3  # the noise given is the noise added


def test_physical_pendulum_inertia_through_an_observed_expression():
    # I theta'' = -m g d sin(theta); what is measured is the horizontal x = d sin(theta)
    inertia, m, g, d = 0.05, 0.4, 9.81, 0.2
    data = measured(
        lambda t, y: [y[1], -m * g * d * np.sin(y[0]) / inertia],
        [0.9, 0.0], 6.0, 151, lambda t, y: {"x_mark": d * np.sin(y[0])}, seed=3,
    )  # fmt: skip
    pendulum = lg.System.from_lagrangian(
        "I*theta_dot**2/2 + m*g*d*cos(theta)", coordinates=["theta"]
    )
    result = pendulum.fit(
        data, ["I=0.06", "theta=0.6"], observe=["x_mark = d*sin(theta)"],
        params={"m": m, "g": g, "d": d}, backend="llvm",
    )  # fmt: skip
    assert_recovered(result, {"I": inertia, "theta": 0.9})


def test_mass_and_stiffness_of_an_undamped_oscillator_are_not_separable():
    # x = cos(sqrt(k/m) t): only k/m is in the data
    t = np.linspace(0.0, 5.0, 101)
    data = {"t": t, "x": np.cos(2.0 * t) + 0.01 * np.random.default_rng(4).standard_normal(t.size)}
    spring = lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"])
    result = spring.fit(data, ["m=1.5", "k=5"], initial={"x": 1.0}, backend="llvm")
    assert abs(abs(result.correlation_of("m", "k")) - 1.0) < 1e-3
    assert any(w.startswith("m and k are correlated") for w in result.warnings), result.warnings
    assert any("fix one at a known value" in w for w in result.warnings)
    assert abs(result.parameters["k"][0] / result.parameters["m"][0] - 4.0) < 0.01
    assert any(w.startswith("the data cannot tell m and k apart") for w in result.warnings)
    assert np.all(np.isinf(result.stderr))  # undetermined, not a number that means nothing


@pytest.mark.slow
def test_a_parameter_the_motion_does_not_depend_on_is_named():
    # the bob's mass cancels from theta'' + gamma theta' + (g/l) sin(theta) = 0
    g, length, gamma = 9.81, 0.5, 0.2
    data = measured(
        lambda t, y: [y[1], -gamma * y[1] - g / length * np.sin(y[0])],
        [0.3, 0.0], 5.0, 101, lambda t, y: {"theta": y[0]}, seed=6,
    )  # fmt: skip
    pendulum = lg.System.from_lagrangian(
        "m*l**2*theta_dot**2/2 + m*g*l*cos(theta)", coordinates=["theta"],
        dissipation="m*l**2*gamma*theta_dot**2/2",
    )  # fmt: skip
    values = {"g": g, "l": 0.52, "gamma": 0.15, "m": 1.0}
    settings = {"params": values, "initial": {"theta": 0.3}, "noise": 0.003, "backend": "llvm"}
    alone = pendulum.fit(data, ["l", "gamma"], **settings)
    both = pendulum.fit(data, ["l", "gamma", "m"], **settings)
    assert both.warnings == (
        "the data do not depend on m: it cannot be fitted from them; fix it at a known value "
        "(leave it out of vary) or measure something it changes",
    )
    assert np.isinf(both.parameters["m"][1]) and np.isnan(both.correlation_of("l", "m"))
    # the others' values and errors are those of the fit without m (sigma given: the
    # degrees of freedom do not enter them)
    assert np.allclose(both.values[:2], alone.values, rtol=1e-6)
    assert np.allclose(both.stderr[:2], alone.stderr, rtol=1e-3)


def test_the_jacobian_is_the_finite_difference_one():
    # the exact Jacobian (sensitivities through the observed expression's gradients,
    # which depend on d itself) against central differences of the residuals
    pendulum = lg.System.from_lagrangian(
        "I*theta_dot**2/2 + m*g*d*cos(theta)", coordinates=["theta"],
        dissipation="b*theta_dot**2/2",
    )  # fmt: skip
    compiled = compile_equations(pendulum.equations_of_motion(), backend="llvm")
    expressions = observed_expressions(pendulum, {"x_mark": "d*sin(theta) + t*d/10"})
    times = np.linspace(0.3, 4.0, 40)
    p = compiled.parameter_vector({"I": 0.05, "m": 0.4, "g": 9.81, "d": 0.2, "b": 0.01})
    problem = FitProblem(
        times=times, data=np.zeros((2, times.size)),
        observation=observation(pendulum, ("x_mark", "theta_dot"), expressions),
        sigma=np.array([0.5, 2.0]), noise_given=True, y0=np.array([0.8, 0.1]), p=p,
    )  # fmt: skip
    names = ("d", "b", "theta", "theta_dot")
    solver = SensitivitySolver(compiled, names, rtol=1e-12, atol=1e-14)
    residuals = _Residuals(solver, problem, compiled)
    x = np.array([0.2, 0.01, 0.8, 0.1])
    _, jacobian, _ = residuals.evaluate(x)
    for j in range(len(names)):
        step = 1e-4 * abs(x[j])
        up, down = x.copy(), x.copy()
        up[j] += step
        down[j] -= step
        difference = (residuals.evaluate(up)[0] - residuals.evaluate(down)[0]) / (2 * step)
        scale = np.max(np.abs(difference))
        assert np.max(np.abs(jacobian[:, j] - difference)) <= 1e-6 * scale, names[j]


@pytest.mark.slow
def test_several_starts_say_how_many_reached_the_best():
    t = np.linspace(0.0, 4.0, 81)
    data = {"t": t, "x": np.exp(-0.1 * t) * np.cos(3.0 * t)}
    spring = lg.System.from_lagrangian(
        "x_dot**2/2 - k*x**2/2", coordinates=["x"], dissipation="c*x_dot**2/2"
    )
    start = {"x": 1.0, "x_dot": -0.1}
    result = spring.fit(data, ["k=8.5", "c=0.15"], initial=start, starts=4, backend="llvm")
    assert result.starts == 4 and 1 <= result.converged <= 4
    assert abs(result.parameters["k"][0] - 9.01) < 1e-5  # k = 3^2 + 0.1^2, c = 2 * 0.1
    assert abs(result.parameters["c"][0] - 0.2) < 1e-5
    again = spring.fit(data, ["k=8.5", "c=0.15"], initial=start, starts=4, backend="llvm")
    assert again.converged == result.converged  # seeded starts


@pytest.mark.parametrize(
    ("vary", "message"),
    [
        ([], "vary: give at least one name to fit"),
        (["k", "k"], "vary: 'k' is given twice"),
        (["z"], "vary: 'z' is neither a parameter nor a coordinate or velocity"),
        (["k=soft"], "vary: the start guess of k is not a number: 'soft'"),
        (["c"], "c has no value to start the fit from: give a guess, vary c=VALUE"),
    ],
)
def test_bad_vary_is_one_clear_error(vary, message):
    spring = lg.System.from_lagrangian(
        "x_dot**2/2 - k*x**2/2", coordinates=["x"], dissipation="c*x_dot**2/2"
    )
    data = {"t": [0.0, 1.0, 2.0], "x": [1.0, 0.5, 0.0]}
    with pytest.raises(lg.ModelError) as error:
        spring.fit(data, vary, params={"k": 1.0}, backend="llvm")
    assert str(error.value).startswith(message)


def test_a_fit_past_its_time_budget_stops_with_one_line():
    spring = lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"])
    t = np.linspace(0.0, 50.0, 2001)
    data = {"t": t, "x": np.cos(2.0 * t)}
    with pytest.raises(RunTooLong) as error:
        spring.fit(
            data, ["k=3"], params={"m": 1.0}, initial={"x": 1.0}, backend="llvm",
            timeout=1e-6,
        )  # fmt: skip
    assert str(error.value).startswith("the fit did not finish within 1e-06 s of CPU")


def test_data_in_other_units_fit_the_model_in_si():
    # x = 0.05 cos(w t) m with w = sqrt(k/m) = 3/s, given in centimetres over milliseconds,
    # as a pandas DataFrame: k comes out in N/m
    import pandas as pd

    spring = lg.loads(
        'coordinates = ["x"]\nlagrangian = "m*x_dot^2/2 - k*x^2/2"\n'
        '[parameters]\nm = "0.5 kg"\nk = "4 N/m"\n[units]\nx = "m"\n[initial]\nx = "5 cm"\n'
    )
    t = np.linspace(0.0, 4.0, 81)
    frame = pd.DataFrame({"t [ms]": 1000 * t, "x [cm]": 5.0 * np.cos(3.0 * t)})
    result = spring.fit(frame, ["k"], backend="llvm")
    assert abs(result.parameters["k"][0] - 4.5) < 1e-6  # m w^2 = 0.5 * 9
    assert np.allclose(result.times, t) and np.allclose(result.observed["x"], 0.05 * np.cos(3 * t))

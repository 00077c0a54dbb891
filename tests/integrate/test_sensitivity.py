"""Forward sensitivities dy(t)/dw against independent references: an analytic solution
differentiated by SymPy, and central differences of full runs (``System.simulate``).

The systems are written here, not taken from the project's examples.  Agreement is
measured per series: max |S - reference| / max |reference| over the output times (a
pointwise ratio is meaningless where a sensitivity crosses zero).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.errors import ModelError

DAMPED_SPRING = """
name = "Damped spring-mass"
coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "k*x^2/2"
dissipation = "b*x_dot^2/2"
[parameters]
m = 1.5
k = 7.0
b = 0.4
[initial]
x = 0.8
x_dot = -0.3
"""

SPRING_PENDULUM = """
name = "Pendulum on a spring"
coordinates = ["r", "phi"]
kinetic = "m*(r_dot^2 + r^2*phi_dot^2)/2"
potential = "k*(r - l0)^2/2 - m*g*r*cos(phi)"
[parameters]
m = 0.7
k = 30.0
l0 = 1.2
g = 9.81
[initial]
r = 1.4
phi = 0.6
"""

DRIVEN_DUFFING = """
name = "Driven Duffing oscillator"
coordinates = ["x"]
kinetic = "x_dot^2/2"
potential = "x^2/2 + a*x^4/4 - F*x*cos(w*t)"
dissipation = "c*x_dot^2/2"
[parameters]
a = 0.5
F = 0.8
w = 1.3
c = 0.1
[initial]
x = 0.2
"""

TIGHT = {"rtol": 1e-12, "atol": 1e-14}


def relative_error(value: np.ndarray, reference: np.ndarray) -> float:
    return float(np.max(np.abs(value - reference)) / np.max(np.abs(reference)))


def central_difference(system, name: str, state: str, times, step: float) -> np.ndarray:
    """d state(times) / d name from two full runs with name -+ step (a parameter or an
    initial value), each integrated at tight tolerance."""
    runs = []
    for sign in (-1.0, 1.0):
        if name in system.parameter_names:
            params = {p.name: p.default for p in system.parameters}
            params[name] += sign * step
            changes = {"params": params}
        else:
            initial = dict(system.initial)
            initial[name] = initial.get(name, 0.0) + sign * step
            changes = {"initial": initial}
        run = system.simulate(
            t_end=float(times[-1]), method="dop853", t_eval=times, **TIGHT, **changes
        )
        runs.append(run[state])
    return (runs[1] - runs[0]) / (2 * step)


def test_an_undamped_spring_matches_its_closed_form():
    """x = x0 cos(sqrt(k/m) t): dx/dk = -x0 t sin(sqrt(k/m) t) / (2 sqrt(k m))."""
    spring = lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"])
    result = spring.sensitivities(
        ["k", "x"], t_end=3.0, points=31, params={"m": 2.0, "k": 5.0}, initial={"x": 0.7}
    )
    t, omega = result.times, np.sqrt(5.0 / 2.0)
    exact_k = -0.7 * t * np.sin(omega * t) / (2 * np.sqrt(5.0 * 2.0))
    assert relative_error(result.of("x", "k"), exact_k) < 1e-8
    assert relative_error(result.of("x", "x"), np.cos(omega * t)) < 1e-8
    assert relative_error(result.of("x_dot", "x"), -omega * np.sin(omega * t)) < 1e-8


@pytest.mark.slow
def test_damped_spring_matches_the_differentiated_analytic_solution():
    """x(t) = e^(-b t / 2m) (x0 cos wt + (v0 + b x0 / 2m) / w sin wt), w^2 = k/m - (b/2m)^2,
    differentiated by SymPy with respect to k, b, x0 and v0."""
    system = lg.loads(DAMPED_SPRING)
    result = system.sensitivities(["k", "b", "x", "x_dot"], t_end=6.0, points=61, **TIGHT)
    m, k, b, x0, v0, t = sympy.symbols("m k b x0 v0 t", real=True)
    decay = b / (2 * m)
    omega = sympy.sqrt(k / m - decay**2)
    x = sympy.exp(-decay * t) * (
        x0 * sympy.cos(omega * t) + (v0 + decay * x0) / omega * sympy.sin(omega * t)
    )
    values = {m: 1.5, k: 7.0, b: 0.4, x0: 0.8, v0: -0.3}
    for name, symbol in (("k", k), ("b", b), ("x", x0), ("x_dot", v0)):
        for state, expression in (("x", x), ("x_dot", sympy.diff(x, t))):
            derivative = sympy.lambdify(t, sympy.diff(expression, symbol).subs(values), "numpy")
            exact = derivative(result.times)
            assert relative_error(result.of(state, name), exact) < 1e-8, (state, name)
    exact_motion = sympy.lambdify(t, x.subs(values), "numpy")(result.times)
    assert relative_error(result.states[:, 0], exact_motion) < 1e-9


@pytest.mark.parametrize(
    ("model", "wrt", "t_end"),
    [
        pytest.param(DAMPED_SPRING, ["k", "b", "x"], 5.0, marks=pytest.mark.slow),
        pytest.param(SPRING_PENDULUM, ["k", "l0", "phi", "r_dot"], 4.0, marks=pytest.mark.slow),
        pytest.param(DRIVEN_DUFFING, ["F", "w", "c"], 8.0, marks=pytest.mark.slow),
    ],
    ids=["damped spring", "spring pendulum", "driven Duffing"],
)
def test_sensitivities_agree_with_central_differences(model, wrt, t_end):
    system = lg.loads(model)
    result = system.sensitivities(wrt, t_end=t_end, points=41, **TIGHT)
    defaults = {p.name: p.default for p in system.parameters}
    for name in wrt:
        step = 1e-4 * max(1.0, abs(defaults.get(name, system.initial.get(name, 0.0))))
        for state in result.state_names:
            reference = central_difference(system, name, state, result.times, step)
            assert relative_error(result.of(state, name), reference) < 1e-6, (name, state)


@pytest.mark.slow
def test_the_compiled_loop_gives_scipys_answers():
    """backend="numba" runs the same DOP853 steps compiled: parameters and initial values
    mixed in the order asked (the loop takes the parameters' columns first)."""
    pytest.importorskip("numba")
    system = lg.loads(SPRING_PENDULUM)
    wrt = ["phi", "k", "r_dot", "l0", "g"]
    ours = system.sensitivities(wrt, t_end=4.0, points=41, backend="numba")
    scipy = system.sensitivities(wrt, t_end=4.0, points=41, backend="numpy")
    assert ours.wrt == scipy.wrt == tuple(wrt)
    for name in wrt:
        for state in ours.state_names:
            error = relative_error(ours.of(state, name), scipy.of(state, name))
            assert error < 1e-9, (name, state)
    np.testing.assert_allclose(ours.states, scipy.states, rtol=0, atol=1e-10)
    # and against central differences of full runs
    reference = central_difference(system, "k", "phi", ours.times, 1e-4 * 30.0)
    assert relative_error(ours.of("phi", "k"), reference) < 1e-6


@pytest.mark.slow
def test_the_compiled_loop_with_initial_values_only():
    pytest.importorskip("numba")
    spring = lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"])
    result = spring.sensitivities(
        ["x_dot", "x"], t_end=3.0, points=31, params={"m": 2.0, "k": 5.0},
        initial={"x": 0.7}, backend="numba",
    )  # fmt: skip
    t, omega = result.times, np.sqrt(5.0 / 2.0)
    assert relative_error(result.of("x", "x"), np.cos(omega * t)) < 1e-8
    assert relative_error(result.of("x", "x_dot"), np.sin(omega * t) / omega) < 1e-8


def test_the_motion_is_the_motion_of_a_plain_run():
    system = lg.loads(SPRING_PENDULUM)
    result = system.sensitivities(["g"], t_end=3.0, points=31, **TIGHT)
    run = system.simulate(t_end=3.0, method="dop853", t_eval=result.times, **TIGHT)
    for column, name in enumerate(result.state_names):
        np.testing.assert_allclose(result.states[:, column], run[name], rtol=0, atol=1e-9)


def test_initial_value_columns_start_as_the_identity_and_parameters_at_zero():
    result = lg.loads(SPRING_PENDULUM).sensitivities(["phi", "k", "r_dot"], t_end=1.0)
    start = result.values[0]
    np.testing.assert_array_equal(start[:, 0], [0.0, 1.0, 0.0, 0.0])
    np.testing.assert_array_equal(start[:, 1], [0.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(start[:, 2], [0.0, 0.0, 1.0, 0.0])
    assert result.settings() == {"t_end": 1.0, "rtol": 1e-10, "atol": 1e-12}


def test_the_dataset_has_time_state_and_wrt_and_survives_netcdf(tmp_path):
    import xarray as xr

    result = lg.loads(DAMPED_SPRING).sensitivities(["k", "x"], t_end=2.0, points=11)
    dataset = result.to_dataset()
    assert dataset["sensitivity"].dims == ("time", "state", "wrt")
    assert list(dataset["wrt"].values) == ["k", "x"]
    assert list(dataset["state"].values) == ["x", "x_dot"]
    assert dataset.attrs["parameter_k"] == 7.0
    path = tmp_path / "s.nc"
    dataset.to_netcdf(path)
    with xr.open_dataset(path) as back:
        np.testing.assert_array_equal(back["sensitivity"].values, result.values)


@pytest.mark.parametrize(
    ("wrt", "message"),
    [
        (
            ["k", "spring"],
            "'spring' is neither a parameter nor a coordinate or velocity "
            "(parameters: m, k, b; initial values: x, x_dot)",
        ),
        (["k", "k"], "'k' is given twice"),
        ([], "give at least one name to differentiate by"),
    ],
)
def test_bad_names_are_refused_with_one_line(wrt, message):
    with pytest.raises(ModelError) as raised:
        lg.loads(DAMPED_SPRING).sensitivities(wrt, t_end=1.0)
    assert message in str(raised.value)
    assert "\n" not in str(raised.value)


def test_constrained_systems_are_refused():
    system = lg.loads(
        'coordinates = ["x", "y"]\nkinetic = "m*(x_dot^2 + y_dot^2)/2"\npotential = "m*g*y"\n'
        'constraints = ["x*x_dot + y*y_dot"]\n[parameters]\nm = 1.0\ng = 9.81\n'
        "[initial]\nx = 1.0\n"
    )
    with pytest.raises(ModelError, match="sensitivities of constrained systems"):
        system.sensitivities(["g"], t_end=1.0)

"""Method "taylor" (heyoka, optional) against analytic solutions and against DOP853."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.errors import ModelError
from lagrangian.integrate.taylor import Taylor
from lagrangian.numeric import compile_equations

pytest.importorskip("heyoka")


def test_oscillator_matches_the_exact_solution_to_rounding():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 - k*x**2/2", coordinates=["x"], parameters={"m": 2.0, "k": 8.0}
    )
    compiled = compile_equations(system.equations_of_motion())
    params = compiled.parameter_vector({"k": 18.0})  # omega = 3: the parameters are runtime
    grid = np.linspace(0.0, 20.0, 41)
    result = Taylor(tol=1e-15).solve(compiled, (0.0, 20.0), [1.0, 0.0], params, t_eval=grid)
    assert result.success
    np.testing.assert_allclose(result.y[0], np.cos(3 * grid), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result.y[1], -3 * np.sin(3 * grid), rtol=0, atol=1e-11)


def test_double_pendulum_agrees_with_dop853_and_ends_on_t_end():
    system = lg.load("double_pendulum")
    trajectory = system.simulate(t_end=5.0, method="taylor", rtol=1e-14)
    reference = system.simulate(t_end=5.0, method="dop853", rtol=1e-13, atol=1e-13)
    assert trajectory.dataset.attrs["method"] == "taylor"
    assert float(trajectory.dataset["t"][-1]) == 5.0
    for name in ("theta1", "theta2", "theta1_dot", "theta2_dot"):
        assert abs(trajectory.final_state[name] - reference.final_state[name]) < 1e-9


def test_what_taylor_does_not_handle_is_refused():
    system = lg.load("double_pendulum")
    with pytest.raises(ModelError, match="does not apply to method 'taylor'"):
        system.simulate(t_end=1.0, method="taylor", dt=0.01)


@pytest.mark.parametrize(
    ("settings", "match"),
    [
        ({"rtol": 0.0}, "rtol must be a finite number > 0"),
        ({"atol": 0.0}, "atol must be a finite number > 0"),
        ({"rtol": float("nan")}, "rtol must be a finite number > 0"),
        ({"rtol": 1e-300}, r"below what taylor can deliver in double precision: give rtol"),
        ({"atol": 1e-17}, r"below what taylor can deliver in double precision: give atol"),
    ],
)
def test_tolerances_it_cannot_use_are_refused(settings, match):
    with pytest.raises(ModelError, match=match):
        Taylor.configure(t_span=(0.0, 1.0), **settings)


def test_the_tolerance_is_echoed_as_rtol_and_atol():
    settings = Taylor.configure(t_span=(0.0, 1.0), rtol=1e-9, atol=1e-11).settings()
    assert settings == {
        "method": "taylor",
        "tol": 1e-11,
        "rtol": 1e-11,
        "atol": 1e-11,
        "backend": "heyoka",
    }


def test_an_indefinite_mass_matrix_is_refused_naming_dop853():
    # M = [[a, 1], [1, -1]]: elimination without pivoting on the tiny pivot a loses 9 digits
    system = lg.System.from_lagrangian(
        "a*x_dot**2/2 + x_dot*y_dot - y_dot**2/2 - x**2/2 - y**2/2",
        coordinates=["x", "y"],
        parameters={"a": 1e-9},
    )
    with pytest.raises(ModelError, match=r"needs a definite mass matrix .*: use dop853$"):
        system.simulate(t_end=1.0, method="taylor", initial={"x": 1.0})
    assert system.simulate(t_end=1.0, method="dop853", initial={"x": 1.0}).status == "success"


def test_a_negative_definite_mass_matrix_is_solved():
    # L = -(T - V): the same motion, M = -1 (every pivot negative: no pivoting needed)
    system = lg.System.from_lagrangian("-x_dot**2/2 + x**2/2", coordinates=["x"])
    trajectory = system.simulate(t_end=3.0, method="taylor", initial={"x": 1.0})
    assert abs(trajectory.final_state["x"] - np.cos(3.0)) < 1e-12


def test_rationals_heyoka_cannot_hold_exactly_become_doubles():
    # x/10: heyoka takes only rationals with a power of 2 below the line
    system = lg.System.from_lagrangian(
        "x_dot**2/2 + y_dot**2/3 + x_dot*y_dot/10 - x**2/2 - y**2/2 - x*y/7",
        coordinates=["x", "y"],
    )
    trajectory = system.simulate(t_end=5.0, method="taylor", initial={"x": 1.0})
    reference = system.simulate(
        t_end=5.0, method="dop853", rtol=1e-13, atol=1e-13, initial={"x": 1.0}
    )
    for name in ("x", "y", "x_dot", "y_dot"):
        assert abs(trajectory.final_state[name] - reference.final_state[name]) < 1e-10


def test_a_failure_names_the_last_finite_state():
    system = lg.System.from_lagrangian("x_dot**2/2 - sqrt(x)", coordinates=["x"])
    trajectory = system.simulate(t_end=3.0, method="taylor", initial={"x": 1.0})
    assert trajectory.status == "failed"
    message = trajectory.dataset.attrs["message"]
    assert message.startswith("the state is not finite after t = 1.8856")
    assert "x_dot = -1.4142" in message


def test_a_first_run_reports_heyokas_build_and_a_second_in_the_process_less():
    # heyoka compiles its Taylor series by LLVM when the integrator is built: the first run
    # pays it (compile_time), the second finds the integrator built (a quartic well this
    # file's other tests do not build, so that the first run here is the first build)
    system = lg.System.from_lagrangian("x_dot**2/2 - x**4/4 - x**2/3", coordinates=["x"])
    first = system.simulate(t_end=1.0, method="taylor", rtol=1e-10, initial={"x": 1.0})
    second = system.simulate(t_end=1.0, method="taylor", rtol=1e-10, initial={"x": 1.0})
    order = math.ceil(-math.log(1e-10) / 2) + 1  # heyoka's order for a tolerance
    assert first.attrs["compiled"] == f"heyoka's Taylor integrator (order {order})"
    assert first.attrs["compile_time"] > 0.0
    assert (
        second.attrs["compiled"] == "nothing: heyoka's integrator was built earlier in this process"
    )
    assert second.attrs["compile_time"] < first.attrs["compile_time"]
    assert second.final_state == first.final_state


def test_the_summary_says_what_a_taylor_run_compiled(capsys):
    command = [
        "simulate", "--lagrangian", "x_dot^2/2 - x^4/4 - x^2/5", "--coordinates", "x",
        "--set", "x=1", "--t-end", "2", "--method", "taylor", "--rtol", "1e-12",
    ]  # fmt: skip
    assert main([*command, "--json"]) == ExitStatus.SUCCESS
    summary = json.loads(capsys.readouterr().out)
    assert summary["compiled"] == "heyoka's Taylor integrator (order 15)"
    assert summary["compile_time"] > 0.0
    assert main(command) == ExitStatus.SUCCESS
    lines = capsys.readouterr().out.splitlines()
    assert lines[2].startswith("compiled: nothing: heyoka's integrator was built earlier in ")
    assert lines[2].endswith(" s of CPU")

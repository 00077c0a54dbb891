"""The default method and backend of a single run, chosen by the run's length (integrate.choice)."""

from __future__ import annotations

import importlib.util
import json

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.integrate import choice as choice_module
from lagrangian.integrate import simulate
from lagrangian.integrate.choice import choose_run, estimated_steps
from lagrangian.integrate.events import Event
from lagrangian.integrate.scipy_methods import Dop853
from lagrangian.integrate.taylor import Taylor
from lagrangian.numeric import compile_equations

DOUBLE = lg.load("double_pendulum").equations_of_motion()
START = {"theta1": 2.0, "theta2": 0.5}


def choose(eom=DOUBLE, t_end=20.0, **given):
    settings = {"method": None, "backend": None, "rtol": None, "atol": None, "params": {}}
    settings.update(given)
    settings.setdefault("initial", START)
    return choose_run(eom, t_end=t_end, **settings)


def test_the_probe_estimates_the_steps_dop853_takes():
    compiled = compile_equations(DOUBLE, backend="numpy")
    y0, p = compiled.state_vector(START), compiled.parameter_vector()
    taken = simulate(compiled, t_end=20.0, initial=START).dataset.attrs["steps"]
    estimate = estimated_steps(compiled, (0.0, 20.0), y0, p, 1e-10, 1e-12)
    assert taken / 1.5 < estimate < 1.5 * taken
    assert estimated_steps(compiled, (0.0, 20.0), y0, p, 1e-10, 1e-12) == estimate  # no clock


def test_a_short_run_takes_scipys_loop_at_once():
    run = choose()
    assert run.method == "dop853"
    assert run.compiled.backend in ("llvm", "numpy")
    assert run.reason.startswith(f"dop853 in SciPy's loop on {run.compiled.backend}: about ")
    assert (run.rtol, run.atol) == (1e-10, 1e-12)


def test_a_long_run_with_events_compiles_dop853s_loop(monkeypatch):
    pytest.importorskip("numba")
    # Taylor's method, heyoka's or ours, is cheaper still for the double pendulum and
    # watches events too (test_taylor_path, test_taylor_numba): left out here
    monkeypatch.setattr(choice_module, "heyoka_installed", lambda: False)
    monkeypatch.setattr(choice_module, "_taylor_problem", lambda *arguments: "left out")
    run = choose(t_end=1e5, events=(Event(lambda t, y, p: y[0]),))
    assert run.method == "dop853"
    assert run.compiled.backend == "numba"
    assert run.reason.startswith("dop853 with its loop compiled (numba): about ")
    assert run.reason.count("\n") == 0


def test_without_numba_a_long_run_says_what_is_missing(monkeypatch):
    monkeypatch.setattr(choice_module, "numba_installed", lambda: False)
    monkeypatch.setattr(choice_module, "heyoka_installed", lambda: False)
    run = choose(t_end=1e5, events=(Event(lambda t, y, p: y[0]),))
    assert run.method == "dop853" and run.compiled.backend != "numba"
    assert "numba is not installed (the compiled loop)" in run.reason
    assert "taylor" not in run.reason


def test_constraints_go_to_the_compiled_loop_not_to_taylor():
    pytest.importorskip("numba")
    eom = lg.load("cartesian_pendulum").equations_of_motion()
    run = choose(eom, t_end=1e4, initial={})
    assert (run.method, run.compiled.backend) == ("dop853", "numba")
    assert run.reason.startswith("dop853 with its loop compiled (numba): ")
    if importlib.util.find_spec("heyoka") is not None:
        assert "; taylor does not take constraints" in run.reason


def test_a_method_or_backend_given_is_kept():
    run = choose(method="rk4")
    assert run.method == "rk4"
    assert run.reason.endswith(": the method asked for")
    run = choose(backend="numpy")
    assert (run.method, run.compiled.backend) == ("dop853", "numpy")
    assert run.reason == "dop853 on numpy: the backend asked for"


def test_the_summary_says_which_method_and_backend_ran_and_why(capsys):
    status = main(["simulate", "harmonic_oscillator", "--t-end", "2", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert status == ExitStatus.SUCCESS
    assert summary["method"] == "dop853"
    assert summary["backend"] in ("llvm", "numpy")
    assert summary["choice"].startswith(f"dop853 in SciPy's loop on {summary['backend']}")
    assert main(["simulate", "harmonic_oscillator", "--t-end", "2"]) == ExitStatus.SUCCESS
    lines = capsys.readouterr().out.splitlines()
    assert lines[1] == f"method: {summary['choice']}"
    assert np.isfinite(summary["final_state"]["x"])


@pytest.mark.parametrize(
    ("method", "linked", "expected"),
    [
        ("dop853", True, Dop853(rtol=1e-9, atol=1e-11, linked=True)),
        ("dop853", False, Dop853(rtol=1e-9, atol=1e-11)),
        ("taylor", False, Taylor(tol=1e-11)),  # heyoka's one tolerance: the smaller
    ],
)
def test_the_integrator_of_a_choice_is_the_one_simulate_runs(method, linked, expected):
    # benchmarks time the default through it: the linked loop is dop853 with linked=True,
    # not SciPy's loop on the same llvm code
    run = choice_module.RunChoice(None, method, 1e-9, 1e-11, "why", linked=linked)
    assert run.integrator(5.0) == expected

"""DOP853's compiled loop over SymEngine's LLVM code of M and f (compiled_dop853.linked_loop):
the method compiled once on a machine, nothing compiled for a new system but SymEngine's
code; the choice takes it for a new system's long run, and the run says what it compiled.

Systems held out of the project (none is an example) are run by both loops: the system's
own generated y' (numba) and the shared method over the LLVM code.  Where both codes
evaluate y' with the same roundings (polynomials of exactly representable values) the two
trajectories are bit for bit the same: the loops take the same steps.  Elsewhere the two
codes of y' differ by rounding (SymEngine's common subexpressions are not SymPy's), which
is checked at random states, and the runs agree within the tolerance.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.codegen.cache import cache_directory, compiled_on_disk
from lagrangian.codegen.llvm import llvm_available
from lagrangian.integrate import choice as choice_module
from lagrangian.integrate import simulate
from lagrangian.integrate.choice import choose_run
from lagrangian.integrate.compiled_dop853 import (
    _method_text,
    compiled_loop,
    linked_applies,
    linked_loop,
)
from lagrangian.integrate.scipy_methods import Dop853
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")
if not llvm_available():
    pytest.skip("SymEngine without LLVM: no linked loop", allow_module_level=True)

#: Held-out systems: (L, coordinates, initial state); parameters 1.0, 1.1, 1.2, ...
EXACT = {  # y' is a polynomial of exactly representable values: the same roundings
    "quartic oscillator": ("x_dot**2/2 - x**2/2 - x**4/4", ["x"], {"x": 1.25}),
    "coupled quartic": (
        "(x_dot**2 + y_dot**2)/2 - x**2/2 - y**2 - x*y/4 - x**4/8",
        ["x", "y"],
        {"x": 0.5, "y": -0.75},
    ),
}
ROUNDED = {  # trigonometric and rational terms: the two codes differ by rounding
    "pendulums and a spring": (
        "m*l**2*(a_dot**2 + b_dot**2)/2 + m*g*l*(cos(a) + cos(b)) - k*l**2*(sin(a) - sin(b))**2/2",
        ["a", "b"],
        {"a": 0.4},
    ),
    "elastic pendulum": (
        "m*(r_dot**2 + r**2*phi_dot**2)/2 + m*g*r*cos(phi) - k*(r - l)**2/2",
        ["r", "phi"],
        {"r": 1.2, "phi": 0.5},
    ),
}


def both_backends(lagrangian: str, coordinates: list[str]):
    eom = lg.System.from_lagrangian(lagrangian, coordinates=coordinates).equations_of_motion()
    return compile_equations(eom, backend="numba"), compile_equations(eom, backend="llvm")


def parameters(compiled) -> dict[str, float]:
    return {name: 1.0 + 0.1 * i for i, name in enumerate(compiled.parameter_names)}


def states(run) -> np.ndarray:
    return np.stack([run[name] for name in (*run.coordinates, *run.velocities)])


def runs(case, t_end=10.0, **options):
    """(the system's own loop, the linked loop) runs of a held-out case."""
    lagrangian, coordinates, initial = case
    numba, llvm = both_backends(lagrangian, coordinates)
    assert linked_applies(llvm)
    values = parameters(numba)
    own = simulate(numba, t_end=t_end, initial=initial, params=values, **options)
    linked = simulate(
        llvm, t_end=t_end, initial=initial, params=values, method=Dop853(linked=True), **options
    )
    return own, linked


@pytest.mark.parametrize("name", sorted(EXACT))
def test_the_same_roundings_give_the_same_trajectory_bit_for_bit(name):
    own, linked = runs(EXACT[name])
    # what the run paid: the LLVM code, or nothing where an earlier test (any order) made it
    paid = ("the right-hand side by LLVM", "the DOP", "nothing: the loop was made earlier")
    assert linked.dataset.attrs["compiled"].startswith(paid)
    assert own.t.tolist() == linked.t.tolist()
    assert np.array_equal(states(own), states(linked))
    assert own.dataset.attrs["rhs_evaluations"] == linked.dataset.attrs["rhs_evaluations"]


@pytest.mark.parametrize("name", sorted(ROUNDED))
def test_the_two_codes_of_y_prime_agree_to_rounding_and_so_do_the_runs(name):
    lagrangian, coordinates, _ = ROUNDED[name]
    numba, llvm = both_backends(lagrangian, coordinates)
    own, linked = compiled_loop(numba), linked_loop(llvm)
    p = np.array(list(parameters(numba).values()))
    rng = np.random.default_rng(7)
    for _ in range(200):
        t, y = rng.uniform(0.0, 10.0), rng.uniform(-2.0, 2.0, size=2 * numba.n)
        y[0] = abs(y[0]) + 0.5  # r > 0 for the elastic pendulum
        expected = own.y_prime_at(t, y, p)
        np.testing.assert_allclose(linked.y_prime_at(t, y, p), expected, rtol=1e-12, atol=1e-14)
    first, second = runs(ROUNDED[name])
    steps = first.dataset.attrs["steps"]
    assert abs(second.dataset.attrs["steps"] - steps) <= max(1, 0.01 * steps)
    assert first.t[-1] == second.t[-1] == 10.0
    np.testing.assert_allclose(states(second)[:, -1], states(first)[:, -1], atol=1e-7)


def test_events_and_outputs_on_a_grid_are_the_same_as_the_systems_own_loop():
    from lagrangian.integrate import Event

    times = np.linspace(0.0, 5.0, 26)
    down = Event(lambda t, y, p: y[0], direction=-1, name="down")
    own, linked = runs(EXACT["quartic oscillator"], t_end=5.0, t_eval=times, events=(down,))
    assert linked.t.tolist() == times.tolist()
    assert np.array_equal(states(own), states(linked))
    assert own.events["down"].times.size >= 1
    assert np.array_equal(own.events["down"].times, linked.events["down"].times)


def test_the_method_is_compiled_into_the_code_cache_once_for_every_system():
    llvm = both_backends(*EXACT["coupled quartic"][:2])[1]
    loop = linked_loop(llvm)
    loop.prepare(2 * llvm.n, len(llvm.parameter_names))
    digest = _method_text()[0]
    assert compiled_on_disk(digest, "linked_derivative")
    assert compiled_on_disk(digest, "advance")
    assert (cache_directory() / f"{digest}.py").is_file()  # the test suite's own folder
    other = both_backends(*ROUNDED["elastic pendulum"][:2])[1]
    assert linked_loop(other).method is loop.method  # one module for every system


def test_a_new_systems_long_run_takes_the_linked_loop_and_a_cached_one_its_own(monkeypatch):
    eom = lg.System.from_lagrangian(
        "x_dot**2/2 - x**2/2 - x**4/12", coordinates=["x"]
    ).equations_of_motion()

    def choose(t_end):
        return choose_run(
            eom, t_end=t_end, method=None, backend=None, rtol=None, atol=None,
            initial={"x": 1.0}, params={},
        )  # fmt: skip

    monkeypatch.setattr(choice_module, "importlib", _NoHeyoka())  # taylor is not the question,
    monkeypatch.setattr(choice_module, "_taylor_problem", lambda *arguments: "left out")  # ours
    monkeypatch.setattr(choice_module, "compiled_ready", lambda compiled: False)
    run = choose(2000.0)
    assert (run.method, run.compiled.backend, run.linked) == ("dop853", "llvm", True)
    assert run.reason.startswith("dop853 with its loop compiled (numba) over the llvm backend")
    monkeypatch.setattr(choice_module, "compiled_ready", lambda compiled: True)
    run = choose(2000.0)
    assert (run.compiled.backend, run.linked) == ("numba", False)
    assert "compiled loop on llvm" not in run.reason  # only offered while it is not cached


class _NoHeyoka:
    """``importlib`` for choice.py, with heyoka not installed."""

    class util:  # stands for importlib.util
        @staticmethod
        def find_spec(name):
            return None


def test_the_summary_says_what_the_run_compiled_and_its_cpu_seconds(capsys):
    command = [
        "simulate", "--lagrangian", "x_dot^2/2 - x^2/2 - x^4/7", "--coordinates", "x",
        "--set", "x=1", "--t-end", "3000", "--method", "dop853",
    ]  # fmt: skip
    assert main([*command, "--json"]) == ExitStatus.SUCCESS
    summary = json.loads(capsys.readouterr().out)
    assert summary["compile_time"] >= 0.0
    assert summary["backend"] == "llvm"
    assert "llvm backend's M and f" in summary["choice"]
    assert summary["compiled"].startswith(("the right-hand side by LLVM", "the DOP853 loop"))
    assert main(command) == ExitStatus.SUCCESS  # again in this process: nothing to make
    lines = capsys.readouterr().out.splitlines()
    assert lines[2].startswith("compiled: nothing: the loop was made earlier in this process, ")
    assert lines[2].endswith(" s of CPU")


def test_a_short_run_reports_its_compile_time_and_compiles_no_loop(capsys):
    status = main(["simulate", "harmonic_oscillator", "--t-end", "2", "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert status == ExitStatus.SUCCESS
    assert summary["choice"].startswith("dop853 in SciPy's loop")
    assert summary["compile_time"] >= 0.0
    assert "compiled" not in summary

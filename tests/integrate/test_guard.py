"""A run that leaves the domain of its equations, or steps across a singularity, fails with a
message naming the time and the state: never a hang, never "success" (integrate.guard)."""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.integrate import simulate
from lagrangian.integrate.guard import ENERGY_JUMP
from lagrangian.integrate.step_size import CoarseStepWarning
from lagrangian.numeric import compile_equations

METHODS = ("dop853", "radau", "rk4", "variational")


@functools.cache
def compiled(lagrangian: str, forces: tuple[tuple[str, str], ...] = ()):
    system = lg.System.from_lagrangian(lagrangian, coordinates=["x"], forces=dict(forces))
    return compile_equations(system.equations_of_motion())


SQRT = "x_dot**2/2 - k*sqrt(x)"  # V = k sqrt(x): undefined for x < 0, F infinite at x = 0
COULOMB = "m*x_dot**2/2 + k/x"  # V = -k/x: falls into x = 0 in finite time


def run(lagrangian, method, forces=(), **options):
    with warnings.catch_warnings():  # NaN and inf are reported, not warned about
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", CoarseStepWarning)  # coarse steps are the point here
        return simulate(compiled(lagrangian, forces), method=method, **options)


@pytest.mark.parametrize("method", METHODS)
def test_a_right_hand_side_undefined_at_the_start_fails_at_once(method):
    trajectory = run(SQRT, method, t_end=1.0, initial={"x": -1.0}, params={"k": 1.0})
    assert trajectory.status == "failed"
    assert trajectory.dataset.attrs["message"].startswith(
        "the right-hand side is not finite at t = 0 (x = -1, x_dot = 0): "
        "the equations of motion are undefined or infinite there"
    )
    assert trajectory.t.tolist() == [0.0]


@pytest.mark.parametrize("method", ["dop853", "radau"])
def test_an_adaptive_run_into_an_infinite_force_fails_when_it_gets_there(method):
    # x'' = -1/(2 sqrt x) from x = 1 at rest reaches x = 0 at t = 4 sqrt(2) / 3 (energy:
    # x'^2/2 + sqrt(x) = 1), where the force is infinite and beyond which V is undefined.
    trajectory = run(SQRT, method, t_end=3.0, initial={"x": 1.0}, params={"k": 1.0})
    assert trajectory.status == "failed"
    message = trajectory.dataset.attrs["message"]
    assert message.startswith("the right-hand side is not finite just after t = 1.885")
    assert "no step size works" in message
    assert trajectory.t[-1] == pytest.approx(4 * np.sqrt(2) / 3, abs=1e-4)


@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_a_fixed_step_run_leaving_the_domain_fails_with_the_last_finite_state(method):
    trajectory = run(SQRT, method, t_end=3.0, dt=1e-3, initial={"x": 1.0}, params={"k": 1.0})
    assert trajectory.status == "failed"
    message = trajectory.dataset.attrs["message"]
    assert message.startswith("the state is not finite after t = 1.88")
    assert np.all(np.isfinite(trajectory.dataset["x"].values))
    assert trajectory.t[-1] == pytest.approx(4 * np.sqrt(2) / 3, abs=5e-3)


@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_stepping_across_a_singularity_is_a_failure_not_a_success(method):
    # from x = 0.01 at rest, V = -1/x reaches x = 0 at t = 1.1e-3: the second step of 1e-3
    # (stable at the start, omega dt = 1.4) lands beyond it on a finite state.
    trajectory = run(
        COULOMB, method, t_end=10.0, dt=1e-3, initial={"x": 0.01}, params={"m": 1, "k": 1}
    )
    assert trajectory.status == "failed"
    message = trajectory.dataset.attrs["message"]
    assert message.startswith("the energy jumped from ")  # -100, or the first step's
    assert "in the step from t = 0.001 (x = " in message
    assert "the motion passes a singularity" in message
    assert trajectory.t.tolist() == [0.0, 0.001]  # the output ends before the broken step


@pytest.mark.slow
@pytest.mark.parametrize("method", ["rk4", "variational"])
def test_an_infinite_force_stepped_across_breaks_the_work_energy_balance(method):
    # no potential: h = T changes by the work of Q = -k/x^2, which one step across x = 0
    # does not follow (the trapezoidal work of its ends is nowhere near the change of T).
    trajectory = run(
        "m*x_dot**2/2", method, forces=(("x", "-k/x**2"),), t_end=10.0, dt=1e-3,
        initial={"x": 0.01}, params={"m": 1, "k": 1},
    )  # fmt: skip
    assert trajectory.status == "failed"
    message = trajectory.dataset.attrs["message"]
    # rk4 lands beyond x = 0; the midpoint's Newton finds no step across it
    assert message.startswith("the energy jumped from 0 to ") or "did not converge" in message


def test_a_forced_run_that_follows_its_forces_is_not_flagged():
    # strong damping: the energy falls to nothing, every step by the work of the friction
    trajectory = run(
        "x_dot**2/2 - x**2/2", "rk4", forces=(("x", "-3*x_dot"),), t_end=20.0,
        initial={"x": 1.0},
    )  # fmt: skip
    assert trajectory.status == "success"


@pytest.mark.parametrize("method", ["rk4", "variational"])
@pytest.mark.parametrize(
    "name, initial, t_end",
    [
        ("simple_pendulum", {"theta": np.pi / 2}, 10.0),  # h = 0 and L = 0 at the start
        ("double_pendulum", {"theta1": 3.0, "theta2": -3.0}, 20.0),  # chaotic, near-vertical
        ("central_force", None, 20.0),
        ("spherical_pendulum", None, 10.0),
    ],
)
def test_accurate_runs_keep_their_energy_balance(method, name, initial, t_end):
    system = compile_equations(lg.load(name).equations_of_motion())
    trajectory = simulate(system, method=method, t_end=t_end, initial=initial)
    assert trajectory.status == "success", trajectory.dataset.attrs["message"]


def test_the_bound_leaves_room_for_coarse_but_stable_steps():
    # rk4 at omega dt = 1 (6 steps a period) changes h by well under a tenth of it a step
    trajectory = run("x_dot**2/2 - x**2/2", "rk4", t_end=50.0, dt=1.0, initial={"x": 1.0})
    assert trajectory.status == "success"
    energy = trajectory.dataset["energy"].values
    assert np.max(np.abs(np.diff(energy))) < ENERGY_JUMP * 0.1 * abs(energy[0])


def test_a_jacobian_undefined_at_an_accepted_state_stops_radau():
    # V = x^(3/2): the force -3 sqrt(x)/2 is finite at x = 0, its derivative is not
    trajectory = run("x_dot**2/2 - x*sqrt(x)", "radau", t_end=1.0, initial={"x": 0.0})
    assert trajectory.status == "failed"
    assert trajectory.dataset.attrs["message"].startswith(
        "the Jacobian of the right-hand side is not finite at t = 0 (x = 0, x_dot = 0)"
    )

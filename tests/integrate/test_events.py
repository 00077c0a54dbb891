"""Events: direction, terminal stops, root location, names; scipy and fixed-step alike."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.errors import ModelError
from lagrangian.integrate import RK4, Event, Status, Variational, simulate
from lagrangian.integrate.events import hermite

from . import systems

# x(t) = cos 2t + sin(2t)/4 vanishes at 2t = pi - atan 4 + k pi, going down first
ZEROS = (np.pi - np.arctan(4.0) + np.pi * np.arange(6)) / 2
DOWN, UP = ZEROS[0::2], ZEROS[1::2]
T_END = 9.0  # six zeros before it

# (method, settings, accuracy of the event times); the fixed-step methods are only
# as accurate as their solution; root location on the step's interpolant is far better
METHODS = [
    ("dop853", {"rtol": 1e-12, "atol": 1e-12}, 1e-10),
    ("radau", {"rtol": 1e-10, "atol": 1e-12}, 1e-8),
    ("rk4", {"dt": 0.01}, 5e-8),
    ("variational", {"dt": 1e-3}, 1e-5),
]
IDS = [case[0] for case in METHODS]


def crossing_zero(**options) -> Event:
    return Event(lambda t, y, p: y[0], **options)


@pytest.mark.parametrize(("method", "settings", "accuracy"), METHODS, ids=IDS)
@pytest.mark.parametrize(("direction", "expected"), [(0, ZEROS), (1, UP), (-1, DOWN)])
def test_events_in_each_direction(method, settings, accuracy, direction, expected):
    trajectory = simulate(
        systems.oscillator(),
        t_end=T_END,
        method=method,
        events=[crossing_zero(direction=direction, name="zero")],
        **settings,
    )
    record = trajectory.events["zero"]
    np.testing.assert_allclose(record.times, expected, rtol=0, atol=accuracy)
    assert record.states.shape == (2, len(expected))
    # the recorded states are on the event surface (to the interpolant's accuracy)
    assert np.max(np.abs(record.states[0])) < max(1e-12, accuracy)
    assert trajectory.status == "success"
    assert trajectory.t[-1] == T_END


@pytest.mark.parametrize(("method", "settings", "accuracy"), METHODS, ids=IDS)
def test_a_terminal_event_stops_the_run_at_its_first_occurrence(method, settings, accuracy):
    upward = crossing_zero(direction=1, terminal=True, name="up")
    turning = Event(lambda t, y, p: y[1], name="turning")  # x' = 0: tan 2t = 1/4
    trajectory = simulate(
        systems.oscillator(),
        t_end=T_END,
        method=method,
        events=[upward, turning],
        n_out=50,
        **settings,
    )
    assert trajectory.status == "event"
    assert trajectory.events["up"].times == pytest.approx([UP[0]], abs=accuracy)
    turns = (np.arctan(0.25) + np.pi * np.arange(2)) / 2  # the third is after the stop
    np.testing.assert_allclose(trajectory.events["turning"].times, turns, atol=accuracy)
    # the last output is the state where it stopped; the earlier outputs are the grid's
    assert trajectory.t[-1] == trajectory.events["up"].times[0]
    assert trajectory.final_state["x"] == pytest.approx(0.0, abs=max(1e-12, accuracy))
    grid = np.linspace(0.0, T_END, 50)
    np.testing.assert_array_equal(trajectory.t[:-1], grid[grid < UP[0]])


@pytest.mark.parametrize("method", ["dop853", "rk4"])
def test_a_zero_at_the_start_is_not_an_occurrence(method):
    # x(0) = 0 moving up: scipy alone would stop at t = 0
    compiled = systems.oscillator()
    start = {"x": 0.0, "x_dot": 1.0}  # x = sin(2t)/2: up again at t = pi
    trajectory = simulate(
        compiled,
        t_end=4.0,
        method=method,
        initial=start,
        events=[crossing_zero(direction=1, terminal=True, name="up")],
        **({"dt": 0.01} if method == "rk4" else {}),
    )
    assert trajectory.status == "event"
    assert trajectory.events["up"].times == pytest.approx([np.pi], abs=1e-8)


def test_events_see_the_parameters():
    # x' = k/8 (= x'(0): not an occurrence at the start), reached again going up
    compiled = systems.oscillator()
    event = Event(lambda t, y, p: y[1] - p[1] / 8, direction=1, terminal=True)  # x' = k/8 = 0.5
    trajectory = simulate(compiled, t_end=10.0, events=[event], params={"k": 4.0})
    assert trajectory.final_state["x_dot"] == pytest.approx(0.5, abs=1e-9)
    assert list(trajectory.events) == ["event1"]


def test_event_names_directions_and_batches_are_checked():
    with pytest.raises(ModelError, match=r"event direction must be -1, 0 or \+1, not 2"):
        Event(lambda t, y, p: y[0], direction=2)
    with pytest.raises(ModelError, match=r"event name must be an identifier, not 'a b'"):
        Event(lambda t, y, p: y[0], name="a b")
    with pytest.raises(ModelError, match=r"two events named 'x'"):
        simulate(systems.oscillator(), t_end=1.0, events=[crossing_zero(name="x")] * 2)
    compiled = systems.oscillator()
    with pytest.raises(ModelError, match="single trajectory"):
        RK4(dt=0.1).solve(
            compiled, (0.0, 1.0), np.zeros((2, 3)), compiled.parameter_vector(),
            events=[crossing_zero()],
        )  # fmt: skip


def test_fixed_step_root_location_is_exact_on_the_interpolant():
    # an event whose root the cubic interpolant holds exactly: a cubic motion
    t0, t1 = 0.0, 0.5
    y0, f0 = np.array([-1.0, 3.0]), np.array([3.0, 0.0])
    y1, f1 = np.array([0.5, 3.0]), np.array([3.0, 0.0])
    # x(t) = -1 + 3 t is linear, so the interpolant is exact and the root is 1/3
    assert hermite(t0, y0, f0, t1, y1, f1, 1 / 3)[0] == pytest.approx(0.0, abs=1e-15)
    values = hermite(t0, y0, f0, t1, y1, f1, np.array([0.0, 0.25, 0.5]))
    np.testing.assert_allclose(values[0], [-1.0, -0.25, 0.5], atol=1e-15)


def test_variational_event_states_lie_on_its_own_motion():
    # event times of a fixed-step run agree with its own grid values to O(h^4)
    compiled = systems.oscillator()
    method = Variational(dt=0.01)
    result = method.solve(
        compiled, (0.0, T_END), compiled.state_vector(), compiled.parameter_vector(),
        events=[crossing_zero(name="zero")],
    )  # fmt: skip
    assert result.status is Status.SUCCESS
    times = result.events[0].times
    for t in times:  # linear interpolation of the grid brackets the root to O(h^2)
        k = np.searchsorted(result.t, t)
        assert result.y[0, k - 1] * result.y[0, k] <= 0

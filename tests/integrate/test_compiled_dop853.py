"""DOP853 with its loop compiled (integrate.compiled_dop853): SciPy's method, SciPy's answers.

Checked against SciPy's DOP853 on the same equations (the same steps up to rounding of the
error estimate, so answers within the tolerance), against analytic solutions (the
pendulum's period by the complete elliptic integral K, one period of a Kepler orbit), and
for the same events, outputs and one-line failures as the SciPy loop.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.integrate import Event, simulate
from lagrangian.integrate.compiled_dop853 import compiled_loop
from lagrangian.integrate.pace import RunPace, RunTooLong
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")

KEPLER = "m*(r_dot**2 + r**2*phi_dot**2)/2 + k*m/r"
SQRT = "x_dot**2/2 - k*sqrt(x)"  # V = k sqrt(x): the force is infinite at x = 0


@functools.cache
def compiled(model: str, backend: str, coordinates: tuple[str, ...] = ()):
    if coordinates:
        system = lg.System.from_lagrangian(model, coordinates=list(coordinates))
    else:
        system = lg.load(model)
    return compile_equations(system.equations_of_motion(), backend=backend)


def states(run) -> np.ndarray:
    """(2n, T): the coordinates and velocities of a trajectory at its times."""
    return np.stack([run[name] for name in (*run.coordinates, *run.velocities)])


def both(model, coordinates=(), **options):
    """(compiled loop, SciPy's loop) runs of the same settings."""
    fast = compiled(model, "numba", coordinates)
    assert compiled_loop(fast) is not None
    return simulate(fast, **options), simulate(compiled(model, "numpy", coordinates), **options)


def test_the_compiled_loop_takes_scipys_steps_and_gives_its_answers():
    ours, scipy = both("double_pendulum", t_end=20.0, initial={"theta1": 0.3, "theta2": 0.2})
    assert ours.status == scipy.status == "success"
    steps, theirs = ours.dataset.attrs["steps"], scipy.dataset.attrs["steps"]
    assert abs(steps - theirs) <= 0.01 * theirs
    assert ours.t[-1] == 20.0
    np.testing.assert_allclose(states(ours)[:, -1], states(scipy)[:, -1], atol=1e-8)
    evaluations = ours.dataset.attrs["rhs_evaluations"]
    assert evaluations == pytest.approx(scipy.dataset.attrs["rhs_evaluations"], rel=0.01)


def test_dense_output_at_given_times_is_scipys():
    times = np.linspace(0.0, 5.0, 41)
    ours, scipy = both("double_pendulum", t_end=5.0, initial={"theta1": 1.0}, t_eval=times)
    assert ours.t.tolist() == times.tolist()
    np.testing.assert_allclose(states(ours), states(scipy), atol=1e-9)


@pytest.mark.parametrize("amplitude", [0.5, 2.0, 3.0])
def test_the_pendulum_period_is_four_sqrt_l_over_g_times_k(amplitude):
    # from rest at theta0 the bob passes theta = 0 downward at T/4 and upward at 3T/4
    period = 4 * np.sqrt(1.0 / 9.81) * ellipk(np.sin(amplitude / 2) ** 2)
    crossings = (
        Event(lambda t, y, p: y[0], direction=-1, name="down"),
        Event(lambda t, y, p: y[0], direction=1, terminal=True, name="up"),
    )
    run = simulate(
        compiled("simple_pendulum", "numba"), t_end=10 * period, initial={"theta": amplitude},
        events=crossings,
    )  # fmt: skip
    assert run.status == "event"
    assert run.events["down"].times.tolist() == pytest.approx([period / 4], rel=1e-9)
    assert run.events["up"].times.tolist() == pytest.approx([3 * period / 4], rel=1e-9)
    assert run.t[-1] == run.events["up"].times[0]


def test_a_kepler_orbit_closes_after_its_period():
    a, e, k = 1.0, 0.5, 1.0
    r0 = a * (1 - e)
    speed = np.sqrt(k / a * (1 + e) / (1 - e))  # at perihelion (vis-viva)
    period = 2 * np.pi * np.sqrt(a**3 / k)
    run = simulate(
        compiled(KEPLER, "numba", ("r", "phi")), t_end=period,
        initial={"r": r0, "phi": 0.0, "phi_dot": speed / r0}, params={"m": 1.0, "k": k},
    )  # fmt: skip
    r, phi, r_dot, phi_dot = states(run)[:, -1]
    assert r == pytest.approx(r0, abs=1e-8)
    assert phi == pytest.approx(2 * np.pi, abs=1e-8)
    assert r_dot == pytest.approx(0.0, abs=1e-7)
    assert phi_dot == pytest.approx(speed / r0, rel=1e-8)


def test_a_terminal_event_stops_where_scipys_does():
    stop = (Event(lambda t, y, p: y[0] - 0.5, direction=-1, terminal=True, name="low"),)
    ours, scipy = both("double_pendulum", t_end=20.0, initial={"theta1": 1.0}, events=stop)
    assert ours.status == scipy.status == "event"
    assert ours.events["low"].times[0] == pytest.approx(scipy.events["low"].times[0], abs=1e-9)
    assert ours.t[-1] == ours.events["low"].times[0]
    assert ours.dataset.attrs["message"] == scipy.dataset.attrs["message"]
    np.testing.assert_allclose(states(ours)[:, -1], states(scipy)[:, -1], atol=1e-9)


def test_events_at_many_steps_are_all_recorded():
    zero = (Event(lambda t, y, p: y[0], name="zero"),)
    ours, scipy = both("simple_pendulum", t_end=50.0, initial={"theta": 1.0}, events=zero)
    assert ours.events["zero"].times.size == scipy.events["zero"].times.size > 20
    np.testing.assert_allclose(ours.events["zero"].times, scipy.events["zero"].times, atol=1e-8)


def test_running_into_an_infinite_force_fails_with_scipys_message():
    # x'' = -1/(2 sqrt x) from x = 1 at rest reaches x = 0 at t = 4 sqrt(2) / 3
    options = {"t_end": 3.0, "initial": {"x": 1.0}, "params": {"k": 1.0}}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ours, scipy = both(SQRT, ("x",), **options)
    assert ours.status == scipy.status == "failed"
    message = ours.dataset.attrs["message"]
    assert message.startswith("the right-hand side is not finite just after t = 1.885")
    assert message.split(" (x = ")[0] == scipy.dataset.attrs["message"].split(" (x = ")[0]
    assert "no step size works" in message
    assert ours.t[-1] == pytest.approx(4 * np.sqrt(2) / 3, abs=1e-4)


def test_a_start_where_the_equations_are_undefined_fails_at_once():
    ours, scipy = both(SQRT, ("x",), t_end=1.0, initial={"x": -1.0}, params={"k": 1.0})
    assert ours.status == "failed"
    assert ours.dataset.attrs["message"] == scipy.dataset.attrs["message"]
    assert ours.t.tolist() == [0.0]


def test_the_time_budget_sees_the_compiled_loop_move():
    system = compiled("double_pendulum", "numba")
    simulate(system, t_end=1.0)  # compiled before the clock starts
    pace = RunPace((0.0, 1e9), 0.05)
    with pytest.raises(RunTooLong):  # two outputs: no steps kept, nothing for memory to refuse
        simulate(system, t_end=1e9, watch=pace, n_out=2)


def test_constrained_systems_run_in_the_loop_with_their_projection():
    # the checks of the motion are tests/integrate/test_constrained_compiled.py's
    system = compiled("cartesian_pendulum", "numba")
    assert system.has_constraints
    loop = compiled_loop(system)
    assert loop is not None and loop.n == 3  # the solve of [q''; lambda]: 2 + 1 unknowns
    assert len(loop.y_prime) == 2  # y' and the projection
    assert len(compiled_loop(compiled("double_pendulum", "numba")).y_prime) == 1


# -- memory: an adaptive run's steps are known only as it goes ---------------------------
CHAOTIC = {"theta1": 2.0, "theta2": 0.5}


def _every_step(available=None, monkeypatch=None, **options):
    from lagrangian.integrate import memory

    if monkeypatch is not None:
        monkeypatch.setattr(memory, "available_memory", lambda: available)
    pendulum = compiled("double_pendulum", "numba")
    return simulate(pendulum, t_end=1000.0, initial=CHAOTIC, **options)


def test_a_run_keeping_every_step_is_refused_once_they_cannot_fit(monkeypatch):
    """The steps kept so far and the latest stretch's pace project the whole run: refused
    when it needs more than is available, run when it needs less (both by a factor 2)."""
    from lagrangian.integrate import memory

    whole = _every_step()
    steps = whole.dataset.attrs["steps"]
    assert steps > 4 * memory.PROJECT_AFTER_STEPS  # projected, then kept on
    needed = memory.run_bytes(4, steps)
    assert _every_step(2 * needed, monkeypatch).dataset.attrs["steps"] == steps
    with pytest.raises(lg.ModelError) as refused:
        _every_step(needed / 2, monkeypatch)
    message = str(refused.value)
    assert message.startswith("dop853 to t_end = 1000 keeping every step (about "), message
    projected = int(message.split("(about ")[1].split(" at the pace")[0].replace(",", ""))
    assert steps / 2 < projected < 2 * steps
    assert message.endswith("give n_out N (N output times), a shorter t_end or a looser rtol")


@pytest.mark.slow  # 2 x 400,000 steps, under tracemalloc: 3-5 s
def test_with_output_times_the_loop_keeps_no_steps():
    """The outputs and the step count are those of the run that kept every step (its last
    step is the state at t_end), and the memory it takes is not the steps': 400,000 steps
    of 4 numbers are 13 MB; the chunks' buffers are 1 MB (NumPy reports to tracemalloc)."""
    import tracemalloc

    pendulum = compiled("double_pendulum", "numba")
    options = {"t_end": 10_000.0, "initial": CHAOTIC}
    whole = simulate(pendulum, **options)
    steps = whole.dataset.attrs["steps"]
    tracemalloc.start()
    try:
        sampled = simulate(pendulum, n_out=200, **options)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert sampled.t.shape == (200,)
    assert sampled.dataset.attrs["steps"] == steps
    np.testing.assert_array_equal(states(sampled)[:, -1], states(whole)[:, -1])
    assert peak < 8 * 4 * steps / 2, (peak, steps)

"""The taylor method's propagation in chunks (issue 36): the same answers as heyoka run by
hand, on systems the project does not ship, without Python per step."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.integrate import taylor_propagate
from lagrangian.integrate.taylor import Taylor
from lagrangian.numeric import compile_equations

hy = pytest.importorskip("heyoka")

K, R0, W0 = 1.5, 1.0, 1.4  # Kepler: k/r potential, periapsis r0, angular rate there


def kepler():
    system = lg.System.from_lagrangian(
        "(r_dot**2 + r**2*phi_dot**2)/2 + k/r", coordinates=["r", "phi"], parameters={"k": K}
    )
    return compile_equations(system.equations_of_motion())


def kepler_by_hand(tol):
    """heyoka's integrator of the same orbit, its equations written by hand."""
    r, phi, vr, vphi = hy.make_vars("r", "phi", "vr", "vphi")
    equations = [
        (r, vr), (phi, vphi), (vr, r * vphi**2 - K / r**2), (vphi, -2.0 * vr * vphi / r)
    ]  # fmt: skip
    return hy.taylor_adaptive(equations, [R0, 0.0, 0.0, W0], tol=tol)


def duffing():
    """x'' + d x' + a x + b x^3 = G cos(w t): damped and driven (time in the equations)."""
    system = lg.System.from_lagrangian(
        "x_dot**2/2 - a*x**2/2 - b*x**4/4",
        coordinates=["x"],
        parameters={"a": -1.0, "b": 1.0, "d": 0.3, "G": 0.5, "w": 1.2},
        forces={"x": "-d*x_dot + G*cos(w*t)"},
    )
    return compile_equations(system.equations_of_motion())


def duffing_by_hand(tol):
    x, v = hy.make_vars("x", "v")
    force = -0.3 * v + 0.5 * hy.cos(1.2 * hy.time) + x - x**3
    return hy.taylor_adaptive([(x, v), (v, force)], [0.5, 0.0], tol=tol)


def test_kepler_outputs_lie_on_the_analytic_ellipse():
    compiled = kepler()
    y0 = np.array([R0, 0.0, 0.0, W0])
    result = Taylor(tol=1e-15).solve(compiled, (0.0, 60.0), y0, compiled.parameter_vector())
    assert result.success and result.steps > 100
    r, phi = result.y[0], result.y[1]
    h = R0**2 * W0  # angular momentum per mass
    p = h**2 / K  # semi-latus rectum; e from r(0) = p / (1 + e) at periapsis
    e = p / R0 - 1
    np.testing.assert_allclose(r * (1 + e * np.cos(phi)), p, rtol=1e-12)
    np.testing.assert_allclose(r**2 * result.y[3], h, rtol=1e-12)


def test_every_step_and_a_grid_equal_heyoka_run_by_hand():
    compiled = kepler()
    y0 = np.array([R0, 0.0, 0.0, W0])
    params = compiled.parameter_vector()
    taylor = Taylor(tol=1e-15)
    steps = taylor.solve(compiled, (0.0, 60.0), y0, params)
    by_hand = kepler_by_hand(1e-15)
    output = by_hand.propagate_until(60.0, c_output=True)[4]
    assert steps.t[-1] == 60.0
    np.testing.assert_allclose(steps.y[:, -1], by_hand.state, rtol=0, atol=1e-12)
    assert abs(steps.steps - (output.times.size - 1)) <= 2  # the same method, rounding aside
    grid = np.linspace(0.0, 60.0, 241)
    on_grid = taylor.solve(compiled, (0.0, 60.0), y0, params, t_eval=grid)
    np.testing.assert_allclose(on_grid.y.T, output(grid), rtol=0, atol=1e-12)


def test_a_driven_damped_duffing_oscillator_equals_heyoka_run_by_hand():
    compiled = duffing()
    grid = np.linspace(0.0, 50.0, 101)
    result = Taylor(tol=1e-14).solve(
        compiled, (0.0, 50.0), [0.5, 0.0], compiled.parameter_vector(), t_eval=grid
    )
    by_hand = duffing_by_hand(1e-14)
    expected = by_hand.propagate_grid(grid)[-1]
    np.testing.assert_allclose(result.y.T, expected, rtol=0, atol=1e-12)


def test_outputs_that_begin_after_the_start_time():
    # heyoka's grid must begin at the integrator's time: this raised ValueError
    compiled = duffing()
    grid = np.linspace(10.0, 50.0, 41)
    result = Taylor(tol=1e-14).solve(
        compiled, (0.0, 50.0), [0.5, 0.0], compiled.parameter_vector(), t_eval=grid
    )
    by_hand = duffing_by_hand(1e-14)
    expected = by_hand.propagate_grid(np.concatenate([[0.0], grid]))[-1][1:]
    np.testing.assert_array_equal(result.t, grid)
    np.testing.assert_allclose(result.y.T, expected, rtol=0, atol=1e-12)


def test_small_chunks_give_the_same_run_and_tell_watch_as_it_goes(monkeypatch):
    compiled = kepler()
    y0, params = np.array([R0, 0.0, 0.0, W0]), compiled.parameter_vector()
    grid = np.linspace(0.0, 60.0, 121)
    whole = Taylor(tol=1e-13).solve(compiled, (0.0, 60.0), y0, params)
    whole_grid = Taylor(tol=1e-13).solve(compiled, (0.0, 60.0), y0, params, t_eval=grid)
    monkeypatch.setattr(taylor_propagate, "FIRST_CHUNK", 7)
    monkeypatch.setattr(taylor_propagate, "CHUNK_SECONDS", 0.0)  # every chunk 7 steps
    seen = []
    chunked = Taylor(tol=1e-13).solve(compiled, (0.0, 60.0), y0, params, watch=seen.append)
    np.testing.assert_array_equal(chunked.t, whole.t)
    np.testing.assert_array_equal(chunked.y, whole.y)
    assert chunked.steps == whole.steps
    assert len(seen) >= whole.steps // 7 and seen == sorted(seen)
    chunked_grid = Taylor(tol=1e-13).solve(compiled, (0.0, 60.0), y0, params, t_eval=grid)
    # heyoka's grid propagation does not take exactly the same steps when it starts
    # again between two output times: equal to rounding, not to the bit
    np.testing.assert_allclose(chunked_grid.y, whole_grid.y, rtol=0, atol=1e-12)


@pytest.mark.parametrize("chunk", [4096, 5])
def test_a_failure_on_a_grid_names_the_last_finite_state(monkeypatch, chunk):
    monkeypatch.setattr(taylor_propagate, "FIRST_CHUNK", chunk)
    monkeypatch.setattr(taylor_propagate, "CHUNK_SECONDS", 0.0)
    system = lg.System.from_lagrangian("x_dot**2/2 - sqrt(x)", coordinates=["x"])
    # x'' = 1/(2 sqrt(x)) < 0 ... x reaches 0 at t = 1.8856 (as in test_taylor's failure)
    grid = np.linspace(0.0, 3.0, 31)
    trajectory = system.simulate(t_end=3.0, method="taylor", initial={"x": 1.0}, t_eval=grid)
    assert trajectory.status == "failed"
    message = trajectory.dataset.attrs["message"]
    assert message.startswith("the state is not finite after t = 1.8856")
    assert "x_dot = -1.4142" in message
    np.testing.assert_array_equal(trajectory["t"], grid[:19])


@pytest.mark.slow  # SciPy's loop at 1e-13 over 10 s: 1.5-4 s
def test_parameters_made_of_parameters_follow_the_values_given():
    # l1*l2*m2, m1 + m2, ... are runtime parameters of their own: a run with other values
    # (after one that built the integrator) must recompute them
    system = lg.load("double_pendulum")
    compiled = compile_equations(system.equations_of_motion())
    y0 = compiled.state_vector({"theta1": 0.3, "theta2": 0.2})
    Taylor(tol=1e-14).solve(compiled, (0.0, 1.0), y0, compiled.parameter_vector())
    values = {"m1": 2.0, "l2": 0.7, "g": 3.7}
    params = compiled.parameter_vector(values)
    taylor = Taylor(tol=1e-14).solve(compiled, (0.0, 10.0), y0, params)
    reference = system.simulate(
        t_end=10.0, method="dop853", rtol=1e-13, atol=1e-13, params=values,
        initial={"theta1": 0.3, "theta2": 0.2},
    )  # fmt: skip
    final = np.array(list(reference.final_state.values()))
    np.testing.assert_allclose(taylor.y[:, -1], final, rtol=0, atol=1e-9)


def chain(links: int) -> lg.System:
    """``links`` unit pendulums hanging one from the other."""
    particles, x, y = [], "0", "0"
    for i in range(1, links + 1):
        x, y = f"{x} + sin(theta{i})", f"{y} - cos(theta{i})"
        particles.append(lg.Particle(f"bob{i}", mass="1", position=[x, y]))
    return lg.System.from_particles(
        coordinates=[f"theta{i}" for i in range(1, links + 1)],
        particles=particles,
        gravity=lg.Gravity(g="g", direction=(0, -1)),
        parameters={"g": 9.81},
    )


@pytest.mark.slow  # the numba system generated for the estimate: 1.5-3 s
def test_the_default_of_a_long_run_of_two_coordinates_is_taylor(monkeypatch):
    # issue 36 item 2: at 1e-10 heyoka takes 0.44 of the compiled DOP853's time, with an
    # error 30x smaller, and starts in 0.3 s against 0.8 s (CPU, benchmarks/taylor_path.py),
    # even where the compiled loop is in the code cache (as here)
    from lagrangian.integrate import choice
    from lagrangian.integrate.choice import choose_run

    monkeypatch.setattr(choice, "compiled_ready", lambda compiled: True)
    monkeypatch.setattr(choice, "method_ready", lambda: True)

    eom = lg.load("double_pendulum").equations_of_motion()
    run = choose_run(
        eom, t_end=1000.0, method=None, backend=None, rtol=1e-10, atol=1e-10,
        initial={"theta1": 0.3, "theta2": 0.2}, params={},
    )  # fmt: skip
    assert run.method == "taylor", run.reason
    assert run.reason.startswith("taylor (heyoka, tol 1e-10): about ")


@pytest.mark.slow  # derives and compiles a 4-link chain, probes its run: 5-20 s
def test_the_default_of_a_long_run_of_a_chain_is_the_compiled_loop():
    # heyoka's compact mode, built for more than two coordinates, takes 3-5x the compiled
    # DOP853's time: over 10^5 time units no start-up makes up for it
    pytest.importorskip("numba")
    from lagrangian.integrate.choice import choose_run

    run = choose_run(
        chain(4).equations_of_motion(), t_end=1e5, method=None, backend=None, rtol=1e-10,
        atol=1e-10, initial={"theta1": 0.1}, params={},
    )  # fmt: skip
    assert (run.method, run.compiled.backend) == ("dop853", "numba"), run.reason
    assert "taylor ~" in run.reason


def test_a_short_run_stays_in_scipys_loop_with_heyoka_installed():
    from lagrangian.integrate.choice import choose_run

    eom = lg.load("double_pendulum").equations_of_motion()
    run = choose_run(
        eom, t_end=20.0, method=None, backend=None, rtol=None, atol=None,
        initial={"theta1": 2.0, "theta2": 0.5}, params={},
    )  # fmt: skip
    assert run.method == "dop853" and run.compiled.backend != "numba"
    assert "too short for a compiled way" in run.reason


# -- events: located on heyoka's continuous output, as the compiled DOP853 locates them ---
DOUBLE = lg.load("double_pendulum").equations_of_motion()


def pendulum_events():
    from lagrangian.integrate import Event

    return [
        Event(lambda t, y, p: y[0], direction=1, name="up"),
        Event(lambda t, y, p: y[1], name="cross"),
    ]


@pytest.mark.slow  # SciPy's loop at 1e-13 over 30 s: 2-6 s
def test_events_match_scipys_loop():
    from lagrangian.integrate import simulate

    compiled = compile_equations(DOUBLE, backend="llvm")
    start = {"theta1": 0.3, "theta2": 0.2}
    tight = {"rtol": 1e-13, "atol": 1e-13, "initial": start, "events": pendulum_events()}
    taylor = simulate(compiled, t_end=30.0, method="taylor", **tight)
    scipy = simulate(compiled, t_end=30.0, method="dop853", **tight)
    assert taylor.status == "success"
    for name in ("up", "cross"):
        ours, theirs = taylor.events[name], scipy.events[name]
        assert ours.times.size == theirs.times.size > 5
        np.testing.assert_allclose(ours.times, theirs.times, rtol=0, atol=1e-11)
        np.testing.assert_allclose(ours.states, theirs.states, rtol=0, atol=1e-10)
    # each crossing lies on its event: theta1 = 0 rising, theta2 = 0
    np.testing.assert_allclose(taylor.events["up"].states[0], 0, atol=1e-14)
    assert np.all(taylor.events["up"].states[2] > 0)
    np.testing.assert_allclose(taylor.events["cross"].states[1], 0, atol=1e-14)


@pytest.mark.parametrize("outputs", [None, np.linspace(0.0, 30.0, 301)])
def test_a_terminal_event_ends_the_run_where_scipys_loop_ends_it(outputs, monkeypatch):
    from lagrangian.integrate import Event, simulate

    monkeypatch.setattr(taylor_propagate, "FIRST_CHUNK", 3)  # over several chunks
    monkeypatch.setattr(taylor_propagate, "CHUNK_SECONDS", 0.0)
    compiled = compile_equations(DOUBLE, backend="llvm")
    stop = [Event(lambda t, y, p: y[0] - 0.25, direction=-1, terminal=True, name="stop")]
    settings = {"rtol": 1e-13, "atol": 1e-13, "events": stop, "t_eval": outputs}
    start = {"theta1": 0.3, "theta2": 0.2}
    taylor = simulate(compiled, t_end=30.0, method="taylor", initial=start, **settings)
    scipy = simulate(compiled, t_end=30.0, method="dop853", initial=start, **settings)
    assert taylor.status == scipy.status == "event"
    assert taylor.dataset.attrs["message"] == scipy.dataset.attrs["message"]
    assert taylor.events["stop"].times.size == 1
    t_stop = taylor.events["stop"].times[0]
    assert abs(t_stop - scipy.events["stop"].times[0]) < 1e-11
    assert taylor["t"][-1] == t_stop and abs(taylor["theta1"][-1] - 0.25) < 1e-14
    if outputs is not None:  # the output times before the event, then the event
        np.testing.assert_array_equal(taylor["t"][:-1], scipy["t"][:-1])
        assert taylor["t"].size == scipy["t"].size
        np.testing.assert_allclose(taylor["theta2"], scipy["theta2"], rtol=0, atol=1e-10)


def test_the_default_of_a_long_run_with_events_is_taylor(monkeypatch):
    from lagrangian.integrate import choice
    from lagrangian.integrate.choice import choose_run

    monkeypatch.setattr(choice, "compiled_ready", lambda compiled: True)
    monkeypatch.setattr(choice, "method_ready", lambda: True)
    run = choose_run(
        lg.load("double_pendulum").equations_of_motion(), t_end=1000.0, method=None,
        backend=None, rtol=1e-10, atol=1e-10, initial={"theta1": 0.3, "theta2": 0.2},
        params={}, events=pendulum_events(),
    )  # fmt: skip
    assert run.method == "taylor", run.reason


def test_a_chunk_holds_at_most_chunk_bytes_of_taylor_coefficients(monkeypatch):
    # a large system's continuous output is 8 (2n) (order + 1) bytes a step: the chunk
    # is bounded by that, below FIRST_CHUNK where it must be
    integrator = kepler_by_hand(1e-13)
    per_step = 8 * 4 * (integrator.order + 1)
    monkeypatch.setattr(taylor_propagate, "CHUNK_BYTES", 64 * per_step)
    asked = []

    class Recording:
        def __getattr__(self, name):
            return getattr(integrator, name)

        def propagate_until(self, t, max_steps, c_output):
            asked.append(max_steps)
            return integrator.propagate_until(t, max_steps=max_steps, c_output=c_output)

    reached = taylor_propagate.propagate(Recording(), 60.0, None, None)
    assert reached.times[-1] == 60.0 and reached.steps > 128
    assert max(asked) == 64 and len(asked) >= reached.steps // 64


def test_an_output_time_given_twice_is_given_twice():
    # heyoka's propagate_grid refuses a repeated time (ValueError, a traceback before)
    compiled = duffing()
    grid = np.array([0.0, 1.0, 1.0, 2.5, 2.5, 4.0])
    result = Taylor(tol=1e-14).solve(
        compiled, (0.0, 4.0), [0.5, 0.0], compiled.parameter_vector(), t_eval=grid
    )
    np.testing.assert_array_equal(result.t, grid)
    expected = duffing_by_hand(1e-14).propagate_grid(np.unique(grid))[-1]
    np.testing.assert_allclose(result.y.T, expected[[0, 1, 1, 2, 2, 3]], rtol=0, atol=1e-12)

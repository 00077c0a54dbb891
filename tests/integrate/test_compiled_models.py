"""The integrators on the built-in examples, through ``compile_equations``.

The same checks as on the hand-written systems, now on the compiled
functions: analytic facts, conservation laws, constraints, batches.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from scipy.special import ellipk

import lagrangian as lg
from lagrangian.integrate import RK4, Event, Variational, simulate
from lagrangian.numeric import compile_equations

from . import systems


@functools.cache
def compiled(name: str):
    return compile_equations(lg.load(name).equations_of_motion())


def test_simple_pendulum_period_matches_the_elliptic_integral():
    theta0, length, g = 1.0, 1.0, 9.81
    period = 4 * np.sqrt(length / g) * ellipk(np.sin(theta0 / 2) ** 2)
    upward = Event(lambda t, y, p: y[0], direction=+1, name="upward")
    trajectory = simulate(
        compiled("simple_pendulum"),
        t_end=4.5 * period,
        rtol=1e-12,
        atol=1e-12,
        events=[upward],
        initial={"theta": theta0},
    )
    times = trajectory.events["upward"].times
    np.testing.assert_allclose(np.diff(times), period, rtol=1e-9)
    assert trajectory.drift("energy") < 1e-10


def test_compiled_pendulum_and_the_hand_written_one_give_the_same_motion():
    mine = simulate(systems.pendulum(), t_end=2.0, method="rk4", dt=0.01)
    theirs = simulate(
        compiled("simple_pendulum"),
        t_end=2.0,
        method="rk4",
        dt=0.01,
        params={"l": 2.0},
        initial={"theta": 1.0},
    )
    np.testing.assert_allclose(theirs["theta"], mine["theta"], rtol=0, atol=1e-12)
    # the energy differs by the constant of the potential: m g l
    np.testing.assert_allclose(theirs["energy"] - mine["energy"], 2.0 * 9.81, atol=1e-11)


def test_spherical_pendulum_p_phi_is_conserved_to_rounding_by_the_variational_method():
    system = compiled("spherical_pendulum")
    assert not system.separable
    trajectory = simulate(system, t_end=5.0, method="variational", dt=0.01)
    assert trajectory.dataset.attrs["scheme"] == "midpoint"
    assert trajectory.drift("p_phi") < 1e-13
    assert trajectory.drift("energy") < 1e-3


def test_central_force_orbit_closes_after_one_kepler_period():
    system = compiled("central_force")  # unit mass, mu = 1, r = 1, theta' = 1.2
    energy = 1.2**2 / 2 - 1.0
    a = -1.0 / (2 * energy)
    period = 2 * np.pi * a**1.5
    trajectory = simulate(system, t_end=period, rtol=1e-12, atol=1e-12)
    final = trajectory.final_state
    assert final["r"] == pytest.approx(1.0, abs=1e-8)
    assert final["r_dot"] == pytest.approx(0.0, abs=1e-8)
    assert final["theta"] == pytest.approx(2 * np.pi, abs=1e-8)
    assert final["theta_dot"] == pytest.approx(1.2, abs=1e-8)
    variational = simulate(system, t_end=period, method="variational", dt=period / 2000)
    assert variational.drift("p_theta") < 1e-13  # theta is cyclic


def test_cartesian_pendulum_stays_on_its_constraint_with_rk4():
    system = compiled("cartesian_pendulum")
    trajectory = simulate(system, t_end=10.0, method="rk4", dt=0.01, n_out=201)
    states = np.array([trajectory[name] for name in ("x", "y", "x_dot", "y_dot")])
    residual = np.array(
        [system.constraint_residual(t, states[:, k], system.parameter_vector())
         for k, t in enumerate(trajectory.t)]
    )  # fmt: skip
    assert np.max(np.abs(residual)) < 1e-8
    assert "lambda1" in trajectory.multipliers
    with pytest.raises(lg.ModelError, match="does not handle constraints"):
        simulate(system, t_end=1.0, method="variational")


def test_double_pendulum_variational_agrees_with_dop853_to_second_order():
    system = compiled("double_pendulum")
    reference = simulate(system, t_end=1.0, rtol=1e-12, atol=1e-12).final_state
    errors = []
    for dt in (0.01, 0.005):
        final = simulate(system, t_end=1.0, method="variational", dt=dt).final_state
        errors.append(max(abs(final[k] - reference[k]) for k in reference))
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.1)  # order 2


@pytest.mark.parametrize("method", [RK4(dt=0.02), Variational(dt=0.02)], ids=["rk4", "variational"])
def test_compiled_batch_is_the_loop_of_single_runs(method):
    system = compiled("double_pendulum")
    params = system.parameter_vector()
    batch = np.array([[2.0, 0.3, -1.0], [0.5, 0.1, 1.0], [0.0, 0.2, 0.0], [0.0, 0.0, -0.5]])
    together = method.solve(system, (0.0, 1.0), batch, params)
    for b in range(batch.shape[1]):
        alone = method.solve(system, (0.0, 1.0), batch[:, b], params)
        np.testing.assert_allclose(together.y[:, b, :], alone.y, rtol=0, atol=1e-13)


EXAMPLES = ["harmonic_oscillator", "vertical_spring", "rotating_wire_bead",
            "planar_particle_forces", "free_particle_spherical", "rolling_disc"]  # fmt: skip
CASES = [
    (name, method)
    for name in EXAMPLES
    for method in ("dop853", "radau", "rk4", "variational")
    if not (name == "rolling_disc" and method == "variational")  # constrained: refused
]


@pytest.mark.parametrize(("name", "method"), CASES)
def test_every_method_runs_every_example(name, method):
    trajectory = simulate(compiled(name), t_end=0.5, method=method, n_out=11)
    assert trajectory.status == "success"
    assert trajectory.t[-1] == 0.5
    assert np.all(np.isfinite(trajectory.dataset.to_array().values))

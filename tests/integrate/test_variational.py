"""The variational integrator: long-time energy behaviour, Noether, batches, failures."""

from __future__ import annotations

import numpy as np
import pytest

from lagrangian.errors import ModelError
from lagrangian.integrate import RK4, Status, Variational, simulate

from . import systems


def _energy_error(compiled, result) -> np.ndarray:
    params = compiled.parameter_vector()
    energy = compiled.energy(0.0, result.y, params)
    return np.abs(energy - energy[0])


@pytest.mark.slow
def test_energy_error_stays_bounded_over_2e4_steps_while_rk4_drifts():
    compiled = systems.pendulum(theta0=1.0)  # omega h = 0.44: a coarse step
    y0, params = compiled.state_vector(), compiled.parameter_vector()
    span = (0.0, 4e3)  # 2e4 steps of 0.2, about 1400 periods
    variational = Variational(dt=0.2).solve(compiled, span, y0, params)
    rk4 = RK4(dt=0.2).solve(compiled, span, y0, params)
    assert variational.steps == rk4.steps == 20_000
    tenth = variational.t.shape[0] // 10
    error = _energy_error(compiled, variational)
    first, last = error[:tenth].max(), error[-tenth:].max()
    assert last <= first * (1 + 1e-6)  # measured: both 0.4089 (4% of |E|), no growth
    rk4_error = _energy_error(compiled, rk4)
    rk4_first, rk4_last = rk4_error[:tenth].max(), rk4_error[-tenth:].max()
    assert rk4_last > 5 * rk4_first  # measured 1.245 -> 7.404: linear drift
    assert rk4_last > 5 * last
    # (1e5 steps of 0.1: 0.1021 bounded against 0.105 -> 1.01, five times the time)


def test_spherical_pendulum_p_phi_is_conserved_to_rounding():
    compiled = systems.spherical_pendulum()  # not separable: the midpoint (Newton) scheme
    # 500 steps (t = 5; it was 20: the same drifts, 1.6e-16 and 3.3e-4, already reached by
    # t = 5; rk4 at this dt loses 1.4e-6 of p_phi by then, dop853 1.1e-10)
    trajectory = simulate(compiled, t_end=5.0, method="variational", dt=0.01)
    assert trajectory.dataset.attrs["scheme"] == "midpoint"
    assert trajectory.drift("p_phi") < 1e-13  # measured 1.6e-16
    assert trajectory.drift("energy") < 1e-3  # measured 3.3e-4, O(h^2), bounded
    dop853 = simulate(compiled, t_end=5.0, method="dop853")
    assert dop853.drift("p_phi") > 1e-12  # not exact for a non-geometric method


def test_separable_systems_use_stormer_verlet_with_one_gradient_per_step():
    compiled = systems.pendulum()
    result = Variational(dt=0.01).solve(
        compiled, (0.0, 1.0), compiled.state_vector(), compiled.parameter_vector()
    )
    assert result.settings["scheme"] == "stormer-verlet"
    assert result.steps == 100
    assert result.rhs_evaluations == 101  # one gradient per step plus the start
    assert result.jacobian_evaluations == 0


def test_midpoint_newton_converges_in_few_iterations():
    compiled = systems.spherical_pendulum()
    result = Variational(dt=0.01).solve(
        compiled, (0.0, 2.0), compiled.state_vector(), compiled.parameter_vector()
    )
    assert result.settings["scheme"] == "midpoint"
    # per step: Jacobians for Newton's method (2 here) and for the velocity (1)
    assert result.jacobian_evaluations <= 4 * result.steps


def test_stormer_verlet_and_midpoint_agree_to_second_order():
    compiled = systems.pendulum()
    y0, params = compiled.state_vector(), compiled.parameter_vector()
    verlet = Variational(dt=1e-3).solve(compiled, (0.0, 1.0), y0, params)
    midpoint = Variational(dt=1e-3, explicit_when_separable=False).solve(
        compiled, (0.0, 1.0), y0, params
    )
    assert midpoint.settings["scheme"] == "midpoint"
    np.testing.assert_allclose(verlet.y[:, -1], midpoint.y[:, -1], atol=1e-5)


@pytest.mark.parametrize(
    "method",
    [RK4(dt=0.05), Variational(dt=0.05), Variational(dt=0.05, explicit_when_separable=False)],
    ids=["rk4", "verlet", "midpoint"],
)
def test_a_batch_is_the_loop_of_single_runs(method):
    compiled = systems.pendulum()
    params = compiled.parameter_vector()
    batch = np.array([[0.3, 1.0, 2.5, -1.2], [0.0, 0.5, -1.0, 2.0]])  # (2n, B)
    together = method.solve(compiled, (0.0, 3.0), batch, params)
    assert together.y.shape == (2, 4, together.t.shape[0])
    for b in range(batch.shape[1]):
        alone = method.solve(compiled, (0.0, 3.0), batch[:, b], params)
        np.testing.assert_allclose(together.y[:, b, :], alone.y, rtol=0, atol=1e-14)


def test_a_batch_of_parameters_is_the_loop_of_single_runs():
    compiled = systems.spherical_pendulum()
    y0 = np.repeat(compiled.state_vector()[:, None], 3, axis=1)
    params = np.array([[1.5, 1.5, 1.5], [0.8, 1.0, 1.2], [9.81, 9.81, 1.62]])  # (P, B)
    together = Variational(dt=0.02).solve(compiled, (0.0, 1.0), y0, params)
    for b in range(3):
        alone = Variational(dt=0.02).solve(compiled, (0.0, 1.0), y0[:, b], params[:, b])
        np.testing.assert_allclose(together.y[:, b, :], alone.y, rtol=0, atol=1e-13)


def test_newton_failure_ends_the_run_with_a_failed_status():
    compiled = systems.spherical_pendulum()
    result = Variational(dt=0.01, max_newton=1).solve(
        compiled, (0.0, 1.0), compiled.state_vector(), compiled.parameter_vector()
    )
    assert result.status is Status.FAILED
    assert not result.success
    assert result.message.startswith(
        "Newton's method for the midpoint velocity did not converge in 1 iterations"
    )
    assert result.message.endswith("at t = 0")
    assert result.t.tolist() == [0.0]  # the last state reached is the last output


def test_variational_refuses_constraints_with_one_clear_error():
    with pytest.raises(ModelError) as error:
        simulate(systems.constrained_pendulum(), t_end=1.0, method="variational")
    assert str(error.value) == (
        "the variational integrator does not handle constraints (lambda1): use rk4, dop853 or radau"
    )


def test_capabilities_are_declared():
    assert (Variational.order, Variational.symplectic, Variational.adaptive) == (2, True, False)
    assert Variational.needs == "lagrangian"
    assert RK4.needs == "first_order"
    assert not RK4.symplectic

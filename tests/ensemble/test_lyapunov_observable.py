"""The ensemble's ``lyapunov`` observable (the variational equations stepped by rk4)."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import ModelError


def oscillator(b: float) -> lg.System:
    return lg.System.from_lagrangian(
        "x_dot**2/2 - x**2/2", coordinates=["x"], forces={"x": "-b*x_dot"}, parameters={"b": b}
    )


def test_a_damped_linear_oscillators_exponent_is_minus_half_the_damping():
    # x'' + b x' + x = 0 (b < 2): every solution decays like exp(-b t / 2), so does every
    # displacement; the rotation adds a bounded factor, O(1 / t) to the estimate
    result = oscillator(0.4).ensemble(
        params={"b": np.array([0.1, 0.4, 1.0])}, t_end=200, dt=0.05, observables="lyapunov"
    )
    np.testing.assert_allclose(result["lyapunov"], [-0.05, -0.2, -0.5], atol=1e-2)


def test_members_equal_single_runs():
    system = lg.load("henon_heiles")
    starts = np.array([-0.25, -0.1])
    together = system.ensemble(initial={"y": starts}, t_end=20, dt=0.01, observables="lyapunov")
    for k, start in enumerate(starts):
        alone = system.ensemble(initial={"y": [start]}, t_end=20, dt=0.01, observables="lyapunov")
        assert together["lyapunov"][k] == pytest.approx(alone["lyapunov"][0], rel=1e-12)


def test_only_the_numpy_path_computes_it():
    with pytest.raises(ModelError, match="observable lyapunov runs on backends numpy and dask"):
        oscillator(0.4).ensemble(t_end=1, backend="numba", observables="lyapunov")
    with pytest.raises(ModelError, match="needs an explicit method"):
        oscillator(0.4).ensemble(t_end=1, method="variational", observables="lyapunov")

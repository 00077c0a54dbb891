"""The fixed step from the motion's time scale (integrate.step_size): analytic solutions
with the default step, refusal past the stability limit, a warning for a coarse step."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.ensemble import run_ensemble
from lagrangian.errors import LagrangianError, ModelError
from lagrangian.integrate import simulate
from lagrangian.integrate.step_size import CoarseStepWarning, motion_rate
from lagrangian.numeric import compile_equations


@pytest.fixture(scope="module")
def oscillator():
    return compile_equations(lg.load("harmonic_oscillator").equations_of_motion())


@pytest.fixture(scope="module")
def pendulum():
    return compile_equations(lg.load("simple_pendulum").equations_of_motion())


# The phase error grows by a fixed amount per radian: rk4 (ω dt)^4/120, variational
# (ω dt)^2/24. The default steps (0.05 and 0.02) give 2.8e-6 and 8.4e-4 at t = 100
# (ensemble of amplitudes up to 2: 5.6e-6, 1.7e-3); the tolerances bound the step as
# tightly as 2e-4 and 0.03 at t = 1000 did (rk4 dt < 0.064, variational dt < 0.022 for
# the ensemble, 0.062 and 0.021 then), with a tenth of the steps: 3.6 s of CPU, not 25 s.
T_END = 100.0
STEP_BOUNDS = [("rk4", 1.5e-5), ("variational", 0.002)]


@pytest.mark.parametrize(("method", "tolerance"), STEP_BOUNDS)
def test_the_oscillator_follows_cos_t_with_the_default_step(oscillator, method, tolerance):
    trajectory = simulate(oscillator, t_end=T_END, method=method, n_out=2)
    assert trajectory.status == "success"
    assert trajectory.dataset.attrs["dt"] < 0.1
    assert abs(float(trajectory.dataset["x"][-1]) - np.cos(T_END)) < tolerance


@pytest.mark.parametrize(("method", "tolerance"), STEP_BOUNDS)
def test_an_ensemble_of_oscillators_follows_a_cos_t(oscillator, method, tolerance):
    amplitudes = np.array([0.5, 1.0, 2.0])
    result = run_ensemble(oscillator, initial={"x": amplitudes}, t_end=T_END, method=method)
    np.testing.assert_allclose(result["final_x"], amplitudes * np.cos(T_END), atol=tolerance)
    assert not result["failed"].any() and result.attrs["failed"] == 0


def test_the_rate_is_the_angular_frequency(oscillator):
    p = oscillator.parameter_vector({"k": 4.0, "m": 1.0})
    y0 = np.array([1.0, 0.0])
    initial, probed = motion_rate(oscillator, 0.0, y0, p, probe_step=0.01, target=0.05)
    assert initial == pytest.approx(2.0, rel=1e-4)
    assert probed == pytest.approx(2.0, rel=1e-3)


def test_the_probe_finds_the_rate_where_the_linearization_is_zero(pendulum):
    # let go at rest from its side, the pendulum's linearization (-g/l cos theta) is zero
    y0 = pendulum.state_vector({"theta": np.pi / 2})
    p = pendulum.parameter_vector()
    initial, probed = motion_rate(pendulum, 0.0, y0, p, probe_step=0.02, target=0.05)
    values = dict(zip(pendulum.parameter_names, p, strict=True))
    assert initial == pytest.approx(0.0, abs=1e-3)
    assert probed > 0.5 * np.sqrt(values["g"] / values["l"])


@pytest.mark.parametrize(("method", "dt"), [("rk4", 2.9), ("variational", 2.0), ("rk4", 10.0)])
def test_a_step_past_the_stability_limit_is_refused(oscillator, method, dt):
    with pytest.raises(ModelError, match=rf"^{method} with dt = {dt:g} is unstable for this "):
        simulate(oscillator, t_end=100.0, method=method, dt=dt)
    with pytest.raises(ModelError, match=rf"^{method} with dt = {dt:g} is unstable for this "):
        run_ensemble(oscillator, initial={"x": [1.0, 2.0]}, t_end=100.0, method=method, dt=dt)


def test_a_coarse_step_is_one_warning(oscillator):
    with pytest.warns(CoarseStepWarning, match=r"^dt = 0\.5 is coarse for this motion: ω·dt"):
        simulate(oscillator, t_end=10.0, method="rk4", dt=0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        simulate(oscillator, t_end=10.0, method="rk4", dt=0.05)


def test_members_that_fail_are_counted_and_all_failing_is_an_error():
    system = lg.System.from_lagrangian("x_dot**2/2 - k*sqrt(x)", coordinates=["x"])
    compiled = compile_equations(system.equations_of_motion())
    # from x = 1 at rest the motion reaches x = 0 (and sqrt of a negative x) at t = 1.89
    with pytest.warns(lg.errors.LagrangianWarning, match=r"^1 of 3 members failed"):
        result = run_ensemble(
            compiled, initial={"x": [1.0, 10.5, 20.0]}, params={"k": 1.0}, t_end=3.0
        )
    assert result["failed"].tolist() == [True, False, False]
    with pytest.raises(LagrangianError, match=r"^the ensemble integration failed for all 2 "):
        run_ensemble(compiled, initial={"x": [0.5, 1.0]}, params={"k": 1.0}, t_end=3.0)

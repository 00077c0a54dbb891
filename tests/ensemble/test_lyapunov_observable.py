"""The ensemble's ``lyapunov`` observable (the variational equations stepped by rk4)."""

from __future__ import annotations

import importlib.util
import math
import warnings

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.integrate.step_size import CoarseStepWarning


def oscillator(b: float) -> lg.System:
    return lg.System.from_lagrangian(
        "x_dot**2/2 - x**2/2", coordinates=["x"], forces={"x": "-b*x_dot"}, parameters={"b": b}
    )


@pytest.mark.slow
def test_a_damped_linear_oscillators_exponent_is_minus_half_the_damping():
    # x'' + b x' + x = 0 (b < 2): every solution decays like exp(-b t / 2), so does every
    # displacement; the rotation adds a bounded factor, O(1 / t) to the estimate, so the
    # run stays long (t = 200: errors 2e-4, 9e-4, 7e-4; at t = 100 already 5e-3 for b = 1).
    # The step is ω·dt = 0.1, not the default 0.05: rk4's error in the stretch per step,
    # (ω dt)^5 / 120 ~ 1e-7, moves the exponents by < 1e-6 (they agree with dt = 0.05's to
    # 1e-6), at half the steps, so the coarse-step warning is silenced here
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoarseStepWarning)
        result = oscillator(0.4).ensemble(
            params={"b": np.array([0.1, 0.4, 1.0])}, t_end=200, dt=0.1, observables="lyapunov"
        )
    np.testing.assert_allclose(result["lyapunov"], [-0.05, -0.2, -0.5], atol=1e-2)


@pytest.mark.slow
def test_members_equal_single_runs():
    system = lg.load("henon_heiles")
    starts = np.array([-0.25, -0.1])
    # w is renormalised after every step, so 200 steps are 200 chances for one member's
    # stretch to leak into another's; the two members' exponents differ (0.18 and 0.13)
    together = system.ensemble(initial={"y": starts}, t_end=2, dt=0.01, observables="lyapunov")
    assert together["lyapunov"][0] != pytest.approx(together["lyapunov"][1], rel=0.1)
    for k, start in enumerate(starts):
        alone = system.ensemble(initial={"y": [start]}, t_end=2, dt=0.01, observables="lyapunov")
        assert together["lyapunov"][k] == pytest.approx(alone["lyapunov"][0], rel=1e-12)


def ueda() -> lg.System:
    # Ueda's oscillator, x'' + k x' + x^3 = B cos t: a Lagrangian with a force
    return lg.System.from_lagrangian(
        "x_dot**2/2 - x**4/4", coordinates=["x"], forces={"x": "B*cos(t) - k*x_dot"},
        parameters={"k": 0.05, "B": 7.5},
    )  # fmt: skip


@pytest.mark.slow
def test_the_ueda_attractors_largest_exponent_is_the_published_one():
    # Y. Ueda, "Randomly transitional phenomena in the system governed by Duffing's
    # equation", J. Stat. Phys. 20 (1979) 181-196, at k = 0.05, B = 7.5: Lyapunov exponents
    # 0.0999, 0, -0.1499 (base e; the 0 is the time direction, which this 2-D state
    # leaves out), as tabulated, with J. C. Sprott, "Chaos and Time-Series Analysis"
    # (Oxford, 2003) pp. 182-183 and 429 as source, at
    # https://sites.google.com/view/lyapunov-spectrum/home/duffing_eqs (RK4, step 0.001).
    # One orbit's estimate scatters by +-5 % over 3000 time units (ours: 0.096 and 0.107
    # from x = 1 and 2, DOP853), so the exponent is the mean over 16 orbits of 200 drive
    # periods each, started on the attractor (after 20 periods): its own standard error
    # is 2 %; long runs gave 0.1037 (one orbit, t = 5000) and 0.1036 +- 0.0012 (32 orbits
    # of 300 periods), 4 % above the published digits. An independent check (a plain
    # RK4 in numba, h = 0.005, t = 1e5 after 1000 of transient, 4 starts x = 2.5, 0.1, 1,
    # -1.5; not this package's code) gave 0.1029, 0.1046, 0.1035, 0.1039: the published
    # 0.0999 is itself about 4 % low (its run length is not stated). The 16-orbit mean of
    # 200 periods moved with the rounding of the machine's libraries (chaotic orbits) to
    # 0.1079, 4 % above the long runs, on 2026-11-29 with the same code: the mean is now
    # over 32 orbits of 300 periods (0.1039 +- 0.0013 there; 64 of 600 gave 0.1034 +-
    # 0.0006), held to the independent runs' 0.1037 within 5 % (about 4 standard errors)
    # and to the published digits within 7 %.
    # The exponents are stepped by numba's compiled loop where it is installed: the numpy
    # backend's steps to rounding (test_compiled_backends_give_the_numpy_backends_values,
    # whose compile of this loop it shares), 960,000 member-steps in about 0.5 s, not 100 s of CPU.
    period = 2 * math.pi
    system, dt = ueda(), period / 100
    settle = system.ensemble(initial={"x": np.linspace(0.5, 2.5, 32)}, t_end=20 * period, dt=dt)
    on_attractor = {"x": np.asarray(settle["final_x"]), "x_dot": np.asarray(settle["final_x_dot"])}
    fast = "numba" if importlib.util.find_spec("numba") else "numpy"
    result = system.ensemble(
        initial=on_attractor, t_end=300 * period, dt=dt, observables="lyapunov", backend=fast
    )
    assert result.attrs["backend"] == fast
    exponents = np.asarray(result["lyapunov"])
    assert np.all(exponents > 0.05)  # every orbit on the chaotic attractor
    assert exponents.mean() == pytest.approx(0.1037, rel=0.05)
    assert exponents.mean() == pytest.approx(0.0999, rel=0.07)


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["numba", "jax"])
def test_compiled_backends_give_the_numpy_backends_values(backend):
    # the variational equations printed for numba (codegen.schemes' ``tangent``, the
    # scheme rk4-tangent), or JAX's traced Jacobian in its jitted loop, against the numpy
    # backend's TangentFlow: the same rk4 steps, so the same exponents to rounding, for
    # a nonlinear system with a varied parameter
    pytest.importorskip(backend)
    system = ueda()
    settings = {
        "initial": {"x": np.array([0.5, 1.0, 2.0])}, "params": {"B": np.array([7.5, 5.0, 9.0])},
        "t_end": 30.0, "dt": 0.02, "observables": ("lyapunov", "final_state"),
    }  # fmt: skip
    numpy = system.ensemble(backend="numpy", **settings)
    theirs = system.ensemble(backend=backend, **settings)
    np.testing.assert_allclose(theirs["lyapunov"], numpy["lyapunov"], rtol=1e-9)
    np.testing.assert_allclose(theirs["final_x"], numpy["final_x"], rtol=1e-9)


def test_backends_without_it_and_implicit_methods_are_refused():
    with pytest.raises(ModelError, match="observable lyapunov runs on backends numpy, numba"):
        oscillator(0.4).ensemble(t_end=1, backend="cuda", observables="lyapunov")
    with pytest.raises(ModelError, match="needs an explicit method"):
        oscillator(0.4).ensemble(t_end=1, method="variational", observables="lyapunov")
    for backend in ("numba", "jax"):
        with pytest.raises(ModelError, match="needs an explicit method"):
            oscillator(0.4).ensemble(
                t_end=1, method="variational", backend=backend, observables="lyapunov"
            )

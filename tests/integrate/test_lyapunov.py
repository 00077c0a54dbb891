"""Lyapunov exponents (integrate/lyapunov.py) against independent facts about the spectrum."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.integrate.lyapunov import lyapunov_spectrum
from lagrangian.numeric import compile_equations


def test_hamiltonian_spectrum_comes_in_pairs_summing_to_zero_with_two_near_zero():
    # Henon-Heiles at E = 1/8 from the chaotic sea: an autonomous Hamiltonian flow, so
    # lambda = (l, 0, -0, -l): the symplectic pairing and the flow and energy directions.
    # The near-zero pair falls like 1/t; after t ~ 300 the orbit depends on rounding (two
    # correct integrations part), and at t = 500 it is 0.005-0.0104 by tolerance and
    # loop (SciPy's or the compiled one), at t = 1000 0.003-0.0053: so t = 1000.
    spectrum = lg.load("henon_heiles").lyapunov(t_end=1000, interval=2.0, rtol=1e-8, atol=1e-10)
    first, second, third, fourth = spectrum.exponents
    assert first > 0.02  # chaotic
    assert abs(first + fourth) < 1e-2 and abs(second + third) < 1e-2
    assert abs(second) < 1e-2 and abs(third) < 1e-2
    assert abs(spectrum.exponents.sum()) < 1e-6
    assert list(spectrum.exponents) == sorted(spectrum.exponents, reverse=True)


def test_damped_spectrum_sums_to_the_divergence_of_the_flow():
    # m l^2 theta'' = -b theta' - m g l sin(theta) + A cos(omega t): div = -b / (m l^2)
    m, length, b = 2.0, 0.7, 0.3
    spectrum = lg.load("driven_damped_pendulum").lyapunov(
        t_end=60, transient=10, params={"m": m, "l": length, "b": b, "A": 1.5 * m * length**2}
    )
    assert spectrum.exponents.sum() == pytest.approx(-b / (m * length**2), abs=1e-3)


def _benettin_logs(t_end: float, transient: float) -> np.ndarray:
    """The summed log-stretches, after each unit of time, of the distance of two nearby
    motions of the Baker-Gollub pendulum (Benettin et al., Phys. Rev. A 14 (1976) 2338):
    the equation written here by hand, the distance renormalised to d0 every time."""
    b, drive, omega = 0.5, 1.5, 2.0 / 3.0

    def rhs(t, y):
        theta, speed = y
        return [speed, -b * speed - math.sin(theta) + drive * math.cos(omega * t)]

    def advance(t0, t1, y):
        return solve_ivp(rhs, (t0, t1), y, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]

    reference = advance(0.0, transient, np.array([0.2, 0.0]))
    d0 = 1e-8
    other = reference + d0 * np.array([1.0, 1.0]) / math.sqrt(2)
    logs = []
    for k in range(round(t_end)):
        t = transient + k
        reference, other = advance(t, t + 1, reference), advance(t, t + 1, other)
        distance = np.linalg.norm(other - reference)
        logs.append(math.log(distance / d0))
        other = reference + (other - reference) * (d0 / distance)
    return np.cumsum(logs)


def test_largest_exponent_agrees_with_two_nearby_motions():
    # Finite-time exponents of two different chaotic orbits differ by more than 5 % unless
    # averaged for thousands of periods; both methods follow the same orbit here: the
    # same start, tolerances of 1e-12, and a total time (150) after which rounding
    # differences, grown like exp(0.1 t), are still far below the orbit's size.  The
    # rates are compared from t = 20 on, once each displacement has turned into the most
    # stretched direction (its first turn adds O(1) to the sums, whatever the method).
    t_end, transient, settled = 120, 30.0, 20
    ours = lg.load("driven_damped_pendulum").lyapunov(
        t_end=t_end, transient=transient, count=1, rtol=1e-12, atol=1e-12
    )
    assert ours.count == 1
    sums = ours.history[:, 0] * (ours.times - transient)
    rate = (sums[-1] - sums[settled - 1]) / (t_end - settled)
    logs = _benettin_logs(t_end, transient)
    reference = (logs[-1] - logs[settled - 1]) / (t_end - settled)
    assert reference > 0.05  # chaotic: the comparison means something
    assert rate == pytest.approx(reference, rel=0.05)


def test_an_integrable_systems_largest_exponent_decays_towards_zero():
    # one degree of freedom, autonomous: integrable; nearby motions separate linearly
    # (the period depends on the amplitude), so the estimate falls like log(t) / t
    spectrum = lg.load("simple_pendulum").lyapunov(
        t_end=120, initial={"theta": 2.5}, count=1, interval=2.0
    )
    times, estimate = spectrum.times, spectrum.history[:, 0]
    early = estimate[np.searchsorted(times, 12.0)]
    assert spectrum.largest < 0.3 * early
    assert spectrum.largest < 0.08


def test_history_ends_with_the_exponents_and_settings_are_echoed():
    compiled = compile_equations(lg.load("henon_heiles").equations_of_motion())
    spectrum = lyapunov_spectrum(compiled, t_end=3.0, count=2, interval=0.5)
    np.testing.assert_array_equal(spectrum.history[-1], spectrum.exponents)
    np.testing.assert_allclose(spectrum.times, np.arange(1, 7) * 0.5)
    assert spectrum.settings() == {
        "t_end": 3.0, "transient": 0.0, "interval": 0.5, "rtol": 1e-9, "atol": 1e-11
    }  # fmt: skip
    again = lyapunov_spectrum(compiled, t_end=3.0, count=2, interval=0.5)
    np.testing.assert_array_equal(again.exponents, spectrum.exponents)  # repeatable


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (
            {"count": 0},
            "the number of exponents must be from 1 to 4 (twice the coordinates), not 0",
        ),
        ({"transient": -1.0}, "the transient must be a time >= 0, not -1"),
        ({"interval": 0.0}, "interval must be a finite number > 0, not 0.0"),
    ],
)
def test_bad_settings_are_one_line_errors(options, message):
    compiled = compile_equations(lg.load("henon_heiles").equations_of_motion())
    with pytest.raises(ModelError) as error:
        lyapunov_spectrum(compiled, t_end=1.0, **options)
    assert message in str(error.value)


def test_constrained_systems_are_refused():
    with pytest.raises(ModelError, match="constrained systems are not supported"):
        lg.load("cartesian_pendulum").lyapunov(t_end=1.0)

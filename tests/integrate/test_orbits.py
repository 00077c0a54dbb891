"""Periodic orbits of a strobe map (integrate/orbits.py, integrate/floquet.py) against
independent computations: SciPy's solve_ivp of equations written out here, the
variational equations with the Jacobian written out here, finite differences of the map,
Liouville's formula and an analytic steady state."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.integrate import floquet

#: The driven pendulum example: b = 1/2, omega = 2/3 (period 3 pi), m = l = g = 1.
DRIVE, DAMPING = 3 * math.pi, 0.5
#: The drive where its attractor is a period-2 orbit (after the first period doubling)
DOUBLED = 1.07


def _pendulum(t, y, drive):
    return [y[1], drive * math.cos(2 * t / 3) - DAMPING * y[1] - math.sin(y[0])]


def _with_tangents(t, z, drive):
    # the state and the 2 x 2 tangent map, J = [[0, 1], [-cos(theta), -b]] written out
    y, w = z[:2], z[2:].reshape(2, 2)
    jacobian = np.array([[0.0, 1.0], [-math.cos(y[0]), -DAMPING]])
    return np.concatenate([_pendulum(t, y, drive), (jacobian @ w).ravel()])


def _wrapped(angle):
    return (angle + math.pi) % (2 * math.pi) - math.pi


@pytest.fixture(scope="module")
def doubled():
    return lg.load("driven_damped_pendulum").orbits(
        strobe=DRIVE, period=2, params={"A": DOUBLED}, attractor=4
    )


def test_the_period_two_orbit_of_the_driven_pendulum(doubled):
    # from its attractor: one orbit, of period 2, its two points listed once
    (orbit,) = doubled.orbits
    assert orbit.period == 2 and orbit.points.shape == (2, 2)
    assert orbit.stable and orbit.kind == "node"
    assert doubled.names == ("theta", "theta_dot")
    # each point is carried to the other in one period by SciPy (theta modulo 2 pi)
    for j in range(2):
        start, end = orbit.points[:, j], orbit.points[:, (j + 1) % 2]
        run = solve_ivp(
            _pendulum, (0, DRIVE), start, args=(DOUBLED,), method="DOP853", rtol=1e-13,
            atol=1e-13,
        )  # fmt: skip
        assert _wrapped(run.y[0, -1] - end[0]) == pytest.approx(0.0, abs=1e-8)
        assert run.y[1, -1] == pytest.approx(end[1], abs=1e-8)


def test_its_multipliers_against_the_variational_equations_written_out(doubled):
    (orbit,) = doubled.orbits
    z0 = np.concatenate([orbit.points[:, 0], np.eye(2).ravel()])
    run = solve_ivp(
        _with_tangents, (0, 2 * DRIVE), z0, args=(DOUBLED,), method="DOP853", rtol=1e-13,
        atol=1e-14,
    )  # fmt: skip
    monodromy = run.y[2:, -1].reshape(2, 2)
    expected = np.sort(np.linalg.eigvals(monodromy).real)[::-1]
    np.testing.assert_allclose(orbit.multipliers.real, expected, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(orbit.monodromy, monodromy, rtol=1e-8, atol=1e-10)
    # Liouville: det M = exp(integral of div f) = exp(-b 2P / (m l^2)), the damping alone
    assert np.prod(orbit.multipliers).real == pytest.approx(
        math.exp(-DAMPING * 2 * DRIVE), rel=1e-9
    )
    assert abs(orbit.multipliers[0]) < 1  # the period-2 attractor: both inside


def test_its_monodromy_against_finite_differences_of_the_map(doubled):
    (orbit,) = doubled.orbits
    x = orbit.points[:, 0]

    def twice(start):
        run = solve_ivp(
            _pendulum, (0, 2 * DRIVE), start, args=(DOUBLED,), method="DOP853", rtol=1e-13,
            atol=1e-13,
        )  # fmt: skip
        return run.y[:, -1]

    h = 1e-5
    columns = [(twice(x + h * e) - twice(x - h * e)) / (2 * h) for e in np.eye(2)]
    np.testing.assert_allclose(orbit.monodromy, np.column_stack(columns), rtol=1e-5, atol=1e-7)


def test_a_start_on_either_point_gives_the_orbit_once(doubled):
    (orbit,) = doubled.orbits
    search = lg.load("driven_damped_pendulum").orbits(
        strobe=DRIVE, period=2, params={"A": DOUBLED}, attractor=0,
        grid={"theta": orbit.points[0] + 1e-4, "theta_dot": orbit.points[1]},
    )  # fmt: skip
    # the grid's 4 combinations: two start next to its points, two elsewhere
    assert search.starts == 4
    found = [o for o in search.orbits if o.period == 2 and o.stable]
    assert len(found) == 1


def test_a_linear_oscillator_has_its_steady_state_as_a_focus():
    # x'' + b x' + x = A cos(omega t): the steady state x = R cos(omega t - phi) is the one
    # fixed point of the strobe map; M = exp(A P) with eigenvalues exp((-b/2 +- i w) P),
    # w = sqrt(1 - b^2/4): a complex pair inside the unit circle
    b, drive, omega = 0.6, 1.0, 1.3
    system = lg.System.from_lagrangian(
        "x_dot**2/2 - x**2/2", coordinates=["x"], forces={"x": "A*cos(omega*t) - b*x_dot"},
        parameters={"A": drive, "omega": omega, "b": b},
    )  # fmt: skip
    period = 2 * math.pi / omega
    search = system.orbits(strobe=period, period=2, attractor=2, transient=5.0)
    (orbit,) = search.orbits
    amplitude = drive / math.hypot(1 - omega**2, b * omega)
    lag = math.atan2(b * omega, 1 - omega**2)
    np.testing.assert_allclose(
        orbit.points[:, 0], [amplitude * math.cos(lag), amplitude * omega * math.sin(lag)],
        atol=1e-9,
    )  # fmt: skip
    w = math.sqrt(1 - b**2 / 4)
    expected = np.exp((-b / 2 + 1j * w) * period)
    assert orbit.period == 1 and orbit.kind == "focus" and orbit.stable
    pair = sorted([expected, expected.conjugate()], key=lambda m: m.imag)
    found = sorted(orbit.multipliers, key=lambda m: m.imag)
    np.testing.assert_allclose(found, pair, rtol=1e-9)


@pytest.mark.slow
def test_a_hamiltonian_strobe_map_has_multipliers_in_reciprocal_pairs():
    # an undamped driven pendulum: the strobe map keeps areas, det M = mu1 mu2 = 1, and
    # each orbit is elliptic (mu on the unit circle) or a saddle (mu, 1/mu real)
    system = lg.System.from_lagrangian(
        "theta_dot**2/2 + cos(theta)", coordinates=["theta"], forces={"theta": "A*cos(t)"},
        parameters={"A": 0.2},
    )  # fmt: skip
    search = system.orbits(
        strobe=2 * math.pi, period=1, attractor=0,
        grid={"theta": np.linspace(-3, 3, 4), "theta_dot": np.linspace(-0.5, 0.5, 3)},
    )  # fmt: skip
    assert search.orbits
    kinds = set()
    for orbit in search.orbits:
        mu = orbit.multipliers
        assert mu[0] * mu[1] == pytest.approx(1.0, abs=1e-8)
        kinds.add(orbit.kind)
        if orbit.kind == "elliptic":
            np.testing.assert_allclose(abs(mu), 1.0, atol=1e-8)
            assert orbit.stable
    assert kinds <= {"elliptic", "saddle", "flip saddle"} and "elliptic" in kinds


@pytest.mark.parametrize(
    ("multipliers", "kind", "stable"),
    [
        ([0.5, 0.1], "node", True),
        ([2.0, 3.0], "node", False),
        ([2.0, 0.1], "saddle", False),
        ([-2.0, 0.1], "flip saddle", False),
        ([-0.5, 0.1], "flip node", True),
        ([0.3 + 0.4j, 0.3 - 0.4j], "focus", True),
        ([0.6 + 0.8j, 0.6 - 0.8j], "elliptic", True),
        ([0.3 + 0.4j, 0.3 - 0.4j, 3.0], "saddle-focus", False),
    ],
)
def test_the_kind_and_stability_from_the_multipliers(multipliers, kind, stable):
    values = np.array(multipliers, dtype=complex)
    assert floquet.kind(values) == kind
    assert floquet.is_stable(values) == stable


def test_multipliers_in_json():
    assert floquet.as_json(np.array([0.5 + 0.0j, 0.3 + 0.4j])) == [0.5, [0.3, 0.4]]


def test_a_strobe_that_is_not_the_drive_period_is_refused():
    with pytest.raises(
        ModelError, match=r"^the equations are not periodic in t with the strobe period 5 "
    ):
        lg.load("driven_damped_pendulum").orbits(strobe=5.0, period=1, attractor=1)


@pytest.mark.parametrize("period", [0, 1.5, 65])
def test_a_bad_period_is_refused(period):
    with pytest.raises(ModelError, match=r"^the period must be a whole number from 1 to 64, not "):
        lg.load("driven_damped_pendulum").orbits(strobe=DRIVE, period=period, attractor=1)

"""Continuation of periodic orbits in a parameter (integrate/continuation.py, arclength.py,
branch_points.py, parameter_map.py) against independent computations: Newton's method
on the strobe map written out here (SciPy's solve_ivp of equations written out here,
finite-difference Jacobians), the brute-force bifurcation diagram, the harmonic balance
of the Duffing oscillator, and Mathieu's characteristic values (scipy.special) for the
parametrically driven pendulum, a model that is not among the examples."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve
from scipy.special import mathieu_b

import lagrangian as lg
from lagrangian.errors import ModelError

#: The driven pendulum example: b = 1/2, omega = 2/3 (period 3 pi), m = l = g = 1.
DRIVE, DAMPING = 3 * math.pi, 0.5

#: Duffing's oscillator w^2 x'' + d w x' + x + c x^3 = F cos(t): x'' + d x' + x + c x^3 =
#: F cos(w t) in the drive's phase t -> w t, so that the strobe (2 pi) does not move
#: with the drive's frequency w, the parameter followed.
DUFFING = """
name = "Duffing oscillator in the drive's phase"
coordinates = ["x"]
kinetic = "w^2*x_dot^2/2"
potential = "x^2/2 + c*x^4/4"

[parameters]
w = 0.9
c = 0.3
d = 0.1
F = 0.12

[forces]
x = "F*cos(t) - d*w*x_dot"

[initial]
x = 0.1
"""
C, D, F = 0.3, 0.1, 0.12

#: A pendulum whose pivot is shaken up and down: g_eff = 1 + h cos(nu t), no damping.
PARAMETRIC = """
name = "Parametrically driven pendulum"
coordinates = ["theta"]
kinetic = "theta_dot^2/2"
potential = "-(1 + h*cos(nu*t))*cos(theta)"

[parameters]
h = 0.05
nu = 2.1

[initial]
theta = 0.0
"""
NU = 2.1


def _map(rhs, x, period, *args):
    """The strobe map from t = 0 by SciPy's DOP853, tight tolerances."""
    solution = solve_ivp(rhs, (0.0, period), x, args=args, method="DOP853", rtol=1e-12,
                         atol=1e-12)  # fmt: skip
    return solution.y[:, -1]


def _jacobian(function, x, step=1e-6):
    """Central differences of ``function`` at x."""
    columns = []
    for k in range(len(x)):
        e = np.zeros(len(x))
        e[k] = step
        columns.append((function(x + e) - function(x - e)) / (2 * step))
    return np.column_stack(columns)


def _fixed_point(function, x, iterations=12):
    """Newton's method on function(x) = x with finite-difference Jacobians."""
    for _ in range(iterations):
        residual = function(x) - x
        if np.max(np.abs(residual)) < 1e-11:
            break
        x = x - np.linalg.solve(_jacobian(function, x) - np.eye(len(x)), residual)
    return x


def _pendulum(t, y, drive):
    return [y[1], drive * math.cos(2 * t / 3) - DAMPING * y[1] - math.sin(y[0])]


def _wrapped(angle):
    return (angle + math.pi) % (2 * math.pi) - math.pi


@pytest.fixture(scope="module")
def pendulum():
    return lg.load("driven_damped_pendulum")


@pytest.fixture(scope="module")
def cascade(pendulum):
    """The driven pendulum's orbit of period 1 at A = 1.05 followed to 1.081, with two
    doublings."""
    return pendulum.continuation(
        vary={"A": (1.05, 1.081, 32)}, strobe=DRIVE, attractor=3, max_doublings=2
    )


def _doublings(continuation):
    """The period doublings, by the period of the branch they are on."""
    return {
        branch.period: [b.value for b in branch.bifurcations if b.kind == "period doubling"]
        for branch in continuation.branches
    }


@pytest.mark.slow
def test_the_driven_pendulums_period_doublings_against_newton_on_the_map(cascade):
    # branches of periods 1, 2 and 4, each doubled from the one before at its doubling
    assert [(b.period, b.parent) for b in cascade.branches] == [(1, None), (2, 0), (4, 1)]
    doublings = _doublings(cascade)
    assert len(doublings[1]) == 1 and len(doublings[2]) == 1
    # independently: Newton's method on the K-fold map of the equations written out here,
    # the multipliers from a finite-difference Jacobian, and the drive where det(M + I) = 0
    # by the secant method
    for period, located in ((1, doublings[1][0]), (2, doublings[2][0])):
        bifurcation = next(b for b in cascade.branches[period // 2].bifurcations)
        guess = bifurcation.points[:, 0]

        def flip(drive, period=period, guess=guess):
            def strobe(x):  # theta modulo 2 pi: the orbit may turn over
                y = _map(_pendulum, x, period * DRIVE, drive)
                return np.array([x[0] + _wrapped(y[0] - x[0]), y[1]])

            x = _fixed_point(strobe, guess)
            return np.linalg.det(_jacobian(strobe, x) + np.eye(2))

        exact = brentq(flip, located - 2e-4, located + 2e-4, xtol=1e-10)
        assert located == pytest.approx(exact, abs=1e-7)
    # the multipliers there: one -1, and the determinant of Liouville's formula
    first = cascade.branches[0].bifurcations[0]
    assert np.min(np.abs(first.multipliers + 1)) < 1e-6
    assert np.prod(first.multipliers).real == pytest.approx(math.exp(-DAMPING * DRIVE), 1e-8)
    # stability: the period-1 orbit is stable before its doubling and not after
    below = [p.stable for p in cascade.branches[0].points if p.value < doublings[1][0] - 1e-4]
    above = [p.stable for p in cascade.branches[0].points if p.value > doublings[1][0] + 1e-4]
    assert all(below) and not any(above)


@pytest.mark.slow
def test_the_doublings_are_where_the_brute_force_diagram_shows_them(pendulum, cascade):
    # the diagram's motions from theta = 0.2 end on the followed orbit or on its mirror
    # image (theta, theta', t) -> (-theta, -theta', t + 3 pi / 2) (the equation is unchanged),
    # which has the same multipliers, so doubles at the same drives: at each drive the
    # diagram shows the number of points the continuation says, 2 ** (doublings below it)
    doublings = _doublings(cascade)
    first, second = doublings[1][0], doublings[2][0]
    values = np.linspace(1.056, 1.080, 25)
    diagram = pendulum.bifurcation(
        vary={"A": values}, variable="theta_dot", period=DRIVE, transient=400 * DRIVE,
        samples=8, steps_per_period=100, backend="numpy",
    )  # fmt: skip
    compared = 0
    for value, points in zip(diagram.values, diagram.points, strict=True):
        if min(abs(value - first), abs(value - second)) < 1.2e-3:
            continue  # too near a doubling for the transient to have died out
        ordered = np.sort(points)
        distinct = 1 + int(np.count_nonzero(np.diff(ordered) > 1e-3))
        expected = 1 if value < first else 2 if value < second else 4
        assert distinct == expected, (value, points)
        compared += 1
    assert compared >= 18


@pytest.mark.slow
def test_at_the_opposite_phase_the_mirror_orbit_doubles_at_the_same_drive(pendulum, cascade):
    # theta -> -theta, t -> t + 3 pi / 2 leaves the equation unchanged, so the mirror image
    # S x = (-theta, -theta') of an orbit of the map at phase 3 pi / 2 is an orbit of the
    # map at phase 0, with the same multipliers: the same doubling
    half = pendulum.continuation(
        vary={"A": (1.05, 1.07, 11)}, strobe=DRIVE, phase=DRIVE / 2, attractor=3,
        max_doublings=0,
    )  # fmt: skip
    (branch,) = half.branches
    (doubling,) = branch.bifurcations
    assert half.strobe.phase == DRIVE / 2
    assert doubling.value == pytest.approx(cascade.branches[0].bifurcations[0].value, abs=1e-8)
    mirrored = -doubling.points[:, 0]
    after = _map(_pendulum, mirrored, DRIVE, doubling.value)  # from t = 0: the phase-0 map
    assert _wrapped(after[0] - mirrored[0]) == pytest.approx(0.0, abs=1e-7)
    assert after[1] == pytest.approx(mirrored[1], abs=1e-7)


@pytest.mark.slow
def test_a_period_doubling_bubble_is_followed_once(pendulum):
    # past A = 1.4249 the period-2 branch doubles at 1.4598 and again at 1.4886: the period-4
    # orbits born at the first join it again at the second (a bubble), coming back along the
    # same orbits with their points shifted; the branch ends there, closed, and is not
    # followed again from the second doubling
    result = pendulum.continuation(
        vary={"A": (1.42, 1.5, 41)}, strobe=DRIVE, attractor=3, max_doublings=2
    )
    periods = [(branch.period, branch.parent) for branch in result.branches]
    doubled = result.branches[1]
    assert periods[:2] == [(1, None), (2, 0)]
    first, second = [b.value for b in doubled.bifurcations if b.kind == "period doubling"][:2]
    bubbles = [b for b in result.branches if b.period == 4 and b.ended == "closed"]
    assert len(bubbles) == 1
    (bubble,) = bubbles
    values = [point.value for point in bubble.points]
    assert bubble.points[0].value == pytest.approx(first, abs=1e-12)
    assert max(values) == pytest.approx(second, abs=1e-4) and min(values) >= first - 1e-9
    turns = [b.value for b in bubble.bifurcations if b.kind == "fold"]
    # where it joins its parent again, and turns back in A: there the period-2 orbits (as
    # period-4 ones) cross it, the Jacobian is singular, and the turn is located to ~1e-7
    assert turns == [pytest.approx(second, abs=1e-6)]
    # no period-4 branch starts at the second doubling
    assert not any(
        b.period == 4 and abs(b.points[0].value - second) < 1e-6 for b in result.branches
    )


@pytest.fixture(scope="module")
def duffing():
    return lg.loads(DUFFING).continuation(
        vary={"w": (0.9, 1.3, 21)}, strobe=2 * math.pi, attractor=3, max_doublings=0
    )


def _duffing(t, y, w):
    return [y[1], (F * math.cos(t) - D * w * y[1] - y[0] - C * y[0] ** 3) / w**2]


@pytest.mark.slow
def test_the_folds_of_the_duffing_resonance_curve(duffing):
    (branch,) = duffing.branches
    folds = [b for b in branch.bifurcations if b.kind == "fold"]
    assert [b.kind for b in branch.bifurcations] == ["fold", "fold"]
    upper, lower = folds  # the branch climbs the upper curve, turns back, turns again
    assert upper.value > lower.value
    values = [p.value for p in branch.points]
    assert values[0] == 0.9 and values[-1] == 1.3
    # the middle part, between the folds, is an unstable saddle; the rest stable
    stable = [p.stable for p in branch.points]
    changes = sum(a != b for a, b in itertools.pairwise(stable))
    assert stable[0] and stable[-1] and changes == 2
    assert {p.kind for p in branch.points if not p.stable} == {"saddle"}
    # independently: the fixed points with x fixed, solved for (x', w) by Newton's method
    # on the map written out here; w(x) has its extremes at the folds
    for fold in folds:
        x0, v0 = fold.points[:, 0]

        def frequency(x, v0=v0, w0=fold.value):
            def equations(unknowns):
                v, w = unknowns
                return _map(_duffing, np.array([x, v]), 2 * math.pi, w) - [x, v]

            return fsolve(equations, [v0, w0], xtol=1e-13)[1]

        step = 2e-3
        a, b, c = (frequency(x0 + k * step) for k in (-1, 0, 1))
        vertex = b - (c - a) ** 2 / (8 * (a - 2 * b + c))  # the parabola's extreme
        assert fold.value == pytest.approx(vertex, abs=1e-6)
        assert abs(fold.value - b) < 1e-4  # the fold's x is the extreme's too

    # the harmonic balance x = r cos(t - phi): ((1 - w^2 + 3 c r^2 / 4)^2 + (d w)^2) r^2 = F^2,
    # its folds where the derivative in r^2 vanishes too: within 1 % of the exact ones
    def balance(unknowns):
        s, w = unknowns
        detuning = 1 - w**2 + 0.75 * C * s
        return [(detuning**2 + (D * w) ** 2) * s - F**2,
                detuning**2 + (D * w) ** 2 + 1.5 * C * s * detuning]  # fmt: skip

    for fold in folds:
        r = math.hypot(*fold.points[:, 0])  # the amplitude, from x and x' at t = 0 (w ~ 1)
        _, w = fsolve(balance, [r**2, fold.value], xtol=1e-13)
        assert fold.value == pytest.approx(w, rel=1e-2)


@pytest.fixture(scope="module")
def parametric():
    return lg.loads(PARAMETRIC).continuation(
        vary={"h": (0.05, 0.35, 7)}, strobe=2 * math.pi / NU, attractor=1, max_doublings=0
    )


@pytest.mark.slow
def test_the_hanging_pendulum_loses_stability_at_mathieus_tongue(parametric):
    # theta'' + (1 + h cos(nu t)) theta = 0 near theta = 0 is Mathieu's equation
    # y'' + (a - 2 q cos 2s) y = 0 with s = nu t / 2, a = 4 / nu^2, q = -2 h / nu^2: the
    # hanging state turns unstable (a multiplier -1) where a = b_1(|q|), the lower edge of
    # the first tongue
    (branch,) = parametric.branches
    (doubling,) = branch.bifurcations
    assert doubling.kind == "period doubling"
    a = 4 / NU**2
    exact = brentq(lambda h: mathieu_b(1, 2 * h / NU**2) - a, 0.05, 0.35, xtol=1e-12)
    assert doubling.value == pytest.approx(exact, abs=1e-7)
    assert np.allclose(doubling.points, 0.0, atol=1e-12)
    assert np.allclose(doubling.multipliers, -1.0, atol=1e-4)  # a double -1 (a Jordan block)


@pytest.mark.slow
def test_the_multipliers_of_a_hamiltonian_branch_stay_in_reciprocal_pairs(parametric):
    (branch,) = parametric.branches
    assert len(branch.points) >= 7
    for point in branch.points:
        first, second = point.multipliers
        assert abs(first * second - 1) < 1e-9
        if abs(first.imag) > 1e-9:  # on the circle, a conjugate pair: elliptic, stable
            assert abs(abs(first) - 1) < 1e-9 and point.stable
        else:  # real, mu and 1 / mu: a flip saddle past the tongue's edge
            assert point.kind == "flip saddle" and not point.stable


#: van der Pol's oscillator driven off its resonance: x'' - mu (1 - x^2) x' + x = F cos(w t)
VAN_DER_POL = """
name = "Forced van der Pol oscillator"
coordinates = ["x"]
kinetic = "x_dot^2/2"
potential = "x^2/2"

[parameters]
mu = 0.2
F = 0.05
w = 1.15

[forces]
x = "mu*(1 - x^2)*x_dot + F*cos(w*t)"

[initial]
x = 0.1
"""
MU, W = 0.2, 1.15


def _van_der_pol(t, y, force):
    return [y[1], MU * (1 - y[0] ** 2) * y[1] - y[0] + force * math.cos(W * t)]


@pytest.mark.slow
def test_the_forced_van_der_pol_oscillator_locks_at_a_neimark_sacker_point():
    # a weak drive off resonance leaves the self-excited oscillation quasi-periodic: the
    # forced periodic orbit is an unstable focus, a complex pair outside the unit circle;
    # a strong one locks it, the pair inside: the pair crosses the circle once
    result = lg.loads(VAN_DER_POL).continuation(
        vary={"F": (0.05, 0.6, 12)}, strobe=2 * math.pi / W, attractor=3, max_doublings=0
    )
    (branch,) = result.branches
    (torus,) = branch.bifurcations
    assert torus.kind == "Neimark-Sacker"
    assert np.allclose(np.abs(torus.multipliers), 1.0, atol=1e-7)
    assert abs(torus.multipliers[0].imag) > 0.5  # a pair, far from +-1
    assert not branch.points[0].stable and branch.points[-1].stable
    assert branch.points[0].kind == "focus"
    # independently: Newton on the map written out here, the pair's modulus from a
    # finite-difference Jacobian, |mu| = 1 where det M = 1 (M 2 x 2, so |mu|^2 = det M)
    period = 2 * math.pi / W

    def modulus(force):
        def strobe(x):
            return _map(_van_der_pol, x, period, force)

        x = _fixed_point(strobe, torus.points[:, 0])
        return np.linalg.det(_jacobian(strobe, x)) - 1.0

    exact = brentq(modulus, torus.value - 5e-3, torus.value + 5e-3, xtol=1e-10)
    assert torus.value == pytest.approx(exact, abs=1e-7)


@pytest.mark.slow
def test_the_map_by_scipy_is_the_compiled_map(pendulum, monkeypatch):
    # where numba is missing the sensitivities run in SciPy's DOP853: the same map, the
    # same monodromy and parameter column to the tolerances
    from lagrangian.derive import derive
    from lagrangian.integrate import compiled_dop853
    from lagrangian.integrate.parameter_map import ParameterMap
    from lagrangian.integrate.strobe import Strobe
    from lagrangian.numeric import compile_equations

    compiled = compile_equations(derive(pendulum), backend="numpy")
    p = compiled.parameter_vector({"A": 1.07})
    x = np.array([-0.3, 1.9])
    clock = Strobe.of(DRIVE)
    maps = [ParameterMap(compiled, clock, "A", p, np.array([0]), 1e-10, 1e-12)]
    monkeypatch.setattr(compiled_dop853, "loop_applies", lambda compiled: False)
    maps.append(ParameterMap(compiled, clock, "A", p, np.array([0]), 1e-10, 1e-12))
    assert maps[0].loop is not None and maps[1].loop is None
    compiled_value, scipy_value = (strobe_map(x, 1.07, 2) for strobe_map in maps)
    assert np.allclose(compiled_value.points, scipy_value.points, atol=1e-8)
    assert np.allclose(compiled_value.monodromy, scipy_value.monodromy, rtol=1e-6, atol=1e-8)
    assert np.allclose(compiled_value.column, scipy_value.column, rtol=1e-6, atol=1e-8)
    # and both are the map: its points at t = 3 pi and 6 pi by solve_ivp
    by_hand = _map(_pendulum, x, 2 * DRIVE, 1.07)
    assert np.allclose(scipy_value.points[:, 2], by_hand, atol=1e-8)
    # the column is dG^2/dA: central differences of the map written out here
    column = (
        _map(_pendulum, x, 2 * DRIVE, 1.07 + 1e-6) - _map(_pendulum, x, 2 * DRIVE, 1.07 - 1e-6)
    ) / 2e-6
    assert np.allclose(scipy_value.column, column, rtol=1e-5)


@pytest.mark.parametrize(
    ("vary", "text"),
    [
        ({"B": (1.0, 2.0, 5)}, "unknown parameter 'B' (parameters: m, l, g, b, A, omega)"),
        ({"A": (2.0, 1.0, 5)}, "the range's low end (2) must be below its high end (1)"),
        ({"A": (1.0, 1.0, 5)}, "the range's low end (1) must be below its high end (1)"),
        ({"A": (1.0, 2.0, 1)}, "the number of values must be a whole number from 2 to 100,000"),
    ],
)
def test_bad_ranges_are_refused(pendulum, vary, text):
    with pytest.raises(ModelError) as error:
        pendulum.continuation(vary=vary, strobe=DRIVE, attractor=1)
    assert str(error.value) == text


def test_max_doublings_is_checked(pendulum):
    with pytest.raises(ModelError, match="max_doublings must be a whole number from 0 to 8"):
        pendulum.continuation(vary={"A": (1.0, 1.1, 3)}, strobe=DRIVE, max_doublings=9)


@pytest.mark.slow
def test_a_continuation_past_its_time_budget_stops_with_advice(pendulum):
    # CPU seconds, from the first look at the clock: any continuation takes more than 1 ms
    from lagrangian.integrate.pace import RunTooLong

    with pytest.raises(RunTooLong) as error:
        pendulum.continuation(
            vary={"A": (1.05, 1.084, 35)}, strobe=DRIVE, attractor=3, timeout=1e-3
        )
    assert str(error.value).startswith("the run did not finish within 0.001 s: it reached ")
    assert str(error.value).endswith(
        " % of the branches; give a shorter range or fewer values in vary, or allow more "
        "time with timeout"
    )

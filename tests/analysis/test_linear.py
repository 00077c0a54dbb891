"""Linearization and normal modes: closed forms, numbers at the defaults, stability."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import sympy

import lagrangian as lg
from lagrangian.analysis.linear import Stability, linearize
from lagrangian.analysis.modes import ModeAnalysis

EQUAL_DOUBLE_PENDULUM = (
    "m*l**2*theta1_dot**2 + m*l**2*theta2_dot**2/2"
    " + m*l**2*theta1_dot*theta2_dot*cos(theta1 - theta2)"
    " + 2*m*g*l*cos(theta1) + m*g*l*cos(theta2)"
)
#: A charge on a potential hill (V = -k r^2/2) in a magnetic field (b = q B).
HILL = "m*(x_dot**2 + y_dot**2)/2 + b*(x*y_dot - y*x_dot)/2 + k*(x**2 + y**2)/2"


def same(a, b):
    return sympy.simplify(a - b) == 0


def modes(system, at):
    return linearize(system.equations_of_motion(), at).normal_modes()


def test_simple_pendulum_small_oscillations():
    system = lg.load("simple_pendulum")
    m, g, l = (system.symbol(n) for n in ("m", "g", "l"))
    linear = linearize(system.equations_of_motion(), {"theta": 0})
    assert linear.mass == sympy.Matrix([[m * l**2]])
    assert linear.stiffness == sympy.Matrix([[m * g * l]])
    assert linear.damping == sympy.zeros(1, 1)
    result = linear.normal_modes()
    assert result.omega_squared == (g / l,)
    assert result.closed_form and result.stability is Stability.STABLE
    assert same(result.frequencies[0], sympy.sqrt(g / l))
    assert same(result.periods[0], 2 * sympy.pi * sympy.sqrt(l / g))
    upside_down = modes(system, {"theta": sympy.pi})
    assert upside_down.omega_squared == (-g / l,)
    assert upside_down.stability is Stability.UNSTABLE and upside_down.frequencies == ()


def test_equal_double_pendulum_frequencies_and_shapes():
    system = lg.System.from_lagrangian(EQUAL_DOUBLE_PENDULUM, coordinates=["theta1", "theta2"])
    g, l = system.symbol("g"), system.symbol("l")
    result = modes(system, {"theta1": 0, "theta2": 0})
    low, high = result.omega_squared
    assert same(low, (2 - sympy.sqrt(2)) * g / l)
    assert same(high, (2 + sympy.sqrt(2)) * g / l)
    assert result.stability is Stability.STABLE
    # in phase (1, sqrt 2) slow, in opposition (1, -sqrt 2) fast
    assert [list(s) for s in result.shapes] == [[1, sympy.sqrt(2)], [1, -sympy.sqrt(2)]]


def test_double_pendulum_small_angle_equations_match_worked_example():
    system = lg.load("double_pendulum")
    s = system.symbol
    m1, m2, l1, l2, g = (s(n) for n in ("m1", "m2", "l1", "l2", "g"))
    t1, t2, a1, a2 = (s(n) for n in ("theta1", "theta2", "theta1_ddot", "theta2_ddot"))
    worked = [
        (m1 + m2) * l1 * a1 + m2 * l2 * a2 + (m1 + m2) * g * t1,
        l2 * a2 + l1 * a1 + g * t2,
    ]
    linear = linearize(system.equations_of_motion(), {"theta1": 0, "theta2": 0})
    for ours, theirs in zip(linear.equations, worked, strict=True):
        ratio = sympy.simplify(ours / theirs)
        assert not ratio.free_symbols & {t1, t2, a1, a2}, ratio


def test_general_double_pendulum_frequencies_at_the_defaults():
    system = lg.load("double_pendulum")
    result = modes(system, {"theta1": 0, "theta2": 0})
    assert result.closed_form
    values = {p.symbol: p.default for p in system.parameters}
    got = sorted(float(w2.xreplace(values)) for w2 in result.omega_squared)
    g = 9.81  # unit masses and lengths: M = [[2, 1], [1, 1]], K = g diag(2, 1)
    expected = scipy.linalg.eigh(np.diag([2 * g, g]), np.array([[2.0, 1.0], [1.0, 1.0]]))[0]
    np.testing.assert_allclose(got, expected, rtol=1e-9)


def test_vertical_spring_about_its_shifted_equilibrium():
    system = lg.load("vertical_spring")
    m, g, k = (system.symbol(n) for n in ("m", "g", "k"))
    result = modes(system, {"x": m * g / k})
    assert same(result.omega_squared[0], k / m)
    plain_m, plain_g, plain_k = sympy.symbols("m g k")  # symbols are matched by name
    assert modes(system, {"x": plain_m * plain_g / plain_k}) == result


def test_two_masses_between_walls():
    system = lg.System.from_lagrangian(
        "m*(x1_dot**2 + x2_dot**2)/2 - k*(x1**2 + (x2 - x1)**2 + x2**2)/2",
        coordinates=["x1", "x2"],
    )
    k, m = system.symbol("k"), system.symbol("m")
    result = modes(system, {"x1": 0, "x2": 0})
    assert set(result.omega_squared) == {k / m, 3 * k / m}
    shapes = {w2: list(v) for w2, v in zip(result.omega_squared, result.shapes, strict=True)}
    assert shapes == {k / m: [1, 1], 3 * k / m: [1, -1]}


def test_three_unequal_masses_fall_back_to_numbers():
    system = lg.System.from_lagrangian(
        "(m1*x1_dot**2 + m2*x2_dot**2 + m3*x3_dot**2)/2"
        " - k*(x1**2 + (x2 - x1)**2 + (x3 - x2)**2 + x3**2)/2",
        coordinates=["x1", "x2", "x3"],
        parameters={"m1": 1.0, "m2": 2.0, "m3": 3.0, "k": 1.5},
    )
    result = modes(system, {"x1": 0, "x2": 0, "x3": 0})
    assert not result.closed_form and result.stability is Stability.STABLE
    stiffness = 1.5 * np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]])
    expected, vectors = scipy.linalg.eigh(stiffness, np.diag([1.0, 2.0, 3.0]))
    np.testing.assert_allclose([float(w2) for w2 in result.omega_squared], expected, rtol=1e-9)
    for shape, vector in zip(result.shapes, vectors.T, strict=True):
        np.testing.assert_allclose([float(v) for v in shape], vector / vector[0], rtol=1e-9)


def test_a_cubic_that_does_not_split_is_seen_without_the_symbolic_factorization(monkeypatch):
    """Three unequal masses: det(K0 - s M0) is an irreducible cubic, seen at rational values
    of the parameters (ModeAnalysis._beyond_quadratics) before any symbolic determinant;
    three equal ones split into a line and a quadratic, and keep their closed form."""
    unequal = lg.System.from_lagrangian(
        "(m1*x1_dot**2 + m2*x2_dot**2 + m3*x3_dot**2)/2"
        " - (k1*x1**2 + k2*(x2 - x1)**2 + k3*(x3 - x2)**2 + k4*x3**2)/2",
        coordinates=["x1", "x2", "x3"],
        parameters={"m1": 1.0, "m2": 2.0, "m3": 3.0, "k1": 1.0, "k2": 2.0, "k3": 3.0, "k4": 4.0},
    )
    equal = lg.System.from_lagrangian(
        "m*(x1_dot**2 + x2_dot**2 + x3_dot**2)/2"
        " - k*(x1**2 + (x2 - x1)**2 + (x3 - x2)**2 + x3**2)/2",
        coordinates=["x1", "x2", "x3"],
    )
    at = {"x1": 0, "x2": 0, "x3": 0}
    symbolic = []
    original = ModeAnalysis._exact_roots
    monkeypatch.setattr(
        ModeAnalysis, "_exact_roots", lambda self: symbolic.append(1) or original(self)
    )
    result = modes(unequal, at)
    assert not result.closed_form and result.stability is Stability.STABLE
    assert symbolic == []  # decided at the rational values, no symbolic determinant
    k, m = equal.symbol("k"), equal.symbol("m")
    result = modes(equal, at)
    assert result.closed_form and symbolic == [1]
    assert same(sum(result.omega_squared), 6 * k / m)
    assert 2 * k / m in result.omega_squared


def test_neutral_direction_is_marginal():
    system = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2)/2 - k*y**2/2", coordinates=["x", "y"]
    )
    result = modes(system, {"y": 0})  # x is free and may be left out
    k, m = system.symbol("k"), system.symbol("m")
    assert result.omega_squared == (0, k / m)
    assert result.stability is Stability.MARGINAL and result.frequencies == (sympy.sqrt(k / m),)


def test_damped_oscillator_is_asymptotically_stable():
    for options in ({"dissipation": "b*x_dot**2/2"}, {"forces": {"x": "-b*x_dot"}}):
        system = lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"], **options)
        linear = linearize(system.equations_of_motion(), {"x": 0})
        assert linear.damping == sympy.Matrix([[system.symbol("b")]])
        result = linear.normal_modes()
        assert result.stability is Stability.ASYMPTOTICALLY_STABLE
        assert result.omega_squared == (system.symbol("k") / system.symbol("m"),)


def test_negative_damping_is_unstable():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 - k*x**2/2",
        coordinates=["x"],
        forces={"x": "b*x_dot"},
        parameters={"m": 1.0, "k": 1.0, "b": 0.1},
    )
    assert modes(system, {"x": 0}).stability is Stability.UNSTABLE


def test_damping_on_one_of_two_oscillators_leaves_the_other_undamped():
    system = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2)/2 - k*(x**2 + y**2)/2",
        coordinates=["x", "y"],
        dissipation="b*x_dot**2/2",
        parameters={"m": 1.0, "k": 2.0, "b": 0.5},
    )
    assert modes(system, {"x": 0, "y": 0}).stability is Stability.STABLE


@pytest.mark.parametrize(("b", "stable"), [(3.0, True), (1.0, False)])
def test_magnetic_field_stabilises_a_potential_hill(b, stable):
    system = lg.System.from_lagrangian(
        HILL, coordinates=["x", "y"], parameters={"m": 1.0, "k": 1.0, "b": b}
    )
    linear = linearize(system.equations_of_motion(), {"x": 0, "y": 0})
    m, k, bb = (system.symbol(n) for n in ("m", "k", "b"))
    assert linear.stiffness == -k * sympy.eye(2)  # K0 is negative definite
    assert linear.dissipative == sympy.zeros(2, 2)
    assert linear.gyroscopic == sympy.Matrix([[0, -bb], [bb, 0]])
    result = linear.normal_modes()
    low, high = result.omega_squared
    assert same(low * high, k**2 / m**2)  # m^2 s^2 + (2 m k - b^2) s + k^2 = 0
    assert same(low + high, (bb**2 - 2 * k * m) / m**2)
    values = {s: system.parameter_values[s.name] for s in (m, k, bb)}
    numbers = [complex(w2.xreplace(values)) for w2 in result.omega_squared]
    if stable:  # (q B)^2 > 4 m k
        assert result.stability is Stability.STABLE
        assert all(abs(z.imag) < 1e-12 and z.real > 0 for z in numbers)
        assert len(result.frequencies) == 2
    else:
        assert result.stability is Stability.UNSTABLE


def test_circulatory_force_causes_flutter():
    """Q = (-a y, a x) is not a potential force: s = k/m +- i a/m, not real."""
    system = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2)/2 - k*(x**2 + y**2)/2",
        coordinates=["x", "y"],
        forces={"x": "-a*y", "y": "a*x"},
    )
    k, m, a = (system.symbol(n) for n in ("k", "m", "a"))
    result = modes(system, {"x": 0, "y": 0})
    assert set(result.omega_squared) == {(k - sympy.I * a) / m, (k + sympy.I * a) / m}
    assert result.stability is Stability.UNSTABLE


def test_conical_pendulum_frequency_with_a_fixed_momentum():
    """Steady precession at theta0 = pi/3 (reduced spherical pendulum): w^2 = 7 g / (2 l)."""
    from lagrangian.analysis.routh import reduce

    reduced = reduce(lg.load("spherical_pendulum").equations_of_motion()).system
    m, l, g = (reduced.symbol(n) for n in ("m", "l", "g"))
    p = sympy.sqrt(sympy.Rational(9, 8) * m**2 * l**3 * g)  # p^2 cos = m^2 l^3 g sin^4
    result = modes(reduced, {"theta": sympy.pi / 3, "p_phi": p})
    assert same(result.omega_squared[0], sympy.Rational(7, 2) * g / l)
    assert result.stability is Stability.STABLE


def test_errors_name_what_is_wrong():
    eom = lg.load("double_pendulum").equations_of_motion()
    with pytest.raises(lg.ModelError, match="theta2"):
        linearize(eom, {"theta1": 0})
    with pytest.raises(lg.ModelError, match="not an equilibrium"):
        linearize(eom, {"theta1": 0.3, "theta2": 0})
    with pytest.raises(lg.ModelError, match="'phi' is not a coordinate or parameter"):
        linearize(eom, {"theta1": 0, "theta2": 0, "phi": 0})
    with pytest.raises(lg.ModelError, match="expected a number or SymPy"):
        linearize(eom, {"theta1": "0", "theta2": 0})


def test_time_dependent_linearization_is_refused():
    """A pendulum whose support oscillates vertically: at rest at theta = 0, but K0(t)."""
    system = lg.System.from_lagrangian(
        "m*l**2*theta_dot**2/2 + m*l*a*W*sin(W*t)*sin(theta)*theta_dot + m*g*l*cos(theta)",
        coordinates=["theta"],
    )
    with pytest.raises(lg.ModelError, match="explicitly on t"):
        linearize(system.equations_of_motion(), {"theta": 0})

"""Rest points on a constraint surface: the numerical points first, their exact forms from
SymPy within a small budget (analysis/surface_exact.py), each point saying which it is.

Models not in the project, each checked against a derivation that does not go through the
multipliers: a bead on a turning tilted wire (by hand, along the wire) and a two-link chain
whose tip slides on the vertical line through its pivot (V and T along the loop, the loop
solved for the first angle by hand)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import scipy.optimize
import sympy

import lagrangian as lg
from lagrangian.analysis import Stability, analyze
from lagrangian.analysis.constrained import surface_rest_points
from lagrangian.output.analysis import format_analysis

#: The two-link chain: masses at the elbow and at the tip, rods a and b (massless).
CHAIN = {"m1": 1.0, "m2": 0.5, "a": 1.0, "b": 0.7, "g": 9.81}

WIRE = """
name = "Bead on a turning tilted wire"
coordinates = ["x", "z"]
constraints = ["x*cos(alpha) - z*sin(alpha)"]
kinetic = "m*(x_dot^2 + z_dot^2 + Omega^2*x^2)/2"
potential = "m*g*z"

[parameters]
m = 0.2
g = 9.81
Omega = 3.0
alpha = 0.6
"""


def _chain() -> lg.System:
    """A double pendulum of point masses whose tip is held on the vertical line through
    the pivot (x = 0): a closed chain with one degree of freedom."""
    return lg.System.from_particles(
        ["theta1", "theta2"],
        [
            lg.Particle("elbow", "m1", ("a*sin(theta1)", "-a*cos(theta1)")),
            lg.Particle(
                "tip",
                "m2",
                ("a*sin(theta1) + b*sin(theta2)", "-a*cos(theta1) - b*cos(theta2)"),
            ),
        ],
        gravity=lg.Gravity("g"),
        constraints=["a*sin(theta1) + b*sin(theta2)"],
        parameters=CHAIN,
    )


def _along_the_loop(theta2: float, branch: int):
    """(V, the inertia of theta2'^2/2, theta1, dtheta1/dtheta2) of the chain on the branch
    theta1 = asin(-b sin(theta2)/a) (branch 1) or pi minus it (branch -1)."""
    m1, m2, a, b, g = (CHAIN[k] for k in ("m1", "m2", "a", "b", "g"))
    s = -b * math.sin(theta2) / a
    theta1 = math.asin(s) if branch == 1 else math.pi - math.asin(s)
    # a cos(theta1) theta1' = -b cos(theta2) theta2' (the tip stays on x = 0)
    rate = -b * math.cos(theta2) / (a * math.cos(theta1))
    rise = a * math.sin(theta1) * rate + b * math.sin(theta2)  # the tip's y' per theta2'
    inertia = m1 * (a * rate) ** 2 + m2 * rise**2
    potential = -g * ((m1 + m2) * a * math.cos(theta1) + m2 * b * math.cos(theta2))
    return potential, inertia, theta1, rate


def _rest_points_along_the_loop() -> list[tuple[float, float, float, float]]:
    """(theta1, theta2, omega^2, dtheta2/dtheta1) where dV/dtheta2 = 0 on either branch."""
    found = []
    h = 1e-5

    def slope(t, k):
        return (_along_the_loop(t + h, k)[0] - _along_the_loop(t - h, k)[0]) / (2 * h)

    grid = [-math.pi + 2 * math.pi * (i + 0.5) / 720 for i in range(720)]
    for branch in (1, -1):
        for left, right in itertools.pairwise(grid):
            if slope(left, branch) * slope(right, branch) < 0:
                theta2 = scipy.optimize.brentq(lambda t, k=branch: slope(t, k), left, right)
                potential = [_along_the_loop(theta2 + j * 1e-4, branch)[0] for j in (-1, 0, 1)]
                curvature = (potential[0] - 2 * potential[1] + potential[2]) / 1e-8
                _, inertia, theta1, rate = _along_the_loop(theta2, branch)
                found.append((theta1, theta2, curvature / inertia, 1 / rate))
    # theta2 = +-pi sits on the grid's ends: the straight chain with its rods opposed
    return found


def _same_angle(x: float, y: float) -> bool:
    return abs(math.remainder(x - y, 2 * math.pi)) < 1e-6


@pytest.mark.slow
def test_a_chain_gives_its_straight_rest_points_exactly_and_the_others_numerically():
    system = _chain()
    found = surface_rest_points(system.equations_of_motion())
    points = found.points
    m1, m2, a, b, g = (system.symbol(k) for k in ("m1", "m2", "a", "b", "g"))
    exact = {(e.point["theta1"], e.point["theta2"]): e for e in points if not e.numeric}
    # the four straight chains, with their forms in the parameters (SymPy cannot solve the
    # whole system in 30 s; the angles at 0 and pi pinned, the rest is at once)
    assert set(exact) == {(0, 0), (0, sympy.pi), (sympy.pi, 0), (sympy.pi, sympy.pi)}
    hanging = exact[0, 0]
    # by hand: along the loop theta2 = -a theta1/b, T = m1 a^2 theta1'^2/2 (the tip moves
    # vertically only, at second order), V = g ((m1 + m2) a + m2 a^2/b) theta1^2/2
    expected = g * ((m1 + m2) * a + m2 * a**2 / b) / (m1 * a**2)
    assert sympy.simplify(hanging.omega_squared[0] - expected) == 0
    assert list(hanging.modes.shapes[0]) == [1, -a / b]
    assert hanging.modes.stability is Stability.STABLE
    assert hanging.multipliers == {"lambda1": 0}  # the line holds nothing at rest
    assert exact[sympy.pi, sympy.pi].modes.stability is Stability.UNSTABLE
    # every point, exact or numerical, is one of the loop's stationary points of V
    reference = _rest_points_along_the_loop()
    numeric = [e for e in points if e.numeric]
    assert len(numeric) == 4 and len(points) == len(reference) + 2  # theta2 = pi: 2 more
    values = {system.symbol(k): v for k, v in CHAIN.items()}
    for e in points:
        theta1, theta2 = (float(e.point[k].subs(values)) for k in ("theta1", "theta2"))
        twins = [r for r in reference if _same_angle(r[0], theta1) and _same_angle(r[1], theta2)]
        if not twins:
            assert _same_angle(theta2, math.pi) and e in exact.values()
            continue
        (twin,) = twins
        assert float(e.omega_squared[0].subs(values)) == pytest.approx(twin[2], rel=1e-5)
        shape = [float(x.subs(values)) for x in e.modes.shapes[0]]
        assert shape == pytest.approx([1.0, twin[3]], rel=1e-6)


@pytest.mark.slow
def test_the_text_says_which_points_are_numeric():
    text = format_analysis(analyze(_chain().equations_of_motion(), stages=("equilibria",)))
    block = text.split("Equilibria (at rest, staying at rest):")[1].split("\n\n")[0]
    lines = [line for line in block.splitlines() if line.startswith("  θ")]
    assert len(lines) == 8
    assert sum("[numeric, at the default parameter values]" in line for line in lines) == 4
    assert "  θ₁ = 0, θ₂ = 0: stable" in lines


@pytest.mark.slow
def test_sympy_is_given_a_small_budget_the_same_for_every_model(monkeypatch):
    # what SymPy may spend is bounded by the constants, not by the stage's time.  The
    # chain's straight points are pinned whole (the equations vanish with the pins put
    # in: nothing to solve) and its whole system (theta1 and theta2 coupled inside sin:
    # SymPy finds nothing in 30 s) is not tried; the slider-crank's pinned systems get
    # EXACT_SECONDS in all; the wire's whole system (linear in x, z, lambda) is tried for
    # UNPINNED_SECONDS at most
    import lagrangian.analysis.surface_exact as exact

    given = []
    solve = exact.in_child

    def recorded(function, arguments, timeout, **options):
        given.append((len(arguments[1]), timeout))
        return solve(function, arguments, timeout, **options)

    monkeypatch.setattr(exact, "in_child", recorded)
    surface_rest_points(_chain().equations_of_motion(), timeout=60.0)
    assert given == []
    surface_rest_points(lg.load("slider_crank").equations_of_motion(), timeout=60.0)
    assert [unknowns for unknowns, _ in given] == [3, 3]  # x, phi, lambda2 (of 5)
    assert all(t <= exact.EXACT_SECONDS for _, t in given) and given[1][1] < given[0][1]
    given.clear()
    surface_rest_points(lg.loads(WIRE).equations_of_motion(), timeout=60.0)
    assert len(given) == 1 and given[0][0] == 3 and given[0][1] <= exact.UNPINNED_SECONDS


def test_a_bead_on_a_turning_tilted_wire_rests_where_the_hand_derivation_says():
    # no value pinned: SymPy solves the whole (linear) system.  Along the wire
    # (x, z) = s (sin(alpha), cos(alpha)): V_eff = m g s cos(alpha) - m Omega^2 s^2
    # sin(alpha)^2/2, stationary at s = g cos(alpha)/(Omega^2 sin(alpha)^2), a maximum
    system = lg.loads(WIRE)
    (rest,) = surface_rest_points(system.equations_of_motion()).points
    m, g, omega, alpha = (system.symbol(k) for k in ("m", "g", "Omega", "alpha"))
    s = g * sympy.cos(alpha) / (omega**2 * sympy.sin(alpha) ** 2)
    assert not rest.numeric
    assert sympy.simplify(rest.point["x"] - s * sympy.sin(alpha)) == 0
    assert sympy.simplify(rest.point["z"] - s * sympy.cos(alpha)) == 0
    assert sympy.simplify(rest.omega_squared[0] + omega**2 * sympy.sin(alpha) ** 2) == 0
    # the wire's normal force balances the weight's and the centrifugal force's parts
    # across it: m g sin(alpha) + m Omega^2 x cos(alpha) = m g / sin(alpha)
    assert sympy.simplify(rest.multipliers["lambda1"] + m * g / sympy.sin(alpha)) == 0
    assert rest.modes.stability is Stability.UNSTABLE


@pytest.mark.slow
def test_with_sympy_ended_at_once_the_same_points_come_numerically():
    system = _chain()
    eom = system.equations_of_motion()
    exact = surface_rest_points(eom).points
    numeric = surface_rest_points(eom, timeout=1e-3).points
    assert all(e.numeric for e in numeric) and len(numeric) == len(exact)
    values = {system.symbol(k): v for k, v in CHAIN.items()}
    for e, twin in zip(exact, numeric, strict=True):
        for name, value in e.point.items():
            assert _same_angle(float(value.subs(values)), float(twin.point[name]))
        assert float(e.omega_squared[0].subs(values)) == pytest.approx(
            float(twin.omega_squared[0]), rel=1e-9
        )


HOOP = """
name = "Bead on a turning hoop, in polar coordinates"
coordinates = ["r", "theta"]
constraints = ["r - R"]
kinetic = "m*(r_dot^2 + r^2*theta_dot^2 + Omega^2*r^2*sin(theta)^2)/2"
potential = "-m*g*r*cos(theta)"

[parameters]
m = 0.2
g = 9.81
Omega = 5.0
R = 0.5
"""


def test_a_bead_on_a_turning_hoop_rests_off_its_axis_exactly():
    # r = R pinned (the value of R and of no other parameter): SymPy solves the rest at
    # once, where the whole system takes it 2.3 s.  By hand: U(theta) = -m g R cos(theta) -
    # m Omega^2 R^2 sin(theta)^2/2 is stationary at cos(theta0) = g/(Omega^2 R), where
    # U'' = m Omega^2 R^2 sin(theta0)^2 and the inertia is m R^2
    system = lg.loads(HOOP)
    points = surface_rest_points(system.equations_of_motion()).points
    m, g, omega, radius = (system.symbol(k) for k in ("m", "g", "Omega", "R"))
    assert len(points) == 4 and not any(e.numeric for e in points)
    assert all(e.point["r"] == radius for e in points)
    cosine = g / (omega**2 * radius)
    off = [e for e in points if sympy.simplify(sympy.cos(e.point["theta"]) - cosine) == 0]
    assert len(off) == 2
    for e in off:
        expected = omega**2 * (1 - cosine**2)
        assert sympy.simplify(e.omega_squared[0] - expected) == 0
        # the hoop pulls the bead in with the centripetal force m Omega^2 R
        assert sympy.simplify(e.multipliers["lambda1"] + m * omega**2 * radius) == 0
        assert e.modes.stability is Stability.STABLE


def test_a_length_is_pinned_at_a_parameters_value_only_where_one_parameter_has_it():
    from lagrangian.analysis.surface_exact import pinned
    from lagrangian.analysis.surface_search import SurfaceRoot

    r, theta, lam, radius, m = sympy.symbols("r theta lambda1 R m")
    root = SurfaceRoot(np.array([0.5, 0.7]), np.array([-2.5]), rank=1)
    pins = pinned(root, [r, theta], [lam], [False, True], {radius: 0.5, m: 0.2})
    assert pins == {r: radius}
    assert pinned(root, [r, theta], [lam], [False, True], {radius: 0.5, m: 0.5}) == {}
    below = SurfaceRoot(np.array([-0.5, math.pi / 3]), np.array([0.0]), rank=1)
    pins = pinned(below, [r, theta], [lam], [False, True], {radius: 0.5, m: 0.2})
    assert pins == {r: -radius, theta: sympy.pi / 3, lam: 0}

"""Equilibria on constraint surfaces found numerically, their multipliers and their modes in
the coordinates q: each checked against a hand derivation or a computation that does not
go through the multipliers (V along the loop of a four-bar, by circle intersection)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis import Stability, analyze, constrained_equilibria
from lagrangian.analysis.constrained import surface_rest_points
from lagrangian.output.analysis import analysis_document, format_analysis

#: SymPy's share, in CPU seconds, where a test wants the numerical route: the child is
#: ended at once and the multi-start search on the surface gives the points.
NUMERIC = 1e-3

PARALLELOGRAM = """
name = "Parallelogram four-bar"
coordinates = ["theta_crank", "theta_coupler", "theta_rocker"]

[parameters]
a = 0.5
b = 1.2
c = 0.5
d = 1.2
m_crank = 0.5
m_coupler = 1.0
m_rocker = 0.8
g = 9.81

[[links]]
name = "crank"
length = "a"
mass = "m_crank"
angle = "theta_crank"

[[links]]
name = "coupler"
length = "b"
mass = "m_coupler"
angle = "theta_coupler"

[[links]]
name = "rocker"
length = "c"
mass = "m_rocker"
angle = "theta_rocker"

[[joints]]
name = "A"
connects = ["ground", "crank.start"]
at = [0, 0]

[[joints]]
name = "B"
connects = ["crank.end", "coupler.start"]

[[joints]]
name = "D"
connects = ["ground", "rocker.start"]
at = ["d", 0]

[[joints]]
name = "C"
connects = ["coupler.end", "rocker.end"]

[gravity]
g = "g"

[initial]
theta_crank = -1.4
theta_coupler = 0.0
theta_rocker = -1.4
"""


def numbers(mapping) -> np.ndarray:
    return np.array([float(v) for v in mapping.values()])


def at_point(equilibria, **target: float):
    """The equilibrium at ``target`` (angles compared modulo 2 pi)."""
    found = [
        e
        for e in equilibria
        if all(
            abs(math.remainder(float(e.point[name]) - value, 2 * math.pi)) < 1e-7
            for name, value in target.items()
        )
    ]
    assert len(found) == 1, [dict(e.point) for e in equilibria]
    return found[0]


def test_the_cartesian_pendulum_numerically_hangs_with_tension_m_g_and_omega_sqrt_g_over_l():
    system = lg.load("cartesian_pendulum")  # m = 1, l = 1, g = 9.81
    points = constrained_equilibria(system.equations_of_motion(), timeout=NUMERIC)
    assert all(e.numeric for e in points)
    bottom = at_point(points, x=0.0, y=-1.0)
    top = at_point(points, x=0.0, y=1.0)
    assert len(points) == 2
    # the rod's tension is -2 l lambda (constraint x^2 + y^2 - l^2): the weight m g
    assert -2 * 1.0 * float(bottom.multipliers["lambda1"]) == pytest.approx(9.81, rel=1e-9)
    assert bottom.modes.stability is Stability.STABLE
    assert float(bottom.omega_squared[0]) == pytest.approx(9.81, rel=1e-9)  # g / l
    assert [float(x) for x in bottom.modes.shapes[0]] == [1.0, 0.0]  # along x at the bottom
    assert top.modes.stability is Stability.UNSTABLE


def test_the_symbolic_pendulum_gives_its_mode_shape_in_x_and_y():
    system = lg.load("cartesian_pendulum")
    points = constrained_equilibria(system.equations_of_motion())
    l = system.symbol("l")
    bottom = next(e for e in points if e.point["y"] == -l)
    assert not bottom.numeric
    assert list(bottom.modes.shapes[0]) == [1, 0]


def test_a_particle_on_a_sphere_rests_at_the_bottom_with_omega_squared_g_over_r_twice():
    system = lg.System.from_particles(
        ["x", "y", "z"],
        [lg.Particle("p", "m", ("x", "y", "z"))],
        gravity=lg.Gravity("g"),
        constraints=["x^2 + y^2 + z^2 - R^2"],
    )
    points = constrained_equilibria(system.equations_of_motion())
    m, g, radius = (system.symbol(n) for n in ("m", "g", "R"))
    (bottom,) = [e for e in points if e.point == {"x": 0, "y": 0, "z": -radius}]
    (top,) = [e for e in points if e.point == {"x": 0, "y": 0, "z": radius}]
    # a spherical pendulum of length R: two modes of g/R, the normal force m g
    assert [sympy.simplify(w2 - g / radius) for w2 in bottom.omega_squared] == [0, 0]
    assert bottom.modes.stability is Stability.STABLE
    assert sympy.simplify(-2 * radius * bottom.multipliers["lambda1"] - m * g) == 0
    assert top.modes.stability is Stability.UNSTABLE
    # the two modes swing in the horizontal plane: no z in either shape
    assert all(shape[2] == 0 for shape in bottom.modes.shapes)


def test_a_parallelogram_four_bar_swings_as_a_pendulum_of_length_a():
    system = lg.loads(PARALLELOGRAM)
    points = constrained_equilibria(system.equations_of_motion(), timeout=NUMERIC)
    hanging = at_point(points, theta_crank=-math.pi / 2, theta_coupler=0, theta_rocker=-math.pi / 2)
    upright = at_point(points, theta_crank=math.pi / 2, theta_coupler=0, theta_rocker=math.pi / 2)
    a, m1, m2, m3, g = 0.5, 0.5, 1.0, 0.8, 9.81
    # by hand: the coupler translates on a circle of radius a (every point of it), the
    # crank and rocker turn about their pivots (I = m a^2/3); V = g a (m1/2 + m2 + m3/2)
    # sin(theta), T = a^2 (m1/3 + m2 + m3/3) theta'^2/2: a pendulum of length a
    omega_squared = g * (m1 / 2 + m2 + m3 / 2) / (a * (m1 / 3 + m2 + m3 / 3))
    assert hanging.modes.stability is Stability.STABLE
    assert [float(w2) for w2 in hanging.omega_squared] == pytest.approx([omega_squared], 1e-9)
    assert upright.modes.stability is Stability.UNSTABLE
    assert [float(w2) for w2 in upright.omega_squared] == pytest.approx([-omega_squared], 1e-9)
    # crank and rocker turn together, the coupler does not turn
    assert [float(x) for x in hanging.modes.shapes[0]] == pytest.approx([1, 0, 1], abs=1e-9)
    # the loop's closure in y carries half the coupler's weight; in x, nothing
    assert numbers(hanging.multipliers) == pytest.approx([0, -g * m2 / 2], abs=1e-9)


def _loop_closed(crank: float, branch: int, a, b, c, d) -> tuple[float, float]:
    """(coupler, rocker) angles of the four-bar at ``crank`` by circle intersection:
    C is b from B = a (cos, sin)(crank) and c from D = (d, 0)."""
    bx, by = a * math.cos(crank), a * math.sin(crank)
    dx, dy = d - bx, -by
    distance = math.hypot(dx, dy)
    along = (b * b - c * c + distance * distance) / (2 * distance)
    across = branch * math.sqrt(b * b - along * along)
    cx = bx + (along * dx - across * dy) / distance
    cy = by + (along * dy + across * dx) / distance
    return math.atan2(cy - by, cx - bx), math.atan2(cy, cx - d)


def _along_the_loop(crank: float, branch: int):
    """(V, kinetic coefficient of theta_crank'^2 / 2) of the built-in four-bar, from its
    geometry alone (uniform rods), the angular rates by central differences."""
    a, b, c, d, m1, m2, m3, g = 0.3, 1.0, 0.8, 1.0, 0.5, 1.0, 0.8, 9.81
    coupler, rocker = _loop_closed(crank, branch, a, b, c, d)
    h = 1e-6
    ahead = _loop_closed(crank + h, branch, a, b, c, d)
    behind = _loop_closed(crank - h, branch, a, b, c, d)
    w2, w3 = ((x - y) / (2 * h) for x, y in zip(ahead, behind, strict=True))
    # the coupler's centre: B + (b/2)(cos, sin)(coupler), its velocity by the chain rule
    vx = -a * math.sin(crank) - b / 2 * math.sin(coupler) * w2
    vy = a * math.cos(crank) + b / 2 * math.cos(coupler) * w2
    inertia = (
        m1 * a * a / 3 + m2 * (vx * vx + vy * vy + b * b / 12 * w2 * w2) + m3 * c * c / 3 * w3**2
    )
    height = m1 * a / 2 * math.sin(crank) + m2 * (a * math.sin(crank) + b / 2 * math.sin(coupler))
    height += m3 * c / 2 * math.sin(rocker)
    return g * height, inertia, (coupler, rocker)


def test_the_four_bar_rests_where_its_potential_along_the_loop_is_stationary():
    import scipy.optimize

    system = lg.load("four_bar")
    points = constrained_equilibria(system.equations_of_motion(), timeout=NUMERIC)
    assert len(points) == 4 and all(e.numeric for e in points)
    expected = []
    for branch in (1, -1):  # the coupler above and below the line of the pivots
        for sign in (1, -1):  # the lowest and the highest V on each branch
            result = scipy.optimize.minimize_scalar(
                lambda t, s=sign, k=branch: s * _along_the_loop(t, k)[0],
                bounds=(-math.pi, math.pi),
                method="bounded",
                options={"xatol": 1e-12},
            )
            h = 1e-4
            potential = [_along_the_loop(result.x + k * h, branch)[0] for k in (-1, 0, 1)]
            curvature = (potential[0] - 2 * potential[1] + potential[2]) / h**2
            _, inertia, (coupler, rocker) = _along_the_loop(result.x, branch)
            expected.append(((result.x, coupler, rocker), curvature / inertia))
    for (crank, coupler, rocker), omega_squared in expected:
        e = at_point(points, theta_crank=crank, theta_coupler=coupler, theta_rocker=rocker)
        assert float(e.omega_squared[0]) == pytest.approx(omega_squared, rel=1e-5)
        assert e.stable == (omega_squared > 0)
        assert len(e.modes.shapes[0]) == 3


def _slider_crank_in_millimetres():
    from importlib.resources import files

    text = files("lagrangian.examples").joinpath("slider_crank.toml").read_text()
    for metres, millimetres in [("r = 0.1 ", "r = 100 "), ("l = 0.4 ", "l = 400 ")]:
        assert metres in text
        text = text.replace(metres, millimetres)
    return lg.loads(text.replace("w = 0.08 ", "w = 80 ").replace("x = 0.5", "x = 500"))


@pytest.mark.parametrize("units", ["metres", "millimetres"])
def test_the_slider_crank_numerically_swings_as_its_hand_derivation_says(units):
    # at theta = 3 pi/2 the crank points down: the piston moves with the crank's tip
    # (dx/dtheta = r) and the rod translates, T = (I + (m_rod + m_piston) r^2) theta'^2/2;
    # only the rod's centre rises, V = m_rod g r sin(theta)/2.  In millimetres the slide
    # (387) and the angles differ in scale: the starts must still reach the loop
    system = lg.load("slider_crank") if units == "metres" else _slider_crank_in_millimetres()
    values = system.parameter_values
    r, l, g = values["r"], values["l"], values["g"]
    inertia = values["I_flywheel"] + (values["m_rod"] + values["m_piston"]) * r * r
    omega_squared = values["m_rod"] * g * r / (2 * inertia)
    points = constrained_equilibria(system.equations_of_motion(), timeout=NUMERIC)
    assert len(points) == 4
    for x in (math.sqrt(l * l - r * r), -math.sqrt(l * l - r * r)):
        e = at_point(points, theta=-math.pi / 2, x=x)
        assert e.modes.stability is Stability.STABLE
        assert float(e.omega_squared[0]) == pytest.approx(omega_squared, rel=1e-9)
        shape = [float(s) for s in e.modes.shapes[0]]  # (theta, x, phi): x moves r per radian
        assert shape[:2] == pytest.approx([1.0, r], rel=1e-9)
        # the rod carries half its weight to the piston's slide (the closure in y)
        assert numbers(e.multipliers) == pytest.approx([0, -values["m_rod"] * g / 2], abs=1e-9)


@pytest.mark.slow
def test_the_slider_crank_symbolic_and_numeric_points_agree():
    system = lg.load("slider_crank")
    eom = system.equations_of_motion()
    symbolic = constrained_equilibria(eom, timeout=60.0)  # SymPy's solve: 6.8 s of CPU alone
    assert not any(e.numeric for e in symbolic)
    numeric = constrained_equilibria(eom, timeout=NUMERIC)
    at = {p.symbol: p.default for p in system.parameters}
    for e in symbolic:
        point = {k: float(v.subs(at)) for k, v in e.point.items()}
        twin = at_point(numeric, **point)
        assert float(e.omega_squared[0].subs(at)) == pytest.approx(float(twin.omega_squared[0]))
        shape = [float(s.subs(at)) for s in e.modes.shapes[0]]
        assert shape == pytest.approx([float(s) for s in twin.modes.shapes[0]], abs=1e-9)


def test_constraints_redundant_at_the_rest_point_are_said_not_crashed_on():
    # a bead on a circle and on the line tangent to it at the bottom: both hold it at
    # (0, -l), where their gradients are parallel: the forces sharing the weight are
    # not determined (any split of m g between the circle and the line)
    system = lg.System.from_particles(
        ["x", "y"],
        [lg.Particle("bead", "m", ("x", "y"))],
        gravity=lg.Gravity("g"),
        constraints=["x^2 + y^2 - l^2", "y + l"],
        parameters={"m": 1.0, "g": 9.81, "l": 1.0},
    )
    found = surface_rest_points(system.equations_of_motion())
    (point,) = found.points
    assert point.point == {"x": 0, "y": -system.symbol("l")}
    assert point.redundant == 1 and point.multipliers == {}
    assert point.modes.stability is Stability.UNDETERMINED
    (note,) = found.notes
    assert note.startswith("equilibria: at x = 0, y = -l the constraints are redundant")
    text = format_analysis(system.analyze())
    assert "constraint forces at rest: not determined (redundant constraints)" in text
    assert note in text


@pytest.mark.slow
def test_analyze_of_the_four_bar_prints_its_equilibria_with_forces_and_shapes():
    eom = lg.load("four_bar").equations_of_motion()
    analysis = analyze(eom, timeout=8.0, stages=("equilibria",))
    text = format_analysis(analysis)
    block = text.split("Equilibria (at rest, staying at rest):")[1].split("\n\n")[0]
    assert "none found" not in block
    assert block.count("[numeric, at the default parameter values]") == 4
    assert block.count("constraint forces at rest: λ₁ = ") == 4
    assert block.count("mode shapes (θ_crank, θ_coupler, θ_rocker): (1, ") == 4
    document = analysis_document(analysis)
    assert len(document["equilibria"]) == 4
    for e in document["equilibria"]:
        assert e["numeric"] is True
        assert set(e["multipliers"]) == {"lambda1", "lambda2"}
        (shape,) = e["mode_shapes"]
        assert len(shape) == 3 and float(shape[0]) == 1.0
    assert sorted(e["stable"] for e in document["equilibria"]) == [False, False, True, True]


def test_a_linkage_without_gravity_rests_anywhere_on_its_loop():
    # no force acts at rest: every configuration the loop allows stays at rest (one
    # answer, not a root per start of the numerical search)
    system = lg.loads(PARALLELOGRAM.replace('[gravity]\ng = "g"\n', ""))
    (everywhere,) = constrained_equilibria(system.equations_of_motion(), timeout=NUMERIC)
    assert everywhere.point == {} and everywhere.omega_squared == (0,)
    assert everywhere.modes.stability is Stability.MARGINAL
    assert dict(everywhere.multipliers) == {"lambda1": 0, "lambda2": 0}
    block = format_analysis(system.analyze()).split("Equilibria (at rest, staying at rest):")[1]
    assert block.startswith("\n  every configuration: marginal\n")


@pytest.mark.parametrize("timeout", [NUMERIC, 10.0])
def test_a_bead_held_on_a_circle_by_a_spring_from_its_centre_rests_anywhere(timeout):
    # V = k (x^2 + y^2)/2 = k l^2/2 on the whole circle: a continuum of rest points (SymPy
    # leaves x free; the search lands on a point of it per start), said once, its one
    # free direction omega^2 = 0, the ring pushing out with k l (lambda = k/2, 2 lambda l)
    system = lg.System.from_particles(
        ["x", "y"],
        [lg.Particle("bead", "m", ("x", "y"))],
        springs=[lg.Spring("k", ends=("bead", (0, 0)))],
        constraints=["x^2 + y^2 - l^2"],
        parameters={"m": 1.0, "k": 3.0, "l": 2.0},
    )
    found = surface_rest_points(system.equations_of_motion(), timeout=timeout)
    (member,) = found.points
    assert math.hypot(*numbers(member.point)) == pytest.approx(2.0, rel=1e-12)
    assert member.modes.stability is Stability.MARGINAL
    assert abs(float(member.omega_squared[0])) < 1e-9
    assert float(member.multipliers["lambda1"]) == pytest.approx(3.0 / 2, rel=1e-12)
    (note,) = found.notes
    assert "is one member of a family of rest points on the constraint surface" in note
    assert "(up to 1 free directions;" in note


def test_latex_gives_the_constraint_forces_of_each_point():
    from lagrangian.output.analysis import latex_analysis

    system = lg.load("cartesian_pendulum")
    latex = latex_analysis(analyze(system.equations_of_motion(), stages=("equilibria",)))
    bottom, top = latex.split(r"\text{(stable)}")[1], latex.split(r"\text{(unstable)}")[1]
    # the hanging bob: tension -2 l lambda1 = m g
    assert bottom.startswith(
        r" \\" + "\n" + r"&\quad\text{constraint forces at rest: } \lambda_{1} = - \frac{g m}{2 l}"
    )
    assert r"\lambda_{1} = \frac{g m}{2 l}" in top


def test_a_driven_linkage_has_no_rest_point_and_says_why():
    # the crank turned at a given rate: the constraints depend on t, nothing stays at rest
    text = format_analysis(lg.load("four_bar_driven").analyze())
    block = text.split("Equilibria (at rest, staying at rest):")[1].split("\n\n")[0]
    assert block == "\n  not computed: none in general, the system depends explicitly on t"


def test_without_default_values_the_numerical_route_asks_for_them():
    # SymPy ended at once, no values to search at: one line naming the parameters
    system = lg.System.from_particles(
        ["x", "y"],
        [lg.Particle("bead", "m", ("x", "y"))],
        gravity=lg.Gravity("g"),
        constraints=["x^2 + y^2 - l^2"],
    )
    with pytest.raises(lg.ModelError) as error:
        constrained_equilibria(system.equations_of_motion(), timeout=NUMERIC)
    assert str(error.value) == (
        "SymPy cannot solve for the equilibria on the constraint surface; give default"
        " values for g, l, m to locate them numerically"
    )


@pytest.mark.parametrize("timeout", [NUMERIC, 10.0])
def test_a_constraint_whose_gradient_vanishes_on_its_surface_is_said_not_none_found(timeout):
    # (x^2 + y^2 - l^2)^2 = 0 holds the bead on the circle, but its gradient is 0 there:
    # no multiplier balances the weight, and "none found" would say there is no rest point
    system = lg.System.from_particles(
        ["x", "y"],
        [lg.Particle("bead", "m", ("x", "y"))],
        gravity=lg.Gravity("g"),
        constraints=["(x^2 + y^2 - l^2)^2"],
        parameters={"m": 1.0, "g": 9.81, "l": 1.0},
    )
    found = surface_rest_points(system.equations_of_motion(), timeout=timeout)
    assert found.points == ()
    (note,) = found.notes
    assert note.startswith(
        "equilibria: dc/dq has rank 0 for 1 constraint all over the constraint surface"
    )


@pytest.mark.slow
def test_the_four_bar_held_at_rest_and_nudged_moves_as_analyze_says():
    # an independent check of the multipliers and the frequency: simulate's own lambda
    # (M q'' = f + A^T lambda) at the rest point, and the period of a small swing about it
    system = lg.load("four_bar")
    points = constrained_equilibria(system.equations_of_motion(), timeout=NUMERIC)
    for e in (e for e in points if e.stable):
        rest = {k: float(v) for k, v in e.point.items()}
        at_rest = {f"{k}_dot": 0.0 for k in rest}  # the model's own start turns the crank
        still = system.simulate(initial=rest | at_rest, t_end=0.1)
        for name, value in e.multipliers.items():
            assert still[name] == pytest.approx(float(value), rel=1e-9)
        assert still["theta_crank"] == pytest.approx(rest["theta_crank"], abs=1e-9)
        # nudged along the crank (held; the others assembled onto the loop)
        period = 2 * math.pi / math.sqrt(float(e.omega_squared[0]))
        start = rest | at_rest | {"theta_crank": rest["theta_crank"] + 1e-4}
        swing = system.simulate(
            initial=start, t_end=3.2 * period, rtol=1e-11, atol=1e-13, n_out=2000
        )
        crank = swing["theta_crank"] - rest["theta_crank"]
        t = swing.t
        up = [
            t[i] - crank[i] * (t[i + 1] - t[i]) / (crank[i + 1] - crank[i])
            for i in range(len(t) - 1)
            if crank[i] < 0 <= crank[i + 1]
        ]
        assert len(up) >= 2
        # 2e-9 apart measured (2.6e-7 at a nudge of 1e-3: the swing's own nonlinearity)
        assert np.mean(np.diff(up)) == pytest.approx(period, rel=1e-6)

"""Planar linkages built from [[links]] and [[joints]]: their coordinates, closure
constraints, Grübler's count, assembly and refusals (runs: tests/integrate/test_linkage_runs.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.errors import ModelError
from lagrangian.examples import example_path
from lagrangian.model.linkage_assembly import assembled

FOUR_BAR = example_path("four_bar").read_text()


def by_name(expr: sympy.Expr, values: dict[str, float]) -> sympy.Expr:
    return expr.xreplace({s: values[s.name] for s in expr.free_symbols if s.name in values})


def test_four_bar_closes_its_loop_with_two_constraints():
    system = lg.load("four_bar")
    assert system.linkage.degrees_of_freedom == 1
    assert [s.name for s in system.linkage.held] == ["theta_crank"]
    names = {s.name: s for c in system.constraints for s in c.free_symbols}
    a, b, c, d = (names[k] for k in "abcd")
    t1, t2, t3 = (names[k] for k in ("theta_crank", "theta_coupler", "theta_rocker"))
    loop = [
        d + c * sympy.cos(t3) - a * sympy.cos(t1) - b * sympy.cos(t2),
        c * sympy.sin(t3) - a * sympy.sin(t1) - b * sympy.sin(t2),
    ]
    assert [sympy.simplify(x - y) for x, y in zip(system.constraints, loop, strict=True)] == [0, 0]
    assert [body.name for body in system.bodies] == ["crank", "coupler", "rocker"]


def test_double_pendulum_written_as_links_moves_as_the_example():
    """Two links without a loop: absolute angles phi = theta - pi/2 of the example's
    downward angles, point masses at the link ends (centre at the end, no inertia)."""
    links = lg.loads(
        """
coordinates = ["phi1", "phi2"]
[parameters]
m1 = 1.0
m2 = 1.0
l1 = 1.0
l2 = 1.0
g = 9.81
[[links]]
name = "upper"
length = "l1"
mass = "m1"
center = "l1"
inertia = 0
angle = "phi1"
[[links]]
name = "lower"
length = "l2"
mass = "m2"
center = "l2"
inertia = 0
angle = "phi2"
[[joints]]
connects = ["ground", "upper.start"]
at = [0, 0]
[[joints]]
connects = ["upper.end", "lower.start"]
[gravity]
g = "g"
"""
    )
    assert links.constraints == ()
    example = lg.load("double_pendulum")
    mine = links.equations_of_motion().accelerations
    theirs = example.equations_of_motion().accelerations
    rng = np.random.default_rng(3)
    for _ in range(5):
        point = dict(zip(["m1", "m2", "l1", "l2", "g"], rng.uniform(0.5, 2.0, 5), strict=True))
        angles, rates = rng.uniform(-2, 2, 2), rng.uniform(-2, 2, 2)
        here = point | {"phi1": angles[0], "phi2": angles[1]}
        here |= {"phi1_dot": rates[0], "phi2_dot": rates[1]}
        there = point | {"theta1": angles[0] + math.pi / 2, "theta2": angles[1] + math.pi / 2}
        there |= {"theta1_dot": rates[0], "theta2_dot": rates[1]}
        for mine_name, their_name in (("phi1", "theta1"), ("phi2", "theta2")):
            got = float(by_name(mine[mine_name], here))
            want = float(by_name(theirs[their_name], there))
            assert got == pytest.approx(want, rel=1e-12, abs=1e-12)


OFFSET_SLIDER = """
coordinates = ["theta", "phi", "x"]
[parameters]
r = 0.2
l = 0.7
e = 0.05
m = 1.0
[[links]]
name = "crank"
length = "r"
mass = "m"
angle = "theta"
[[links]]
name = "rod"
length = "l"
mass = "m"
angle = "phi"
[[links]]
name = "block"
length = 0.1
mass = "m"
[[joints]]
connects = ["ground", "crank.start"]
at = [0, 0]
[[joints]]
connects = ["crank.end", "rod.start"]
[[joints]]
name = "guide"
kind = "prismatic"
connects = ["ground", "block.start"]
at = [0, "e"]
axis = [1, 0]
slide = "x"
[[joints]]
name = "pin"
connects = ["rod.end", "block.start"]
"""


def test_offset_slider_crank_assembles_onto_its_closed_form():
    """A mechanism not among the examples: the piston's line is offset by e, so
    x = r cos(theta) + sqrt(l^2 - (r sin(theta) - e)^2), and the rod's rate follows."""
    system = lg.loads(OFFSET_SLIDER)
    assert [s.name for s in system.linkage.held] == ["theta"]
    params = np.array([p.default for p in system.parameters])
    r, l, e = 0.2, 0.7, 0.05
    for theta in np.linspace(-3, 3, 13):
        q, v = assembled(system, 0.0, np.array([theta, -0.1, 0.6]), np.array([2.0, 0, 0]), params)
        assert q[0] == theta and v[0] == 2.0  # held
        x = r * math.cos(theta) + math.sqrt(l**2 - (r * math.sin(theta) - e) ** 2)
        assert q[2] == pytest.approx(x, abs=1e-12)
        # x' = d/dt of the closed form
        s = r * math.sin(theta) - e
        rate = -r * math.sin(theta) * 2.0 - s * r * math.cos(theta) * 2.0 / math.sqrt(l**2 - s**2)
        assert v[2] == pytest.approx(rate, abs=1e-10)


def test_a_loop_that_cannot_close_is_refused_naming_the_joint():
    system = lg.loads(FOUR_BAR.replace("b = 1.0 ", "b = 0.2 ").replace("c = 0.8 ", "c = 0.2 "))
    params = np.array([p.default for p in system.parameters])
    with pytest.raises(ModelError) as raised:
        assembled(system, 0.0, np.array([1.0, 0.6, 1.5]), np.zeros(3), params)
    assert str(raised.value).startswith(
        "joints: the linkage cannot close at theta_crank = 1: joint 'C' stays "
    )
    assert str(raised.value).endswith(
        " apart (Newton's method found no assembly near the given angles; check the link "
        "lengths (Grashof's condition) and the held values)"
    )


def write(tmp_path, text):
    path = tmp_path / "linkage.toml"
    path.write_text(text)
    return str(path)


def refusal(capsys, tmp_path, text, command="derive"):
    path = write(tmp_path, text)
    status = main([command, path])
    err = capsys.readouterr().err.strip()
    assert status == ExitStatus.BAD_INPUT
    assert len(err.splitlines()) == 1
    return err.removeprefix("lagrangian: error: ").replace(path, "FILE")


def test_grubler_refuses_a_structure(capsys, tmp_path):
    triangle = FOUR_BAR.replace(
        '[[joints]]\nname = "C"\nconnects = ["coupler.end", "rocker.end"]',
        '[[joints]]\nname = "C"\nconnects = ["coupler.end", "rocker.end"]\n'
        '[[joints]]\nname = "E"\nconnects = ["ground", "coupler.start"]\nat = [0.2, 0]',
    )
    assert refusal(capsys, tmp_path, triangle) == (
        "FILE: joints: the linkage has -1 degrees of freedom by Grübler's count "
        "(3 x 3 links - 2 x 5 joints): it is a structure, not a mechanism"
    )


def test_more_drives_than_freedoms_are_refused(capsys, tmp_path):
    text = FOUR_BAR.replace('at = ["d", 0]', 'at = ["d", 0]\ndrive = "t"').replace(
        "at = [0, 0]", 'at = [0, 0]\ndrive = "2*t"'
    )
    assert refusal(capsys, tmp_path, text) == (
        "FILE: joints: 2 drives for 1 degrees of freedom (Grübler: 3 x 3 links - 2 x 4 "
        "joints): the linkage is over-constrained"
    )


def test_a_joint_naming_a_missing_link_is_refused(capsys, tmp_path):
    text = FOUR_BAR.replace('connects = ["crank.end", "coupler.start"]',
                            'connects = ["crank.end", "couple.start"]')  # fmt: skip
    assert refusal(capsys, tmp_path, text) == (
        "FILE: joints[1].connects[1]: no link named 'couple' (links: coupler, crank, rocker) "
        "in 'couple.start'"
    )


@pytest.mark.parametrize(
    ("old", "new", "expected"),
    [
        ('angle = "theta_rocker"', 'angle = "theta_rock"',
         "FILE: links[2].angle: 'theta_rock' is not one of the coordinates"),
        ('connects = ["coupler.end", "rocker.end"]', 'connects = ["coupler.end", "rocker.tip"]',
         "FILE: joints[3].connects[1]: link 'rocker' has no point 'tip' (points: start, end) "
         "in 'rocker.tip'"),
        ('at = ["d", 0]\n', "",
         "FILE: joints[2].at: a joint to ground needs its point 'at'"),
        ('name = "C"\n', 'name = "C"\nkind = "spherical"\n',
         "FILE: joints[3].kind: unknown kind 'spherical' (expected one of revolute, prismatic)"),
        ('angle = "theta_rocker"\n', "",
         "FILE: links[2].angle: link 'rocker' is placed by the revolute joint 'D': name the "
         "coordinate of its angle"),
    ],
)  # fmt: skip
def test_malformed_linkages_name_the_field(capsys, tmp_path, old, new, expected):
    assert old in FOUR_BAR
    assert refusal(capsys, tmp_path, FOUR_BAR.replace(old, new, 1)) == expected


def test_cannot_close_exits_2_from_the_command_line(capsys, tmp_path):
    text = FOUR_BAR.replace("b = 1.0 ", "b = 0.2 ").replace("c = 0.8 ", "c = 0.2 ")
    assert "the linkage cannot close at theta_crank = 1: joint 'C'" in refusal(
        capsys, tmp_path, text, command="simulate"
    )


def test_a_start_where_the_held_coordinate_fixes_nothing_is_refused():
    """The slider-crank with the piston's x held: at the dead centre x = r + l the crank
    and the rod are in line and the loop's Jacobian in (theta, phi) is singular."""
    text = OFFSET_SLIDER.replace('coordinates = ["theta", "phi", "x"]',
                                 'coordinates = ["x", "theta", "phi"]')  # fmt: skip
    system = lg.loads(text.replace("e = 0.05", "e = 0.0"))
    assert [s.name for s in system.linkage.held] == ["x"]
    params = np.array([p.default for p in system.parameters])
    with pytest.raises(ModelError) as raised:
        assembled(system, 0.0, np.array([0.9, 0.0, 0.0]), np.zeros(3), params)
    assert str(raised.value) == (
        "joints: the linkage cannot be assembled at x = 0.9: the constraints of joints pin "
        "are dependent there (a redundant joint, or a position where the held coordinates do "
        "not fix the others; give other values or list another coordinate first)"
    )
    q, _ = assembled(system, 0.0, np.array([0.7, 1.0, -0.3]), np.zeros(3), params)
    r, rod = 0.2, 0.7  # away from it: theta from the law of cosines
    assert math.cos(q[1]) == pytest.approx((0.7**2 + r**2 - rod**2) / (2 * 0.7 * r), abs=1e-12)


WATT_SIX_BAR = """
coordinates = ["t1", "t2", "t3", "t4", "t5"]
[parameters]
a = 0.3
b = 1.0
c = 0.8
d = 1.0
e = 0.9
f = 0.7
m = 1.0
[[links]]
name = "crank"
length = "a"
mass = "m"
angle = "t1"
[[links]]
name = "coupler"
length = "b"
mass = "m"
angle = "t2"
points = {E = [0.5, 0.3]}
[[links]]
name = "rocker"
length = "c"
mass = "m"
angle = "t3"
points = {F = [0.4, -0.2]}
[[links]]
name = "upper"
length = "e"
mass = "m"
angle = "t4"
[[links]]
name = "lower"
length = "f"
mass = "m"
angle = "t5"
[[joints]]
connects = ["ground", "crank.start"]
at = [0, 0]
[[joints]]
connects = ["crank.end", "coupler.start"]
[[joints]]
connects = ["ground", "rocker.start"]
at = ["d", 0]
[[joints]]
name = "C"
connects = ["coupler.end", "rocker.end"]
[[joints]]
connects = ["coupler.E", "upper.start"]
[[joints]]
connects = ["rocker.F", "lower.start"]
[[joints]]
name = "G"
connects = ["upper.end", "lower.end"]
"""


def circles_meet(p, r, q, s, left):
    """The point at distance r from p and s from q, left of p -> q (or right)."""
    p, q = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    between = np.linalg.norm(q - p)
    u = (q - p) / between
    along = (r**2 - s**2 + between**2) / (2 * between)
    height = math.sqrt(r**2 - along**2) * (1 if left else -1)
    return p + along * u + height * np.array([-u[1], u[0]])


def test_a_watt_six_bar_assembles_onto_two_loops_closed_by_hand():
    """Two loops (joints C and G close them), 5 links and 7 joints: Grübler 15 - 14 = 1.
    Each loop is closed by hand: C and G where two circles meet, on the side the guesses
    are on."""
    system = lg.loads(WATT_SIX_BAR)
    assert system.linkage.degrees_of_freedom == 1
    assert [j.name for j in system.linkage.joints if not j.tree] == ["C", "G"]
    assert len(system.constraints) == 4
    params = np.array([p.default for p in system.parameters])
    a, b, c, d, e, f = 0.3, 1.0, 0.8, 1.0, 0.9, 0.7

    def rotate(angle, point):
        return np.array([
            math.cos(angle) * point[0] - math.sin(angle) * point[1],
            math.sin(angle) * point[0] + math.cos(angle) * point[1],
        ])  # fmt: skip

    for t1 in np.linspace(0.2, 6.0, 9):
        guess = np.array([t1, 0.6, 1.5, 1.2, 2.2])
        q, v = assembled(system, 0.0, guess, np.array([1.0, 0, 0, 0, 0]), params)
        B = a * np.array([math.cos(t1), math.sin(t1)])
        C = circles_meet(B, b, [d, 0.0], c, left=True)
        t2 = math.atan2(*(C - B)[::-1])
        t3 = math.atan2(C[1], C[0] - d)
        E = B + rotate(t2, [0.5, 0.3])
        F = np.array([d, 0.0]) + rotate(t3, [0.4, -0.2])
        G = circles_meet(E, e, F, f, left=True)
        expected = [t1, t2, t3, math.atan2(*(G - E)[::-1]), math.atan2(*(G - F)[::-1])]
        assert np.allclose(np.angle(np.exp(1j * (q - expected))), 0.0, atol=1e-11)
        # the rates close both loops too: d/dt of every constraint is 0
        names = {s.name: s for c in system.constraints for s in c.free_symbols}
        point = {names[n]: x for n, x in zip(["t1", "t2", "t3", "t4", "t5"], q, strict=True)}
        point |= {names[k]: x for k, x in zip("abcdef", (a, b, c, d, e, f), strict=True)}
        for constraint in system.constraints:
            rate = sum(
                float(constraint.diff(names[n]).xreplace(point)) * v[k]
                for k, n in enumerate(["t1", "t2", "t3", "t4", "t5"])
                if n in names
            )
            assert abs(rate) < 1e-12


QUICK_RETURN = """
coordinates = ["theta", "phi", "s"]
[parameters]
r = 0.3
h = 0.5
L = 1.2
m = 1.0
[[links]]
name = "crank"
length = "r"
mass = "m"
angle = "theta"
[[links]]
name = "rocker"
length = "L"
mass = "m"
angle = "phi"
[[links]]
name = "block"
length = 0.1
mass = "m"
[[joints]]
connects = ["ground", "crank.start"]
at = [0, 0]
[[joints]]
connects = ["ground", "rocker.start"]
at = [0, "-h"]
[[joints]]
name = "slot"
kind = "prismatic"
connects = ["rocker.start", "block.start"]
axis = [1, 0]
slide = "s"
[[joints]]
name = "pin"
connects = ["crank.end", "block.start"]
"""


def test_a_block_sliding_on_a_turning_link_assembles_onto_the_closed_form():
    """Whitworth's quick return (an inverted slider-crank), not among the examples: the
    block slides along the rocker, which turns about (0, -h), so the slide's axis turns
    with it; phi = atan2(r sin(theta) + h, r cos(theta)), s = the distance pivot-pin."""
    system = lg.loads(QUICK_RETURN)
    assert system.linkage.degrees_of_freedom == 1
    assert [j.name for j in system.linkage.joints if not j.tree] == ["pin"]
    params = np.array([p.default for p in system.parameters])
    r, h = 0.3, 0.5
    for theta in np.linspace(-3.0, 3.0, 13):
        q, v = assembled(system, 0.0, np.array([theta, 1.5, 0.5]), np.array([1.0, 0, 0]), params)
        x, y = r * math.cos(theta), r * math.sin(theta) + h
        assert q[1] == pytest.approx(math.atan2(y, x), abs=1e-12)
        assert q[2] == pytest.approx(math.hypot(x, y), abs=1e-12)
        # rates: d/dt of the closed form with theta' = 1
        dx, dy = -r * math.sin(theta), r * math.cos(theta)
        assert v[1] == pytest.approx((x * dy - y * dx) / (x * x + y * y), abs=1e-10)
        assert v[2] == pytest.approx((x * dx + y * dy) / math.hypot(x, y), abs=1e-10)

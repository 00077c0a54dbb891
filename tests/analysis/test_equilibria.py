"""Equilibria: the worked examples, a bead on a rotating hoop, and the numerical route."""

from __future__ import annotations

import math

import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis.equilibria import equilibria
from lagrangian.analysis.linear import Stability
from lagrangian.model import Gravity, Particle


def points(found):
    return [dict(e.point) for e in found]


def same(a, b):
    return sympy.simplify(a - b) == 0


def hoop(omega: float):
    """A bead on a circular hoop of radius R turning at omega about the vertical axis."""
    bead = Particle(
        name="bead",
        mass="m",
        position=(
            "R*sin(theta)*cos(omega*t)",
            "R*sin(theta)*sin(omega*t)",
            "-R*cos(theta)",
        ),
    )
    return lg.System.from_particles(
        ["theta"],
        [bead],
        gravity=Gravity(g="g", direction=(0, 0, -1)),
        parameters={"m": 1.0, "R": 1.0, "omega": omega, "g": 9.81},
    )


def test_simple_pendulum_hangs_and_stands():
    system = lg.load("simple_pendulum")
    g, l = system.symbol("g"), system.symbol("l")
    down, up = equilibria(system.equations_of_motion())
    assert (dict(down.point), dict(up.point)) == ({"theta": 0}, {"theta": sympy.pi})
    assert not down.numeric
    assert down.stable and down.modes.stability is Stability.STABLE
    assert down.omega_squared == (g / l,)
    assert same(down.modes.periods[0], 2 * sympy.pi * sympy.sqrt(l / g))
    assert not up.stable and up.modes.stability is Stability.UNSTABLE
    assert up.omega_squared == (-g / l,)


def test_vertical_spring_rests_where_spring_balances_gravity():
    system = lg.load("vertical_spring")
    m, g, k = (system.symbol(n) for n in ("m", "g", "k"))
    (rest,) = equilibria(system.equations_of_motion())
    assert same(rest.point["x"], m * g / k)
    assert rest.stable and same(rest.omega_squared[0], k / m)


def test_bead_on_rotating_wire_is_thrown_outward():
    system = lg.load("rotating_wire_bead")
    (rest,) = equilibria(system.equations_of_motion())
    assert dict(rest.point) == {"r": 0}
    assert rest.omega_squared == (-(system.symbol("omega") ** 2),)
    assert rest.modes.stability is Stability.UNSTABLE


@pytest.mark.slow
def test_double_pendulum_has_four_equilibria_only_one_stable():
    found = equilibria(lg.load("double_pendulum").equations_of_motion())
    pi = sympy.pi
    assert points(found) == [
        {"theta1": 0, "theta2": 0},
        {"theta1": 0, "theta2": pi},
        {"theta1": pi, "theta2": 0},
        {"theta1": pi, "theta2": pi},
    ]
    assert [e.stable for e in found] == [True, False, False, False]
    assert all(len(e.omega_squared) == 2 for e in found)


def test_spherical_pendulum_leaves_out_the_cyclic_azimuth():
    found = equilibria(lg.load("spherical_pendulum").equations_of_motion())
    assert points(found) == [{"theta": 0}, {"theta": sympy.pi}]
    # sin(theta)^2 in M vanishes at the poles: phi is degenerate there, and the modes are
    # those of theta alone: the pendulum in a vertical plane, g/l below and -g/l above
    system = lg.load("spherical_pendulum")
    g, l = system.symbol("g"), system.symbol("l")
    down, up = found
    assert down.degenerate == up.degenerate == ("phi",)
    assert down.omega_squared == (g / l,) and down.modes.stability is Stability.STABLE
    assert up.omega_squared == (-g / l,) and up.modes.stability is Stability.UNSTABLE
    assert list(down.modes.shapes[0]) == [1, 0]  # theta moves, the degenerate phi does not


@pytest.mark.parametrize("name", ["central_force", "planar_particle_forces"])
def test_systems_never_at_rest(name):
    assert equilibria(lg.load(name).equations_of_motion()) == ()


def test_free_particle_is_at_rest_everywhere_with_neutral_directions():
    (everywhere,) = equilibria(lg.load("free_particle_spherical").equations_of_motion())
    assert dict(everywhere.point) == {}
    assert everywhere.omega_squared == (0, 0, 0)
    assert everywhere.modes.stability is Stability.MARGINAL


def test_charge_in_magnetic_field_rests_everywhere_and_gyrates():
    system = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2)/2 + b*(x*y_dot - y*x_dot)/2", coordinates=["x", "y"]
    )
    (everywhere,) = equilibria(system.equations_of_motion())
    m, b = system.symbol("m"), system.symbol("b")
    assert dict(everywhere.point) == {}
    assert everywhere.omega_squared == (0, b**2 / m**2)  # the cyclotron frequency
    assert everywhere.modes.stability is Stability.MARGINAL


def test_unspecified_potential_cannot_be_solved():
    eom = lg.load("velocity_dependent_potential").equations_of_motion()
    with pytest.raises(lg.ModelError, match="unspecified function"):
        equilibria(eom)


def test_explicit_time_dependence_means_no_equilibria():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 - k*x**2/2", coordinates=["x"], forces={"x": "F*cos(W*t)"}
    )
    assert equilibria(system.equations_of_motion()) == ()


def test_complex_roots_are_dropped():
    system = lg.System.from_lagrangian("m*x_dot**2/2 - x**4/4 - a*x**2/2", coordinates=["x"])
    (rest,) = equilibria(system.equations_of_motion())  # not x = +-i sqrt(a)
    assert dict(rest.point) == {"x": 0}
    assert rest.stable


@pytest.mark.parametrize("omega", [5.0, 2.0])
def test_bead_on_rotating_hoop_rises_when_spun_fast(omega):
    system = hoop(omega)
    R, g, w = (system.symbol(n) for n in ("R", "g", "omega"))
    found = equilibria(system.equations_of_motion())
    by_angle = {e.point["theta"]: e for e in found}
    assert by_angle[0].omega_squared == (g / R - w**2,) or same(
        by_angle[0].omega_squared[0], g / R - w**2
    )
    assert same(by_angle[sympy.pi].omega_squared[0], -(g / R + w**2))
    assert by_angle[sympy.pi].modes.stability is Stability.UNSTABLE
    risen = [angle for angle in by_angle if angle not in (0, sympy.pi)]
    if omega**2 > 9.81:  # above the critical speed: the bottom is unstable, the bead rises
        assert by_angle[0].modes.stability is Stability.UNSTABLE
        assert len(risen) == 2
        for angle in risen:
            assert same(sympy.cos(angle), g / (R * w**2))
            e = by_angle[angle]
            assert same(e.omega_squared[0], w**2 - g**2 / (R**2 * w**2))
            assert e.modes.stability is Stability.STABLE
    else:  # below it: only the bottom and the top, the bottom stable
        assert by_angle[0].modes.stability is Stability.STABLE
        assert risen == []


@pytest.mark.slow
def test_transcendental_equilibrium_is_found_numerically():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 - k*(x**2/2 - sin(x))",
        coordinates=["x"],
        parameters={"m": 1.0, "k": 2.0},
    )
    (rest,) = equilibria(system.equations_of_motion())
    assert rest.numeric
    x0 = float(rest.point["x"])
    assert abs(x0 - math.cos(x0)) < 1e-12
    assert abs(float(rest.omega_squared[0]) - 2.0 * (1 + math.sin(x0))) < 1e-9
    assert rest.stable and not rest.modes.closed_form


@pytest.mark.slow
def test_numerical_route_needs_default_values():
    system = lg.System.from_lagrangian("m*x_dot**2/2 - k*(x**2/2 - sin(x))", coordinates=["x"])
    with pytest.raises(lg.ModelError, match="default values for k, m"):
        equilibria(system.equations_of_motion())


def test_timeout_falls_back_to_numerical_roots_modulo_two_pi():
    found = equilibria(lg.load("double_pendulum").equations_of_motion(), timeout=1e-6)
    assert all(e.numeric for e in found)
    pi = math.pi
    expected = [(0.0, 0.0), (0.0, pi), (pi, 0.0), (pi, pi)]
    got = [(float(e.point["theta1"]), float(e.point["theta2"])) for e in found]
    assert len(got) == 4
    for (a, b), (c, d) in zip(sorted(got), expected, strict=True):
        assert abs(a - c) < 1e-9 and abs(b - d) < 1e-9
    assert [e.stable for e in found] == [True, False, False, False]
    # (2 -+ sqrt(2)) g/l for equal masses and lengths, at g = 9.81
    low, high = (float(w2) for w2 in found[0].omega_squared)
    assert abs(low - (2 - math.sqrt(2)) * 9.81) < 1e-9 * 9.81
    assert abs(high - (2 + math.sqrt(2)) * 9.81) < 1e-9 * 9.81


def test_equilibrium_is_frozen():
    (rest, _) = equilibria(lg.load("simple_pendulum").equations_of_motion())
    with pytest.raises(TypeError):
        rest.point["theta"] = 1
    with pytest.raises(AttributeError):
        rest.numeric = True


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_the_symbolic_solve_forks_quietly_after_jax_started_its_threads():
    jnp = pytest.importorskip("jax.numpy")
    jnp.ones(3).sum().block_until_ready()  # XLA's thread pools are running now
    found = lg.load("simple_pendulum").equilibria()
    assert sorted(round(float(e.point["theta"]), 9) for e in found) == [0.0, round(math.pi, 9)]


@pytest.mark.slow
def test_a_coordinate_singularity_is_not_an_equilibrium():
    # spherical coordinates with a horizontal axis: at theta = 0 the bob is at (l, 0, 0),
    # sideways; G = 0 there only because phi names nothing (issue 22: a gimbal lock)
    system = lg.System.from_particles(
        ["theta", "phi"],
        particles=[
            Particle("bob", "m", ("l*cos(theta)", "l*sin(theta)*cos(phi)", "l*sin(theta)*sin(phi)"))
        ],
        gravity=Gravity("g", (0, 0, -1)),
        parameters={"m": 1.0, "l": 1.0, "g": 9.81},
    )
    points = system.equilibria()
    assert {(str(e.point["theta"]), str(e.point["phi"])) for e in points} == {
        ("pi/2", "pi/2"), ("3*pi/2", "pi/2"), ("pi/2", "3*pi/2"), ("3*pi/2", "3*pi/2"),
    }  # fmt: skip
    analysis = system.analyze(timeout=None)
    assert "equilibria: theta = 0, phi = 0 is a singular point of the coordinates (phi " \
        "degenerate there), not an equilibrium" in " ".join(analysis.notes)  # fmt: skip


@pytest.mark.slow
def test_the_singular_points_of_a_top_that_are_at_rest_stay_equilibria():
    # zxz Euler angles are singular at theta = 0 and pi, where the top stands and hangs
    top, hanging = lg.load("heavy_top").equilibria()
    assert (top.point["theta"], hanging.point["theta"]) == (0, sympy.pi)
    assert top.modes.stability.value == "unstable"
    assert hanging.modes.stability.value == "marginal"  # the turn about the vertical: 0
    assert set(hanging.degenerate) == {"phi", "psi"}


def atwood(m1: float, m2: float):
    """The Atwood machine: x the height the lighter side rises, V = (m2 - m1) g x."""
    return lg.System.from_energies(
        "(m1 + m2)*x_dot**2/2",
        "(m2 - m1)*g*x",
        ["x"],
        parameters={"m1": m1, "m2": m2, "g": 9.81},
    )


@pytest.mark.slow  # an analysis and the CLI
def test_a_balanced_atwood_machine_is_at_rest_everywhere_at_its_values(tmp_path, capsys):
    from lagrangian.cli import ExitStatus, main
    from lagrangian.model.values import with_values

    assert atwood(2.0, 1.0).equilibria() == ()  # (m1 - m2) g never vanishes: none
    balanced = with_values(atwood(2.0, 1.0), {"m1": 1.0, "m2": 1.0})  # as --set gives it
    (line,) = balanced.equilibria()
    # every x, neutral: was 'none found' (the force at rest was judged for generic values)
    assert dict(line.point) == {} and line.numeric
    assert line.modes.stability.value == "marginal" and line.modes.omega_squared == (0,)
    model = tmp_path / "atwood.toml"
    model.write_text(
        'coordinates = ["x"]\nkinetic = "(m1 + m2)*x_dot^2/2"\npotential = "(m2 - m1)*g*x"\n'
        "[parameters]\nm1 = 2\nm2 = 1\ng = 9.81\n",
        encoding="utf-8",
    )
    argv = ["analyze", str(model), "--set", "m1=1", "--set", "m2=1"]
    assert main(argv) == ExitStatus.SUCCESS
    text = capsys.readouterr().out
    assert "  every configuration: marginal  [numeric, at the given values]\n" in text
    assert "ω² = 0: every direction: every configuration is at rest" in text


@pytest.mark.slow  # SymPy solves the hoop's equilibria
def test_an_angle_of_an_equilibrium_is_written_without_whole_turns():
    # a bead on a hoop turning at omega: off the axis at cos(theta) = g/(R omega^2), both
    # sides; SymPy gave one of them as -acos(g/(R omega^2)) + 2 pi
    hoop = lg.System.from_energies(
        "m*R**2*(theta_dot**2 + omega**2*sin(theta)**2)/2",
        "-m*g*R*cos(theta)",
        ["theta"],
        parameters={"m": 1.0, "R": 1.0, "g": 9.81, "omega": 5.0},
    )
    R, g, omega = (hoop.symbol(n) for n in ("R", "g", "omega"))
    points = {e.point["theta"] for e in hoop.equilibria()}
    off_axis = sympy.acos(g / (R * omega**2))
    assert points == {0, sympy.pi, off_axis, -off_axis}

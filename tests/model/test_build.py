"""Models a user writes from a textbook: each checked against a hand derivation."""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg


def acc(system, name="theta"):
    return system.equations_of_motion().accelerations[name]


def same(a, b, system):
    """a == b identically (both in the system's symbols)."""
    return sympy.simplify(a - b) == 0


def s(system, names):
    return [system.symbol(n) for n in names.split()]


def test_undeclared_names_become_positive_parameters():
    system = lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"])
    assert system.parameter_names == ("k", "m")
    assert all(p.symbol.is_positive for p in system.parameters)
    x, m, k = s(system, "x m k")
    assert same(acc(system, "x"), -k * x / m, system)


def test_sympy_input_is_rebound_by_name():
    x, x_dot, k = sympy.symbols("x x_dot k")  # no assumptions: not our symbols
    system = lg.System.from_lagrangian(x_dot**2 / 2 - k * x**4 / 4, coordinates=["x"])
    x, k = s(system, "x k")
    assert acc(system, "x") == -k * x**3


def test_driven_pendulum_with_moving_pivot():
    # pivot moves vertically: y0 = a cos(w t); ddot theta = -(g + ddot y0) sin(theta) / l
    system = lg.System.from_particles(
        coordinates=["theta"],
        particles=[lg.Particle("bob", "m", ("l*sin(theta)", "a*cos(w*t) - l*cos(theta)"))],
        gravity=lg.Gravity("g"),
    )
    theta, l, g, a, w = s(system, "theta l g a w")
    t = system.time
    expected = -(g - a * w**2 * sympy.cos(w * t)) * sympy.sin(theta) / l
    assert same(acc(system), expected, system)
    assert not system.is_autonomous


def test_forces_and_dissipation_enter_with_the_right_sign():
    system = lg.System.from_energies(
        kinetic="m*x_dot^2/2",
        potential="k*x^2/2",
        coordinates=["x"],
        forces={"x": "F0*cos(w*t)"},
        dissipation="b*x_dot^2/2",
    )
    x, x_dot, m, k, b, F0, w = s(system, "x x_dot m k b F0 w")
    expected = (F0 * sympy.cos(w * system.time) - b * x_dot - k * x) / m
    assert same(acc(system, "x"), expected, system)


def test_spring_with_rest_length_on_a_plane():
    system = lg.System.from_particles(
        coordinates=["x", "y"],
        particles=[lg.Particle("p", "m", ("x", "y"))],
        springs=[lg.Spring("k", ends=("p", (0, 0)), rest_length="L0")],
    )
    x, y, m, k, L0 = s(system, "x y m k L0")
    r = sympy.sqrt(x**2 + y**2)
    eom = system.equations_of_motion()
    assert same(eom.accelerations["x"], -k * (r - L0) * x / r / m, system)
    assert same(eom.accelerations["y"], -k * (r - L0) * y / r / m, system)


def test_planar_rigid_body_physical_pendulum():
    system = lg.System.from_particles(
        coordinates=["theta"],
        bodies=[
            lg.RigidBody2D(
                "rod", "m", "m*l^2/12", center=("l/2*sin(theta)", "-l/2*cos(theta)"), angle="theta"
            )
        ],
        gravity=lg.Gravity("g"),
    )
    theta, l, g = s(system, "theta l g")
    assert same(acc(system), -3 * g * sympy.sin(theta) / (2 * l), system)


def test_unspecified_function_of_a_coordinate():
    system = lg.System.from_lagrangian(
        "m*x_dot^2/2 - U", coordinates=["x"], functions={"U": ["x"]}, parameters={"m": 1.0}
    )
    (declared,) = system.functions
    x, m = s(system, "x m")
    assert acc(system, "x") == -sympy.Derivative(declared.function(x), x) / m


def test_conservative_forces_are_integrated_into_a_potential():
    system = lg.System.from_energies(
        kinetic="m*(x_dot^2 + y_dot^2)/2",
        potential=0,
        coordinates=["x", "y"],
        conservative_forces={"x": "-k*x + c*y", "y": "c*x - k*y**3"},
    )
    x, y, k, c = s(system, "x y k c")
    expected_v = k * x**2 / 2 - c * x * y + k * y**4 / 4
    assert same(system.potential, expected_v, system)


def test_negative_and_real_parameters():
    system = lg.System.from_lagrangian(
        "m*(x_dot^2 + y_dot^2)/2 + q*B*(x*y_dot - y*x_dot)/2",
        coordinates=["x", "y"],
        parameters={"m": 1.0, "B": 1.0, "q": {"value": -1.0, "sign": "real"}},
    )
    q = system.symbol("q")
    assert q.is_real and q.is_positive is None
    x_dot, y_dot, m, B = s(system, "x_dot y_dot m B")
    eom = system.equations_of_motion()
    assert same(eom.accelerations["x"], q * B * y_dot / m, system)
    assert same(eom.accelerations["y"], -q * B * x_dot / m, system)


def test_latex_input_gives_the_same_system():
    text = lg.System.from_lagrangian(
        "m*l^2*theta_dot^2/2 + m*g*l*cos(theta)", coordinates=["theta"]
    )
    latex = lg.System.from_lagrangian(
        r"\frac{1}{2} m l^{2} \dot{\theta}^{2} + m g l \cos\theta", coordinates=["theta"]
    )
    assert text.lagrangian == latex.lagrangian


def test_relativistic_particle_mass_matrix_depends_on_velocity():
    system = lg.System.from_lagrangian("-m*c^2*sqrt(1 - x_dot^2/c^2) - k*x^2/2", coordinates=["x"])
    x, x_dot, m, c, k = s(system, "x x_dot m c k")
    expected = -k * x * (1 - x_dot**2 / c**2) ** sympy.Rational(3, 2) / m
    assert same(acc(system, "x"), expected, system)


@pytest.mark.parametrize("name", ["double_pendulum", "spherical_pendulum"])
def test_particle_examples_have_textbook_energies(name):
    system = lg.load(name)
    assert system.kinetic is not None and system.potential is not None
    assert same(system.lagrangian, system.kinetic - system.potential, system)

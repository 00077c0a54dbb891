"""Derivations outside the textbook mould, each against a closed form worked out by hand.

Velocity-dependent mass matrices, unspecified functions of time, forces given
as unspecified functions, parameters of each sign, moving spring supports,
oblique gravity, potentials from conservative forces, and constraints.
"""

from __future__ import annotations

import math
import random

import pytest
import sympy

import lagrangian as lg
from helpers import assert_close, evaluate, random_point, scale_of, total_time_derivative

N_POINTS = 5


def check_accelerations(system, expected, rng: random.Random, *, functions=None, **point_options):
    """eom.accelerations[q] == expected[q](point) at N_POINTS random points."""
    eom = system.equations_of_motion()
    assert eom.accelerations is not None
    assert set(eom.accelerations) == set(expected)
    points = []
    for _ in range(N_POINTS):
        point = random_point(system, rng, **point_options)
        for name, closed_form in expected.items():
            assert_close(
                evaluate(eom.accelerations[name], point, functions),
                closed_form(point),
                scale=1.0,
                what=f"{name}_ddot at {point}",
            )
        points.append(point)
    return eom, points


def test_relativistic_particle_mass_matrix_depends_on_the_velocity(rng):
    """L = -m c^2 sqrt(1 - v^2/c^2) - k x^2/2: m gamma^3 x'' = -k x."""
    system = lg.System.from_lagrangian(
        "-m*c**2*sqrt(1 - x_dot**2/c**2) - k*x**2/2", coordinates=["x"]
    )

    def expected(p):
        return -p["k"] * p["x"] * (1 - p["x_dot"] ** 2 / p["c"] ** 2) ** 1.5 / p["m"]

    eom, points = check_accelerations(system, {"x": expected}, rng, ranges={"c": (2.5, 4.0)})
    assert eom.mass_matrix[0, 0].has(system.symbol("x_dot"))
    for p in points:
        gamma = 1 / math.sqrt(1 - p["x_dot"] ** 2 / p["c"] ** 2)
        assert_close(evaluate(eom.mass_matrix[0, 0], p), p["m"] * gamma**3)


def test_unspecified_function_of_position_and_time(rng):
    """L = x_dot^2/2 + A(x, t) x_dot - V(x): the A_x x_dot terms cancel, x'' = -A_t - V_x."""
    system = lg.System.from_lagrangian(
        "x_dot**2/2 + A(x, t)*x_dot - V(x)",
        coordinates=["x"],
        functions={"A": ["x", "t"], "V": ["x"]},
    )
    concrete = {
        "A": lambda x, t: sympy.sin(x * t) + x**2 * t,
        "V": lambda x: x**4 / 4 - sympy.cos(x),
    }

    def expected(p):
        x, t = p["x"], p["t"]
        a_t = math.cos(x * t) * x + x**2
        v_x = x**3 + math.sin(x)
        return -a_t - v_x

    _, _ = check_accelerations(system, {"x": expected}, rng, functions=concrete)
    eom = system.equations_of_motion()
    assert eom.accelerations["x"].has(sympy.Derivative)


def test_unspecified_generalized_force(rng):
    """Worked example 9 with F_x an unspecified function of (x, y, t)."""
    system = lg.System.from_energies(
        kinetic="m*(x_dot**2 + y_dot**2)/2",
        potential=0,
        coordinates=["x", "y"],
        functions={"F": ["x", "y", "t"]},
        forces={"x": "F(x, y, t)", "y": "-b*y_dot"},
    )
    concrete = {"F": lambda x, y, t: x * y + sympy.cos(t)}
    check_accelerations(
        system,
        {
            "x": lambda p: (p["x"] * p["y"] + math.cos(p["t"])) / p["m"],
            "y": lambda p: -p["b"] * p["y_dot"] / p["m"],
        },
        rng,
        functions=concrete,
    )


@pytest.mark.parametrize("sign", ["real", "negative", "nonnegative", "positive"])
def test_parameters_of_every_sign(rng, sign):
    """m x'' = -c x - e x_dot for c of each declared sign (the sign must not be assumed)."""
    value = {"real": -1.0, "negative": -2.0, "nonnegative": 0.0, "positive": 3.0}[sign]
    system = lg.System.from_energies(
        kinetic="m*x_dot**2/2",
        potential="c*x**2/2 + c**3*x",
        coordinates=["x"],
        parameters={"m": 1.0, "c": {"value": value, "sign": sign}},
        dissipation="m*c**2*x_dot**2/2",
    )
    assert system.parameter_values["c"] == value

    def expected(p):
        c = p["c"]
        return (-c * p["x"] - c**3 - p["m"] * c**2 * p["x_dot"]) / p["m"]

    check_accelerations(system, {"x": expected}, rng)


def test_spring_to_a_moving_support_on_a_line(rng):
    """V = k (|x - a cos(w t)| - L0)^2 / 2: explicit time and an absolute value."""
    system = lg.System.from_particles(
        coordinates=["x"],
        particles=[lg.Particle("p", mass="m", position=["x", 0])],
        springs=[lg.Spring(stiffness="k", ends=("p", ("a*cos(w*t)", 0)), rest_length="L0")],
    )
    assert not system.is_autonomous

    def expected(p):
        d = p["x"] - p["a"] * math.cos(p["w"] * p["t"])
        return -p["k"] * (abs(d) - p["L0"]) * math.copysign(1.0, d) / p["m"]

    def degenerate(p):
        return abs(p["x"] - p["a"] * math.cos(p["w"] * p["t"])) < 0.2

    check_accelerations(system, {"x": expected}, rng, avoid=degenerate)


def test_gravity_direction_is_normalised(rng):
    """direction (1, -1) is the unit vector (1, -1)/sqrt(2): x'' = g/sqrt 2, y'' = -g/sqrt 2."""
    system = lg.System.from_particles(
        coordinates=["x", "y"],
        particles=[lg.Particle("p", mass="m", position=["x", "y"])],
        gravity=lg.Gravity(g="g", direction=(1, -1)),
    )
    check_accelerations(
        system,
        {"x": lambda p: p["g"] / math.sqrt(2), "y": lambda p: -p["g"] / math.sqrt(2)},
        rng,
    )


def test_default_gravity_points_down_the_last_axis(rng):
    system = lg.System.from_particles(
        coordinates=["x", "y", "z"],
        particles=[lg.Particle("p", mass="m", position=["x", "y", "z"])],
        gravity=lg.Gravity(g="g"),
    )
    check_accelerations(
        system, {"x": lambda p: 0.0, "y": lambda p: 0.0, "z": lambda p: -p["g"]}, rng
    )


def test_rigid_body_spinning_at_a_driven_rate(rng):
    """A rod whose angle is theta + w t about a fixed centre: the drive adds nothing to theta''."""
    system = lg.System.from_particles(
        coordinates=["theta"],
        bodies=[lg.RigidBody2D("rod", mass="m", inertia="I0", center=(0, 0), angle="theta + w*t")],
        potential="k*theta**2/2",
    )
    check_accelerations(system, {"theta": lambda p: -p["k"] * p["theta"] / p["I0"]}, rng)


def test_potential_from_coupled_conservative_forces(rng):
    """Q_x = -2 x y^2, Q_y = -2 x^2 y derive from V = x^2 y^2."""
    system = lg.System.from_energies(
        kinetic="m*(x_dot**2 + y_dot**2)/2",
        potential=0,
        coordinates=["x", "y"],
        conservative_forces={"x": "-2*x*y**2", "y": "-2*x**2*y"},
    )
    check_accelerations(
        system,
        {
            "x": lambda p: -2 * p["x"] * p["y"] ** 2 / p["m"],
            "y": lambda p: -2 * p["x"] ** 2 * p["y"] / p["m"],
        },
        rng,
    )


def test_forces_without_a_potential_are_refused():
    with pytest.raises(lg.ModelError) as caught:
        lg.System.from_energies(
            kinetic="m*(x_dot**2 + y_dot**2)/2",
            potential=0,
            coordinates=["x", "y"],
            conservative_forces={"x": "y", "y": "-x"},
        )
    assert "potential" in str(caught.value)


# -- constraints -------------------------------------------------------------------------
def test_holonomic_constraint_pendulum_in_cartesian_coordinates(rng):
    """x^2 + y^2 - l^2 = 0 with gravity: the accelerations of a pendulum of length l."""
    system = lg.System.from_particles(
        coordinates=["x", "y"],
        particles=[lg.Particle("bob", mass="m", position=["x", "y"])],
        gravity=lg.Gravity(g="g"),
        constraints=["x**2 + y**2 - l**2"],
    )
    eom = system.equations_of_motion()
    assert eom.accelerations is not None
    for _ in range(N_POINTS):
        point = random_point(system, rng)
        theta, omega, l, g = point["x"], point["x_dot"], point["l"], point["g"]
        # a state on the constraint: x = l sin(theta), y = -l cos(theta), tangent velocity
        point.update(
            x=l * math.sin(theta),
            y=-l * math.cos(theta),
            x_dot=l * math.cos(theta) * omega,
            y_dot=l * math.sin(theta) * omega,
        )
        theta_ddot = -g / l * math.sin(theta)
        x_ddot = l * (math.cos(theta) * theta_ddot - math.sin(theta) * omega**2)
        y_ddot = l * (math.sin(theta) * theta_ddot + math.cos(theta) * omega**2)
        assert_close(evaluate(eom.accelerations["x"], point), x_ddot, scale=1.0)
        assert_close(evaluate(eom.accelerations["y"], point), y_ddot, scale=1.0)


def test_velocity_constraint(rng):
    """x_dot - y_dot = 0: m x'' + k x = lambda, m y'' = -lambda, so x'' = y'' = -k x / (2 m)."""
    system = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2)/2 - k*x**2/2",
        coordinates=["x", "y"],
        constraints=["x_dot - y_dot"],
    )

    def expected(p):
        return -p["k"] * p["x"] / (2 * p["m"])

    eom, points = check_accelerations(system, {"x": expected, "y": expected}, rng)
    # the constraint, differentiated, holds along the solved motion
    rate = total_time_derivative(sympy.Symbol("x_dot") - sympy.Symbol("y_dot"), ("x", "y"))
    for p in points:
        values = dict(p)
        for q in ("x", "y"):
            values[f"{q}_ddot"] = evaluate(eom.accelerations[q], p)
        assert abs(evaluate(rate, values)) <= 1e-9 * scale_of(rate, values)


def test_particles_given_as_sympy_expressions_are_rebound_by_name(rng):
    """The double pendulum from plain-Symbol SymPy positions equals the built-in example."""
    theta1, theta2, l1, l2 = sympy.symbols("theta1 theta2 l1 l2")
    x1, y1 = l1 * sympy.sin(theta1), -l1 * sympy.cos(theta1)
    x2, y2 = x1 + l2 * sympy.sin(theta2), y1 - l2 * sympy.cos(theta2)
    system = lg.System.from_particles(
        coordinates=["theta1", "theta2"],
        particles=[
            lg.Particle("bob1", mass=sympy.Symbol("m1"), position=(x1, y1)),
            lg.Particle("bob2", mass=sympy.Symbol("m2"), position=(x2, y2)),
        ],
        gravity=lg.Gravity(g=sympy.Symbol("g"), direction=(0, -1)),
    )
    reference = lg.load("double_pendulum")
    assert set(system.parameter_names) == set(reference.parameter_names)
    ours, theirs = system.equations_of_motion(), reference.equations_of_motion()
    for _ in range(N_POINTS):
        point = random_point(system, rng)
        for name in ("theta1", "theta2"):
            assert_close(
                evaluate(ours.accelerations[name], point),
                evaluate(theirs.accelerations[name], point),
                what=name,
            )


def test_multiplier_names_do_not_clash_with_the_models_names():
    """A parameter called lambda1 in a constrained model must stay distinguishable by name.

    The outputs are text over the model's names (DESIGN 5), so two different
    symbols printed 'lambda1' in one equation cannot be read back; refusing the
    name with a LagrangianError is an acceptable answer too.
    """
    system = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2)/2 - lambda1*x**2/2",
        coordinates=["x", "y"],
        constraints=["x_dot - y_dot"],
    )
    try:
        eom = system.equations_of_motion()
    except lg.LagrangianError:
        return
    for equation in eom.equations:
        names = sorted(s.name for s in equation.free_symbols)
        assert len(names) == len(set(names)), f"two symbols share a name in {equation}"

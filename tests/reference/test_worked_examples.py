"""The ten worked examples (shared/reference/worked-examples.md) as acceptance tests.

Every reference below is typed from the PRINTED equations of motion of the
worked examples, with plain SymPy symbols, never from the toolkit's output:
the accelerations are obtained by solving the printed equations (a linear
system in the accelerations) with SymPy in the test.  A printed equation of
the form ``d/dt (...) = 0`` is differentiated by the chain rule in
``helpers.total_time_derivative``.  The comparisons are numerical, at seeded
random points, symbols matched by name.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cache

import pytest
import sympy

import lagrangian as lg
from helpers import (
    assert_close,
    evaluate,
    plain,
    random_point,
    scale_of,
    substitute_by_name,
    substitute_functions,
    total_time_derivative,
)

N_POINTS = 6

sin, cos, exp = sympy.sin, sympy.cos, sympy.exp
t = sympy.Symbol("t")
x, y, z, r, theta, phi, theta1, theta2 = sympy.symbols("x y z r theta phi theta1 theta2")
x_dot, y_dot, z_dot, r_dot, theta_dot, phi_dot, theta1_dot, theta2_dot = sympy.symbols(
    "x_dot y_dot z_dot r_dot theta_dot phi_dot theta1_dot theta2_dot"
)
x_ddot, y_ddot, z_ddot, r_ddot, theta_ddot, phi_ddot, theta1_ddot, theta2_ddot = sympy.symbols(
    "x_ddot y_ddot z_ddot r_ddot theta_ddot phi_ddot theta1_ddot theta2_ddot"
)
m, l, g, k, mu, m1, m2, l1, l2, omega, F_x, F_y = sympy.symbols(
    "m l g k mu m1 m2 l1 l2 omega F_x F_y"
)


def d_dt(expr: sympy.Expr, coordinates: tuple[str, ...]) -> sympy.Expr:
    return total_time_derivative(expr, coordinates)


# -- example 2: concrete functions for A, B, C, V -----------------------------------
CONCRETE = {
    "A": lambda x, y, z: sin(x) * y + z**2 / 3,
    "B": lambda x, y, z: x * z - cos(y) + x**2 * y / 5,
    "C": lambda x, y, z: exp(x / 3) * y + y * z,
    "V": lambda x, y, z: x**2 * y / 2 + cos(z) * x + y**4 / 10,
}


def _velocity_dependent_equations() -> list[sympy.Expr]:
    A, B, C, V = (CONCRETE[name](x, y, z) for name in "ABCV")

    def dd(f, s):
        return sympy.diff(f, s)

    # printed x-equation; y and z by cycling x->y->z, A->B->C
    return [
        x_ddot + y_dot * (dd(A, y) - dd(B, x)) + z_dot * (dd(A, z) - dd(C, x)) + dd(V, x),
        y_ddot + z_dot * (dd(B, z) - dd(C, y)) + x_dot * (dd(B, x) - dd(A, y)) + dd(V, y),
        z_ddot + x_dot * (dd(C, x) - dd(A, z)) + y_dot * (dd(C, y) - dd(B, z)) + dd(V, z),
    ]


def _double_pendulum_equations() -> list[sympy.Expr]:
    c12, s12 = cos(theta1 - theta2), sin(theta1 - theta2)
    return [
        (m1 + m2) * l1 * theta1_ddot
        + m2 * l2 * theta2_ddot * c12
        + m2 * l2 * theta2_dot**2 * s12
        + (m1 + m2) * g * sin(theta1),
        l2 * theta2_ddot + l1 * theta1_ddot * c12 - l1 * theta1_dot**2 * s12 + g * sin(theta2),
    ]


@dataclass(frozen=True)
class WorkedExample:
    """One worked example: names, printed equations (each = 0) and printed L."""

    name: str
    coordinates: tuple[str, ...]
    parameters: frozenset[str]
    equations: Callable[[], list[sympy.Expr]]
    lagrangian: sympy.Expr
    ranges: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    avoid: Callable[[Mapping[str, float]], bool] | None = None
    functions: Mapping[str, Callable[..., sympy.Expr]] = field(default_factory=dict)


def _sin_theta_small(point: Mapping[str, float]) -> bool:
    return abs(math.sin(point["theta"])) < 0.2


EXAMPLES = [
    WorkedExample(
        "simple_pendulum",
        ("theta",),
        frozenset({"m", "l", "g"}),
        lambda: [m * l**2 * theta_ddot + m * g * l * sin(theta)],
        m * l**2 * theta_dot**2 / 2 - m * g * l * (1 - cos(theta)),
    ),
    WorkedExample(
        "velocity_dependent_potential",
        ("x", "y", "z"),
        frozenset(),
        _velocity_dependent_equations,
        sympy.Integer(0),  # L holds unspecified functions: checked separately
        functions=CONCRETE,
    ),
    WorkedExample(
        "harmonic_oscillator",
        ("x",),
        frozenset({"m", "k"}),
        lambda: [m * x_ddot + k * x],
        m * x_dot**2 / 2 - k * x**2 / 2,
    ),
    WorkedExample(
        "central_force",
        ("r", "theta"),
        frozenset({"mu"}),
        lambda: [
            r_ddot - r * theta_dot**2 + mu / r**2,
            d_dt(r**2 * theta_dot, ("r", "theta")),
        ],
        (r_dot**2 + r**2 * theta_dot**2) / 2 + mu / r,
        ranges={"r": (0.5, 2.0)},
    ),
    WorkedExample(
        "spherical_pendulum",
        ("theta", "phi"),
        frozenset({"m", "l", "g"}),
        lambda: [
            m * l**2 * theta_ddot
            - m * l**2 * sin(theta) * cos(theta) * phi_dot**2
            + m * g * l * sin(theta),
            d_dt(m * l**2 * sin(theta) ** 2 * phi_dot, ("theta", "phi")),
        ],
        m * l**2 * (theta_dot**2 + sin(theta) ** 2 * phi_dot**2) / 2 - m * g * l * (1 - cos(theta)),
        avoid=_sin_theta_small,
    ),
    WorkedExample(
        "double_pendulum",
        ("theta1", "theta2"),
        frozenset({"m1", "m2", "l1", "l2", "g"}),
        _double_pendulum_equations,
        # the CORRECT T (the lecture's printed T has two typos) minus the printed V
        (m1 + m2) * l1**2 * theta1_dot**2 / 2
        + m2 * l2**2 * theta2_dot**2 / 2
        + m2 * l1 * l2 * theta1_dot * theta2_dot * cos(theta1 - theta2)
        - m1 * g * l1 * (1 - cos(theta1))
        - m2 * g * (l1 + l2 - l1 * cos(theta1) - l2 * cos(theta2)),
    ),
    WorkedExample(
        "vertical_spring",
        ("x",),
        frozenset({"m", "k", "g"}),
        lambda: [m * x_ddot + k * x - m * g],
        m * x_dot**2 / 2 - k * x**2 / 2 + m * g * x,
    ),
    WorkedExample(
        "free_particle_spherical",
        ("r", "theta", "phi"),
        frozenset({"m"}),
        lambda: [
            m * (r_ddot - r * theta_dot**2 - r * sin(theta) ** 2 * phi_dot**2),
            d_dt(m * r**2 * theta_dot, ("r", "theta", "phi"))
            - m * r**2 * sin(theta) * cos(theta) * phi_dot**2,
            d_dt(m * r**2 * sin(theta) ** 2 * phi_dot, ("r", "theta", "phi")),
        ],
        m * (r_dot**2 + r**2 * theta_dot**2 + r**2 * sin(theta) ** 2 * phi_dot**2) / 2,
        ranges={"r": (0.5, 2.0)},
        avoid=_sin_theta_small,
    ),
    WorkedExample(
        "planar_particle_forces",
        ("x", "y"),
        frozenset({"m", "F_x", "F_y"}),
        lambda: [m * x_ddot - F_x, m * y_ddot - F_y],
        m * (x_dot**2 + y_dot**2) / 2,
    ),
    WorkedExample(
        "rotating_wire_bead",
        ("r",),
        frozenset({"m", "omega"}),
        lambda: [m * r_ddot - m * r * omega**2],
        m * (r_dot**2 + r**2 * omega**2) / 2,
    ),
]
BY_NAME = {example.name: example for example in EXAMPLES}
NAMES = [example.name for example in EXAMPLES]


@cache
def reference_accelerations(name: str) -> dict[str, sympy.Expr]:
    """The printed equations of ``name`` solved for the accelerations (plain symbols)."""
    example = BY_NAME[name]
    unknowns = [sympy.Symbol(f"{q}_ddot") for q in example.coordinates]
    equations = example.equations()
    for equation in equations:
        assert sympy.Poly(equation, *unknowns).total_degree() == 1, equation
    solution = sympy.solve(equations, unknowns, dict=True)
    assert len(solution) == 1, solution
    return {q: solution[0][a] for q, a in zip(example.coordinates, unknowns, strict=True)}


@cache
def loaded(name: str):
    system = lg.load(name)
    return system, system.equations_of_motion()


def points(name: str, rng: random.Random, count: int = N_POINTS) -> list[dict[str, float]]:
    example = BY_NAME[name]
    system, _ = loaded(name)
    return [random_point(system, rng, example.ranges, avoid=example.avoid) for _ in range(count)]


# -- the checks, for every example ---------------------------------------------------
def test_there_are_ten_examples():
    assert len(set(NAMES)) == 10


@pytest.mark.parametrize("name", NAMES)
def test_coordinates_and_parameters_are_named_as_in_the_reference(name):
    example = BY_NAME[name]
    system, _ = loaded(name)
    assert tuple(c.name for c in system.coordinates) == example.coordinates
    assert {p.name for p in system.parameters} == example.parameters


@pytest.mark.parametrize("name", NAMES)
def test_accelerations_match_the_printed_equations(name, rng):
    example = BY_NAME[name]
    _, eom = loaded(name)
    assert eom.accelerations is not None
    assert set(eom.accelerations) == set(example.coordinates)
    reference = reference_accelerations(name)
    for point in points(name, rng):
        for q in example.coordinates:
            assert_close(
                evaluate(eom.accelerations[q], point, example.functions),
                evaluate(reference[q], point),
                what=f"{name}: {q}_ddot at {point}",
            )


@pytest.mark.parametrize("name", NAMES)
def test_each_equation_vanishes_on_the_reference_accelerations(name, rng):
    example = BY_NAME[name]
    _, eom = loaded(name)
    assert len(eom.equations) == len(example.coordinates)
    reference = {f"{q}_ddot": a for q, a in reference_accelerations(name).items()}
    for point in points(name, rng):
        values = dict(point)
        for q in example.coordinates:  # the accelerations of the motion through this state
            values[f"{q}_ddot"] = evaluate(reference[f"{q}_ddot"], point)
        for q, equation in zip(example.coordinates, eom.equations, strict=True):
            residual = evaluate(equation, values, example.functions)
            scale = scale_of(equation, values, example.functions)
            assert abs(residual) <= 1e-9 * scale, f"{name}: equation of {q} = {residual}"


@pytest.mark.parametrize("name", NAMES)
def test_mass_matrix_form_equals_the_equations_up_to_a_factor_per_row(name, rng):
    """(M q'' - f)_i = c_i(q, q_dot, t) * equations[i], with c_i != 0 and free of q''."""
    example = BY_NAME[name]
    _, eom = loaded(name)
    n = len(example.coordinates)
    assert eom.mass_matrix.shape == (n, n)
    assert eom.forcing.shape == (n, 1)
    accelerations = [sympy.Symbol(f"{q}_ddot") for q in example.coordinates]
    rows = plain(eom.mass_matrix) * sympy.Matrix(accelerations) - plain(eom.forcing)
    for point in points(name, rng, count=3):
        for i, q in enumerate(example.coordinates):
            ratios = []
            for _ in range(3):  # off-shell: independent random accelerations
                values = dict(point)
                values.update({f"{c}_ddot": rng.uniform(-2, 2) for c in example.coordinates})
                equation = evaluate(eom.equations[i], values, example.functions)
                row = evaluate(rows[i], values, example.functions)
                assert abs(equation) > 1e-12, f"{name}: equation of {q} vanished off-shell"
                ratios.append(row / equation)
            assert abs(ratios[0]) > 1e-12
            for ratio in ratios[1:]:
                assert_close(ratio, ratios[0], what=f"{name}: factor of row {q}")


@pytest.mark.parametrize("name", NAMES)
def test_accelerations_solve_the_mass_matrix_form(name, rng):
    example = BY_NAME[name]
    _, eom = loaded(name)
    for point in points(name, rng, count=3):
        values = dict(point)
        for q in example.coordinates:
            values[f"{q}_ddot"] = evaluate(eom.accelerations[q], point, example.functions)
        for i, q in enumerate(example.coordinates):
            residual = sum(
                evaluate(eom.mass_matrix[i, j], values, example.functions) * values[f"{c}_ddot"]
                for j, c in enumerate(example.coordinates)
            ) - evaluate(eom.forcing[i], values, example.functions)
            scale = scale_of(eom.forcing[i], values, example.functions) + sum(
                abs(
                    evaluate(eom.mass_matrix[i, j], values, example.functions) * values[f"{c}_ddot"]
                )
                for j, c in enumerate(example.coordinates)
            )
            assert abs(residual) <= 1e-9 * scale, f"{name}: row {q} of M q'' - f = {residual}"


@pytest.mark.parametrize("name", [n for n in NAMES if n != "velocity_dependent_potential"])
def test_lagrangian_is_the_printed_one_up_to_a_constant(name, rng):
    """L - L_printed has zero gradient in every q, q_dot and t (an additive constant)."""
    example = BY_NAME[name]
    system, _ = loaded(name)
    difference = plain(system.lagrangian) - example.lagrangian
    variables = [t]
    for q in example.coordinates:
        variables += [sympy.Symbol(q), sympy.Symbol(f"{q}_dot")]
    for point in points(name, rng, count=3):
        for variable in variables:
            derivative = sympy.diff(difference, variable)
            scale = scale_of(sympy.diff(example.lagrangian, variable), point) + 1.0
            assert abs(evaluate(derivative, point)) <= 1e-9 * scale, f"{name}: dL/d{variable}"


# -- the by-products stated in the worked examples -----------------------------------
def test_velocity_dependent_potential_lagrangian_is_the_printed_one(rng):
    system, _ = loaded("velocity_dependent_potential")
    assert {f.name for f in system.functions} == {"A", "B", "C", "V"}
    for declaration in system.functions:
        assert [a.name for a in declaration.arguments] == ["x", "y", "z"]
    A, B, C, V = (CONCRETE[name](x, y, z) for name in "ABCV")
    printed = (x_dot**2 + y_dot**2 + z_dot**2) / 2 - V + A * x_dot + B * y_dot + C * z_dot
    for point in points("velocity_dependent_potential", rng, count=3):
        assert_close(evaluate(system.lagrangian, point, CONCRETE), evaluate(printed, point))


def test_velocity_dependent_potential_equations_hold_unspecified_functions():
    """The x-equation holds dA/dy - dB/dx times y_dot with A, B left unspecified."""
    system, eom = loaded("velocity_dependent_potential")
    functions = {f.name: f for f in system.functions}
    a_y = sympy.Derivative(functions["A"].applied, system.symbol("y"))
    b_x = sympy.Derivative(functions["B"].applied, system.symbol("x"))
    x_equation = sympy.expand(eom.equations[0])
    coefficient = x_equation.coeff(system.symbol("y_dot"))
    assert sympy.expand(coefficient**2 - (a_y - b_x) ** 2) == 0
    assert sympy.expand(x_equation.coeff(system.symbol("x_ddot")) ** 2) == 1


def test_double_pendulum_kinetic_energy_is_the_correct_one(rng):
    """Not the lecture's printed T (two typos), but T from the particles' positions."""
    system, _ = loaded("double_pendulum")
    correct = (
        (m1 + m2) * l1**2 * theta1_dot**2 / 2
        + m2 * l2**2 * theta2_dot**2 / 2
        + m2 * l1 * l2 * theta1_dot * theta2_dot * cos(theta1 - theta2)
    )
    assert sympy.simplify(plain(system.kinetic) - correct) == 0
    for point in points("double_pendulum", rng):
        assert_close(evaluate(system.kinetic, point), evaluate(correct, point))


def test_double_pendulum_small_angle_equations(rng):
    """Linearised about rest, the printed small-angle equations hold."""
    _, eom = loaded("double_pendulum")
    small = [
        (m1 + m2) * l1 * theta1_ddot + m2 * l2 * theta2_ddot + (m1 + m2) * g * theta1,
        l2 * theta2_ddot + l1 * theta1_ddot + g * theta2,
    ]
    reference = sympy.solve(small, [theta1_ddot, theta2_ddot], dict=True)[0]
    eps = sympy.Symbol("eps")
    for point in points("double_pendulum", rng, count=3):
        for q, unknown in (("theta1", theta1_ddot), ("theta2", theta2_ddot)):
            scaled = substitute_by_name(
                eom.accelerations[q],
                {
                    "theta1": eps * sympy.Float(point["theta1"]),
                    "theta2": eps * sympy.Float(point["theta2"]),
                    "theta1_dot": eps * sympy.Float(point["theta1_dot"]),
                    "theta2_dot": eps * sympy.Float(point["theta2_dot"]),
                },
            )
            linear = sympy.diff(scaled, eps).subs(eps, 0)
            assert_close(
                evaluate(linear, point),
                evaluate(reference[unknown], point),
                what=f"linearised {q}_ddot",
            )


def test_rotating_wire_kinetic_energy_and_jacobi_integral(rng):
    system, eom = loaded("rotating_wire_bead")
    kinetic = m * (r_dot**2 + r**2 * omega**2) / 2
    assert sympy.simplify(plain(system.kinetic) - kinetic) == 0
    # L is not explicitly time dependent although the constraint is
    assert not system.lagrangian.has(system.symbol("t"))
    # h = r_dot dL/dr_dot - L = m (r_dot^2 - r^2 omega^2)/2 is conserved along the motion
    lagrangian = plain(system.lagrangian)
    h = r_dot * sympy.diff(lagrangian, r_dot) - lagrangian
    assert sympy.simplify(h - m * (r_dot**2 - r**2 * omega**2) / 2) == 0
    h_rate = total_time_derivative(h, ("r",))
    for point in points("rotating_wire_bead", rng):
        values = dict(point, r_ddot=evaluate(eom.accelerations["r"], point))
        assert abs(evaluate(h_rate, values)) <= 1e-9 * scale_of(h_rate, values)


def test_vertical_spring_equilibrium_is_mg_over_k(rng):
    system, eom = loaded("vertical_spring")
    for point in points("vertical_spring", rng):
        at_rest = dict(point, x=point["m"] * point["g"] / point["k"], x_dot=0.0)
        acceleration = evaluate(eom.accelerations["x"], at_rest)
        assert abs(acceleration) <= 1e-9 * point["g"], acceleration
        # and the potential is k x^2/2 - m g x up to a constant
        v = plain(system.potential) - (k * x**2 / 2 - m * g * x)
        assert abs(evaluate(sympy.diff(v, x), point)) <= 1e-9 * (1 + point["k"] + point["g"])


def test_spherical_pendulum_p_phi_is_conserved(rng):
    _, eom = loaded("spherical_pendulum")
    p_phi = m * l**2 * sin(theta) ** 2 * phi_dot
    rate = total_time_derivative(p_phi, ("theta", "phi"))
    for point in points("spherical_pendulum", rng):
        values = dict(point)
        for q in ("theta", "phi"):
            values[f"{q}_ddot"] = evaluate(eom.accelerations[q], point)
        assert abs(evaluate(rate, values)) <= 1e-9 * scale_of(rate, values)


def test_concrete_functions_really_replace_the_unspecified_ones():
    """Guard of the helper: the test above would be vacuous if nothing were replaced."""
    _, eom = loaded("velocity_dependent_potential")
    replaced = substitute_functions(eom.accelerations["x"], CONCRETE)
    assert not replaced.atoms(sympy.Derivative)
    assert {s.name for s in replaced.free_symbols} <= {"x", "y", "z", "x_dot", "y_dot", "z_dot"}

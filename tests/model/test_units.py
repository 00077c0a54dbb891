"""Units in the model file (issue 31): values with units converted to SI at load, every
term's dimension checked, the units of the other names inferred.

The dimensioned models here are written by hand from the built-in examples (the
unitless version is the example itself, or the same text with bare SI numbers): a right
one must give the same equations and the same numbers; a wrong one must be refused with
the one line that names the field, the term as written and both dimensions.
"""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.model.dimensions import (
    DIMENSIONLESS,
    ENERGY,
    FORCE,
    LENGTH,
    MASS,
    RATE,
    describe,
    dimension,
    unit_text,
)

PENDULUM_WITH_UNITS = """
name = "pendulum"
coordinates = ["theta"]
kinetic = "m*l^2*theta_dot^2/2"
potential = "-m*g*l*cos(theta)"
[parameters]
m = "2 kg"
l = "50 cm"
g = "9.81 m/s^2"
b = "0.1 N*m*s"
A = "1.5 N*m"
omega = "120 rpm"
[forces]
theta = "A*cos(omega*t) - b*theta_dot"
[initial]
theta = 0.2
"""
PENDULUM_IN_SI = f"""
name = "pendulum"
coordinates = ["theta"]
kinetic = "m*l^2*theta_dot^2/2"
potential = "-m*g*l*cos(theta)"
[parameters]
m = 2.0
l = 0.5
g = 9.81
b = 0.1
A = 1.5
omega = {120 * 2 * math.pi / 60!r}
[forces]
theta = "A*cos(omega*t) - b*theta_dot"
[initial]
theta = 0.2
"""

CART_POLE_WITH_UNITS = """
name = "Cart-pole"
coordinates = ["x", "theta"]
[parameters]
M = "1 kg"
m = "100 g"
l = "0.5 m"
g = "32.2 ft/s^2"
[[particles]]
name = "cart"
mass = "M"
position = ["x", "0"]
[[particles]]
name = "bob"
mass = "m"
position = ["x + l*sin(theta)", "l*cos(theta)"]
[gravity]
g = "g"
direction = [0, -1]
[inputs]
F = "x"
[units]
x = "cm"
[initial]
x = 10
theta = 0.1
"""

ROLLING_DISC_WITH_UNITS = """
coordinates = ["x", "y", "phi", "theta"]
kinetic = "m*(x_dot^2 + y_dot^2)/2 + (m*R^2/4)*phi_dot^2/2 + (m*R^2/2)*theta_dot^2/2"
potential = "0"
constraints = ["x_dot - R*cos(phi)*theta_dot", "y_dot - R*sin(phi)*theta_dot"]
[parameters]
m = "1 kg"
R = "50 cm"
"""

HEAVY_TOP_WITH_UNITS = """
coordinates = ["phi", "theta", "psi"]
[parameters]
M = "1 kg"
l = "30 cm"
g = "9.81 m/s^2"
I1 = "0.01 kg*m^2"
I3 = "200 kg*cm^2"
[[bodies]]
name = "top"
mass = "M"
position = ["l*sin(theta)*sin(phi)", "-l*sin(theta)*cos(phi)", "l*cos(theta)"]
inertia = ["I1", "I1", "I3"]
orientation = {euler = ["phi", "theta", "psi"], convention = "zxz"}
[gravity]
g = "g"
"""

SPRINGS_WITH_UNITS = """
coordinates = ["x", "y"]
dissipation = "c*(x_dot^2 + y_dot^2)/2"
[parameters]
m = "0.5 kg"
k = "2 N/mm"
L = "20 cm"
c = "0.3 N*s/m"
[[particles]]
name = "p"
mass = "m"
position = ["x", "y"]
[[springs]]
stiffness = "k"
rest_length = "L"
ends = ["p", [0, 0]]
"""


def load_text(tmp_path, text, name="model.toml"):
    path = tmp_path / name
    path.write_text(text)
    return lg.load(path)


def same_equations(a, b):
    left, right = a.equations_of_motion(), b.equations_of_motion()
    return all((x - y).expand() == 0 for x, y in zip(left.equations, right.equations, strict=True))


def test_a_pendulum_with_units_is_the_pendulum_in_si_numbers(tmp_path):
    dimensioned = load_text(tmp_path, PENDULUM_WITH_UNITS, "a.toml")
    plain = load_text(tmp_path, PENDULUM_IN_SI, "b.toml")
    assert plain.units is None
    assert same_equations(dimensioned, plain)
    assert dimensioned.parameter_values == pytest.approx(dict(plain.parameter_values), rel=1e-15)
    assert dimensioned.parameter_values["omega"] == pytest.approx(4 * math.pi)
    assert dimensioned.units.unit("theta") == "rad"
    assert dimensioned.units.unit("theta_dot") == "rad/s"
    assert dimensioned.units.inferred == ("theta",)


def test_the_cart_pole_with_units_converts_its_initial_state_and_infers_its_input(tmp_path):
    dimensioned = load_text(tmp_path, CART_POLE_WITH_UNITS)
    plain = lg.load("cart_pole")
    assert same_equations(dimensioned, plain)
    assert dimensioned.parameter_values["m"] == pytest.approx(0.1)
    assert dimensioned.parameter_values["g"] == pytest.approx(32.2 * 0.3048)
    assert dict(dimensioned.initial) == pytest.approx({"x": 0.1, "theta": 0.1})
    units = dimensioned.units
    assert units.dimension("F") == FORCE  # the generalized force on a length
    assert units.unit("x") == "m"  # declared in cm, computed in m
    assert units.bare("x", 10) == pytest.approx(0.1)
    assert units.unit("x_ddot") == "m/s^2"


def test_the_rolling_disc_infers_its_coordinates_from_its_constraints(tmp_path):
    system = load_text(tmp_path, ROLLING_DISC_WITH_UNITS)
    assert same_equations(system, lg.load("rolling_disc"))
    units = system.units
    assert [units.dimension(n) for n in ("x", "y", "phi", "theta")] == [
        LENGTH, LENGTH, DIMENSIONLESS, DIMENSIONLESS
    ]  # fmt: skip
    assert set(units.inferred) == {"x", "y", "phi", "theta"}


def test_a_3d_body_and_springs_with_units(tmp_path):
    top = load_text(tmp_path, HEAVY_TOP_WITH_UNITS, "top.toml")
    assert same_equations(top, lg.load("heavy_top"))
    assert top.parameter_values["I3"] == pytest.approx(0.02)
    springs = load_text(tmp_path, SPRINGS_WITH_UNITS, "springs.toml")
    assert springs.parameter_values["k"] == pytest.approx(2000.0)
    assert springs.units.dimension("x") == LENGTH


CART_WITH_FRICTION_AND_DEGREES = """
coordinates = ["x", "theta"]
[parameters]
M = "1 kg"
m = "100 g"
l = "0.5 m"
g = "9.81 m/s^2"
r = "5 cm"
mu = 0.1
F0 = "2 N"
tau0 = "3 s"
[[particles]]
name = "cart"
mass = "M"
position = ["x", "0"]
[[particles]]
name = "bob"
mass = "m"
position = ["x + l*sin(theta)", "-l*cos(theta)"]
[gravity]
g = "g"
[forces]
x = "F0*exp(-t/tau0) - mu*M*g*sign(x_dot) - sqrt(M*F0/l)*Abs(x_dot)/10"
[inputs]
tau = {theta = "tau", x = "-tau/r"}
[units]
theta = "deg"
[initial]
theta = 30
theta_dot = 10
"""

CHARGE_IN_A_FIELD = """
coordinates = ["x", "y"]
lagrangian = "m*(x_dot^2 + y_dot^2)/2 - q*V + q*(x_dot*A + y_dot*B)"
[parameters]
m = "1 kg"
q = "1 C"
[functions]
V = ["x", "y"]
A = ["x", "y"]
B = ["x", "y"]
[units]
x = "m"
y = "m"
"""


def test_friction_inputs_and_an_angle_in_degrees(tmp_path):
    system = load_text(tmp_path, CART_WITH_FRICTION_AND_DEGREES)
    assert dict(system.initial) == pytest.approx({"theta": math.pi / 6, "theta_dot": math.pi / 18})
    units = system.units
    assert units.unit("theta") == "rad" and units.unit("mu") == "1"
    assert units.unit("tau") == "J"  # a torque: the generalized force on an angle
    assert units.bare("theta", 90) == pytest.approx(math.pi / 2)


def test_declared_functions_get_their_units_from_the_equations(tmp_path):
    units = load_text(tmp_path, CHARGE_IN_A_FIELD).units
    assert units.unit("V") == "kg*m^2/(s^3*A)"  # a potential: J/C = V
    assert units.unit("A") == "kg*m/(s^2*A)"  # a vector potential: V*s/m = T*m


def model_with(kinetic="m*x_dot^2/2", potential="k*x^2/2", extra="", parameters=""):
    return f"""
coordinates = ["x"]
kinetic = "{kinetic}"
potential = "{potential}"
{extra}
[parameters]
m = "2 kg"
k = "100 N/m"
g = "9.81 m/s^2"
b = "0.5 N*s/m"
w = "3 1/s"
{parameters}
[units]
x = "m"
"""


@pytest.mark.parametrize(
    "text, message",
    [
        (
            model_with(potential="k*x^2/2 + k*x + m*g*x"),
            "potential: the term k*x is a force (N), the other terms are energies (J)",
        ),
        (
            model_with(kinetic="m*x_dot/2"),
            "kinetic: the term m*x_dot/2 is a momentum (kg*m/s), expected an energy (J)",
        ),
        (
            model_with(potential="k*x^2/2 - m*g"),
            "potential: the term m*g is a force (N), the other term is an energy (J)",
        ),
        (
            model_with(potential="k*x^2/2*cos(w)"),
            "potential: the argument w of cos is a rate (1/s), expected dimensionless",
        ),
        (
            model_with(extra='dissipation = "b*x_dot/2"'),
            "dissipation: the term b*x_dot/2 is a force (N), expected a power (W)",
        ),
        (
            model_with(extra='constraints = ["x_dot - w*x - x"]'),
            "constraints[0]: the term x is a length (m), the other terms are velocities (m/s)",
        ),
        (
            model_with(potential="k*(x - m)^2/2"),
            "potential: the term m is a mass (kg), the other term is a length (m)",
        ),
        (
            model_with(potential="k*x^2/2 + exp(x)"),
            "potential: the argument x of exp is a length (m), expected dimensionless",
        ),
    ],
)
def test_a_term_of_the_wrong_dimension_is_named_with_both_dimensions(tmp_path, text, message):
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text)
    assert str(caught.value) == f"{tmp_path / 'model.toml'}: {message}"


@pytest.mark.parametrize(
    "forces, message",
    [
        ('x = "b*x"', "forces.x: the term b*x is a momentum (kg*m/s), expected a force (N)"),
        ('x = "k*x*x"', "forces.x: the term k*x*x is an energy (J), expected a force (N)"),
    ],
)
def test_a_generalized_force_is_energy_per_unit_of_its_coordinate(tmp_path, forces, message):
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, model_with() + f"\n[forces]\n{forces}\n")
    assert str(caught.value).endswith(message)


def test_a_torque_is_expected_on_an_angle(tmp_path):
    text = PENDULUM_WITH_UNITS.replace('"A*cos(omega*t) - b*theta_dot"', '"A/l - b*theta_dot"')
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text)
    assert str(caught.value).endswith(
        "forces.theta: the term A/l is a force (N), the other term is a torque (N*m)"
    )


@pytest.mark.parametrize(
    "component, message",
    [
        (
            '[[particles]]\nmass = "k"\nposition = ["x", "0"]',
            "particles[0].mass: the term k is a stiffness (N/m), expected a mass (kg)",
        ),
        (
            '[[particles]]\nmass = "m"\nposition = ["x + m", "0"]',
            "particles[0].position[0]: the term m is a mass (kg), the other term is a length (m)",
        ),
        (
            '[[particles]]\nmass = "m"\nposition = ["x", "0"]\n[gravity]\ng = "w"',
            "gravity.g: the term w is a rate (1/s), expected an acceleration (m/s^2)",
        ),
        (
            '[[particles]]\nname = "p"\nmass = "m"\nposition = ["x", "0"]\n'
            '[[springs]]\nstiffness = "b"\nends = ["p", [0, 0]]',
            "springs[0].stiffness: the term b is a damping coefficient (N*s/m), expected a "
            "stiffness (N/m)",
        ),
        (
            '[[bodies]]\nmass = "m"\ninertia = "m*L"\ncenter = ["x", "0"]\nangle = "0"',
            "bodies[0].inertia: the term m*L is of dimension kg*m, expected a moment of "
            "inertia (kg*m^2)",
        ),
    ],
)
def test_components_are_checked(tmp_path, component, message):
    text = f"""
coordinates = ["x"]
{component}
[parameters]
m = "2 kg"
k = "100 N/m"
b = "0.5 N*s/m"
w = "3 1/s"
L = "1 m"
"""
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text)
    assert str(caught.value).endswith(message)


def test_names_the_model_leaves_undetermined_are_named_in_one_error(tmp_path):
    text = """
coordinates = ["x"]
lagrangian = "m*x_dot^2/2 - a*b*x^2"
[parameters]
m = "1 kg"
a = 1.0
b = 2.0
"""
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text)
    assert str(caught.value).endswith(
        "units: the units of a, b are not determined by the model: give them in [units] "
        "or with the value"
    )


def test_one_unit_is_enough_when_the_equations_fix_the_rest(tmp_path):
    text = """
coordinates = ["theta"]
lagrangian = "m*l^2*theta_dot^2/2 + m*g*l*cos(theta)"
[parameters]
m = 1.0
l = 2.0
g = "9.81 m/s^2"
"""
    units = load_text(tmp_path, text).units
    assert (units.dimension("m"), units.dimension("l")) == (MASS, LENGTH)
    assert set(units.inferred) == {"theta", "m", "l"}


@pytest.mark.parametrize(
    "entry, message",
    [
        ('l = "3 parsecz"', "parameters.l: unknown unit 'parsecz' (did you mean 'parsec'?)"),
        ('l = "20 degC"', "parameters.l: '20 degC' has a unit with an offset"),
        ('l = "fifty cm"', "parameters.l: expected a number and a unit, such as '50 cm'"),
        ('l = "1 m**99999"', "parameters.l: '1 m**99999': exponents in a unit have at most"),
        ('l = "1 m; import os"', "parameters.l: '1 m; import os' is not a number with a unit"),
    ],
)
def test_a_bad_value_with_a_unit_is_one_line_naming_it(tmp_path, entry, message):
    text = f'coordinates = ["x"]\nlagrangian = "m*x_dot^2/2"\n[parameters]\nm = "1 kg"\n{entry}\n'
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text)
    assert f"{tmp_path / 'model.toml'}: {message}" in str(caught.value)
    assert "\n" not in str(caught.value)


def test_units_of_a_name_the_model_does_not_have_are_refused(tmp_path):
    text = 'coordinates = ["x"]\nlagrangian = "m*x_dot^2/2"\n[parameters]\nm = 1.0\n'
    text += '[units]\nz = "m"\n'
    with pytest.raises(ModelError, match=r"units\.z: not a coordinate, parameter, input or"):
        load_text(tmp_path, text)


def test_a_value_and_a_units_entry_must_agree(tmp_path):
    text = (
        'coordinates = ["x"]\nlagrangian = "m*x_dot^2/2"\n[parameters]\nm = "1 m"\n'
        '[units]\nm = "kg"\n'
    )
    with pytest.raises(ModelError, match=r"parameters\.m: '1 m' is a length"):
        load_text(tmp_path, text)


def test_dimension_names():
    assert describe(ENERGY, plural=True) == "energies (J)"
    assert describe(dimension(mass=1, length=1, time=-3)) == "of dimension kg*m/s^3"
    assert unit_text(RATE, angle=True) == "rad/s"
    assert unit_text(dimension(length=Fraction_half())) == "m^(1/2)"


def Fraction_half():
    from fractions import Fraction

    return Fraction(1, 2)


def test_a_model_without_units_loads_no_unit_library():
    code = "import lagrangian as lg, sys; lg.load('double_pendulum'); print('pint' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"
    assert lg.load("double_pendulum").units is None


def test_a_drag_term_of_the_wrong_power_is_named_as_written(tmp_path):
    text = CART_WITH_FRICTION_AND_DEGREES.replace("Abs(x_dot)/10", "Abs(x_dot) * x_dot/10")
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text)
    assert str(caught.value).endswith(
        "forces.x: the term sqrt(M*F0/l)*Abs(x_dot) * x_dot/10 is a power (W), the other "
        "terms are forces (N)"
    )


def test_initial_values_may_carry_units(tmp_path):
    text = PENDULUM_WITH_UNITS.replace("theta = 0.2", 'theta = "30 deg"\ntheta_dot = "60 rpm"')
    system = load_text(tmp_path, text)
    assert dict(system.initial) == pytest.approx({"theta": math.pi / 6, "theta_dot": 2 * math.pi})
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text.replace('"60 rpm"', '"3 m"'))
    assert str(caught.value).endswith(
        "initial.theta_dot: theta_dot is an angular rate (rad/s) but the value is a length (m)"
    )


@pytest.mark.parametrize(
    "force, message",
    [
        ("A*cos(omega*t) - theta_dot",
         "the term theta_dot is an angular rate (rad/s), the other term is a torque (N*m)"),
        ("A*cos(omega*t) - b*theta_dot - theta_dot",
         "the term theta_dot is an angular rate (rad/s), the other terms are torques (N*m)"),
        ("A*cos(omega*t) - omega",  # a parameter's rate is not an angle's velocity
         "the term omega is a rate (1/s), the other term is a torque (N*m)"),
    ],
)  # fmt: skip
def test_an_angles_rate_is_said_in_radians_per_second(tmp_path, force, message):
    text = PENDULUM_WITH_UNITS.replace('"A*cos(omega*t) - b*theta_dot"', f'"{force}"')
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text)
    assert str(caught.value).endswith(f"forces.theta: {message}")


@pytest.mark.parametrize(
    "potential, message",
    [
        (
            "k*x^2/2*atan2(x, w)",
            "potential: the argument w of atan2 is a rate (1/s), the other argument is a "
            "length (m)",
        ),
        (r"\\frac{1}{2} k x^2 + \\frac{1}{2} m x", r"potential: the term \\frac{1}{2} m x is of"),
    ],
)
def test_arguments_and_latex_terms_are_named_as_written(tmp_path, potential, message):
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, model_with(potential=potential))
    assert message.replace("\\\\", "\\") in str(caught.value)

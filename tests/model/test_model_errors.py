"""Malformed and hostile model files: a ModelError naming file and field, nothing executed."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.errors import ModelError

PENDULUM = """
coordinates = ["theta"]
[parameters]
m = 1.0
l = 1.0
g = 9.81
"""


def load_text(tmp_path, text):
    path = tmp_path / "model.toml"
    path.write_text(text)
    return lg.load(path)


@pytest.mark.parametrize(
    "text, field, fragment",
    [
        # code injection: nothing is evaluated
        ("lagrangian = \"__import__('os').system('touch pwned')\"", "lagrangian", ""),
        ('lagrangian = "().__class__.__bases__[0]"', "lagrangian", ""),
        ("lagrangian = \"eval('1')\"", "lagrangian", "eval"),
        ('lagrangian = "lambda: 0"', "lagrangian", ""),
        ('lagrangian = "m*theta_dot**2; import os"', "lagrangian", ""),
        # resource exhaustion
        ('lagrangian = "9**9**9**9"', "lagrangian", ""),
        ('lagrangian = "10**10**10 * theta_dot**2"', "lagrangian", ""),
        ('lagrangian = "' + "(" * 5000 + "theta" + ")" * 5000 + '"', "lagrangian", ""),
        ('lagrangian = "' + "theta_dot+" * 30000 + 'theta"', "lagrangian", ""),
        # unknown symbols and misplaced names
        ('lagrangian = "m*l**2*theta_dot**2/2 + q*cos(theta)"', "lagrangian", "'q'"),
        ('lagrangian = "m*theta_ddot*theta"', "", "accelerations"),
        ('lagrangian = "foo(theta)"', "lagrangian", "foo"),
    ],
)
def test_hostile_expressions_are_refused(tmp_path, text, field, fragment):
    with pytest.raises(ModelError) as caught:
        load_text(
            tmp_path, PENDULUM.replace("[parameters]", text + "\n[parameters]")
        ).equations_of_motion()
    message = str(caught.value)
    assert "model.toml" in message
    assert field in message and fragment in message
    assert "\n" not in message
    assert not (tmp_path / "pwned").exists()


@pytest.mark.parametrize(
    "text, fragment",
    [
        ("coordinates = [", "invalid TOML"),
        ('name = "x"', "coordinates: missing field"),
        ('coordinates = "theta"\nlagrangian = "theta_dot**2"', "coordinates: expected a list"),
        ('coordinates = []\nlagrangian = "1"', "non-empty list"),
        ('coordinates = ["theta", "theta"]\nlagrangian = "theta_dot**2"', "listed twice"),
        ('coordinates = ["t"]\nlagrangian = "t_dot**2"', "reserved"),
        ('coordinates = ["x_dot"]\nlagrangian = "1"', "must not end in _dot"),
        ('coordinates = ["x"]\nlagrangian = 3\nbogus = 1', "bogus: unknown key"),
        ('coordinates = ["x"]\nlagrangian = true', "lagrangian: expected an expression"),
        ('coordinates = ["x"]\nlagrangian = ["x"]', "lagrangian: expected an expression"),
        ('coordinates = ["x"]\nlagrangian = "x_dot**2"\n[parameters]\nm = "heavy"', "parameters.m"),
        ('coordinates = ["x"]\nlagrangian = "x_dot**2"\n[parameters]\nx = 1.0', "declared twice"),
        ('coordinates = ["x"]\nlagrangian = "x_dot**2"\n[parameters]\nsin = 1.0', "reserved"),
        (
            'coordinates = ["x"]\nlagrangian = "x_dot**2"\n'
            '[parameters]\nk = {value = -1.0, sign = "positive"}',
            "contradicts",
        ),
        ('coordinates = ["x"]\nkinetic = "x_dot**2"\nlagrangian = "x_dot**2"', "not both"),
        ('coordinates = ["x"]\npotential = "x**2"', "no kinetic energy"),
        ('coordinates = ["x"]\nlagrangian = "x_dot**2"\n[forces]\ny = "1"', "forces.y"),
        ('coordinates = ["x"]\nlagrangian = "x_dot**2"\n[initial]\nz = 1.0', "initial.z"),
        ('coordinates = ["x"]\nlagrangian = "x_dot**2"\n[simulate]\nspeed = 1', "simulate.speed"),
        (
            'coordinates = ["x"]\n[[particles]]\nmass = "1"\nposition = ["x_dot", "0"]',
            "particles[0].position[0]",
        ),
        ('coordinates = ["x"]\n[[particles]]\nmass = "1"\nposition = ["x"]', "2 or 3 components"),
        ('coordinates = ["x"]\n[[particles]]\nposition = ["x", "0"]', "particles[0].mass: missing"),
        (
            'coordinates = ["x"]\n[[particles]]\nmass = 1\nposition = ["x", 0]\n'
            '[[springs]]\nstiffness = 1\nends = ["nobody", [0, 0]]',
            "no particle or body named 'nobody'",
        ),
        (
            'coordinates = ["x", "y"]\nkinetic = "(x_dot**2 + y_dot**2)/2"\n'
            '[conservative_forces]\nx = "y"\ny = "-x"',
            "do not derive from a potential",
        ),
        ('coordinates = ["x"]\nlagrangian = "x_dot**2"\n[functions]\nA = ["q"]', "functions.A"),
    ],
)
def test_malformed_models_name_the_field(tmp_path, text, fragment):
    with pytest.raises(ModelError) as caught:
        load_text(tmp_path, text)
    message = str(caught.value)
    assert fragment in message
    assert message.startswith(str(tmp_path / "model.toml"))
    assert "\n" not in message


def test_singular_mass_matrix_names_the_coordinate(tmp_path):
    system = load_text(
        tmp_path, 'coordinates = ["x", "y"]\nlagrangian = "x_dot**2/2 + y_dot*x - y**2"'
    )
    with pytest.raises(lg.SingularMassMatrixError, match="no kinetic term for y"):
        system.equations_of_motion()


def test_missing_file_and_unknown_example():
    with pytest.raises(ModelError, match="no such model file"):
        lg.load("definitely_not_an_example")
    with pytest.raises(ModelError, match="no such model file"):
        lg.load("missing.toml")


def test_huge_powers_of_velocities_derive_without_overflow(tmp_path):
    # (x_dot + 1)**999 overflows floats at the rank check; the symbolic answer stays exact
    system = load_text(
        tmp_path, 'coordinates = ["x"]\nlagrangian = "(x_dot + 1)**999*(x + 1)**999"'
    )
    acceleration = system.equations_of_motion().accelerations["x"]
    x, x_dot = system.symbol("x"), system.symbol("x_dot")
    expected = (1 - 998 * x_dot) * (x_dot + 1) / (998 * (x + 1))
    assert (acceleration - expected).equals(0)


def test_singular_error_names_the_file(tmp_path):
    system = load_text(tmp_path, 'coordinates = ["x"]\nlagrangian = "3*x_dot - x**2"')
    with pytest.raises(lg.SingularMassMatrixError, match=r"model\.toml: singular mass matrix"):
        system.equations_of_motion()

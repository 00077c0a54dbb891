"""The editor's text as a model: a model file (TOML) or a Lagrangian alone."""

from __future__ import annotations

import pytest

from lagrangian.errors import ModelError
from lagrangian.examples import example_path
from lagrangian.facade import load
from lagrangian.serve.models import PARAMETER_START, model_from_text


def test_a_lagrangian_alone_has_the_coordinates_of_its_velocities():
    system = model_from_text("m*l**2*theta_dot**2/2 + m*g*l*cos(theta) + b*phi_dot*theta")
    assert system.coordinate_names == ("phi", "theta")
    assert system.parameter_names == ("b", "g", "l", "m")
    assert all(p.default == PARAMETER_START for p in system.parameters)


def test_time_is_not_a_parameter_and_a_leading_l_is_allowed():
    system = model_from_text("L = x_dot**2/2 - x**2*cos(w*t)/2")
    assert system.coordinate_names == ("x",)
    assert system.parameter_names == ("w",)
    assert system.lagrangian.has(system.time)


def test_a_latex_lagrangian_is_read_as_latex():
    system = model_from_text(r"\frac{1}{2} m \dot{x}^2 - \frac{1}{2} k x^2")
    assert system.coordinate_names == ("x",)
    assert system.parameter_names == ("k", "m")


def test_a_text_with_an_equals_sign_is_a_model_file():
    from_file = load("double_pendulum")
    typed = model_from_text(example_path("double_pendulum").read_text())
    assert (typed.name, typed.lagrangian) == (from_file.name, from_file.lagrangian)
    assert typed.parameter_values == from_file.parameter_values


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "editor: type a model file (TOML) or a Lagrangian, e.g. m*x_dot**2/2 - k*x**2/2"),
        (
            "m*x**2",
            "editor: lagrangian: the Lagrangian has no velocity: write the velocity of a "
            "coordinate q as q_dot",
        ),
        (
            "x_dot**2 +",
            "editor: lagrangian: unexpected end of expression at position 11 in 'x_dot**2 +'",
        ),
        ("x_dot**2 + __import__('os')", "editor: lagrangian:"),
        ("coordinates = 3", "editor: "),
    ],
)
def test_a_bad_text_is_one_line_naming_the_editor(text, message):
    with pytest.raises(ModelError) as caught:
        model_from_text(text)
    assert str(caught.value).startswith(message)
    assert "\n" not in str(caught.value)

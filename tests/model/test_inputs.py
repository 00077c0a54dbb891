"""Inputs ([inputs] in a model file, ``inputs=`` in Python): their forces, errors, simulation."""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.cli import main

CART = """
name = "Pushed cart"
coordinates = ["x", "theta"]
[parameters]
M = 2.0
m = 0.5
l = 1.0
g = 9.81
b = 0.3
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
x = "-b*x_dot"
[inputs]
F = "x"
tau = {theta = "tau", x = "-tau/l"}
"""

SLIDER = """
coordinates = ["x"]
kinetic = "m*x_dot**2/2"
potential = "0"
[parameters]
m = 2.0
[initial]
x = 0.5
x_dot = -1.0
[inputs]
F = "x"
"""


def load_text(tmp_path, text, name="model.toml"):
    path = tmp_path / name
    path.write_text(text)
    return lg.load(path)


def test_inputs_add_their_generalized_forces(tmp_path):
    system = load_text(tmp_path, CART)
    F, tau, b, l = (system.symbol(n) for n in ("F", "tau", "b", "l"))
    x_dot = system.symbol("x_dot")
    assert system.input_names == ("F", "tau")
    assert system.forces["x"] - (-b * x_dot + F - tau / l) == 0
    assert system.forces["theta"] == tau
    assert dict(system.inputs[1].forces) == {"theta": tau, "x": -tau / l}
    # each input is a real parameter with default 0, after the declared ones
    assert system.parameter_names[-2:] == ("F", "tau")
    parameters = {p.name: p for p in system.parameters}
    assert parameters["F"].default == 0.0 and parameters["F"].sign == "real"
    assert F.is_real and F.is_positive is None
    eom = system.equations_of_motion()
    assert eom.forcing[0].has(F) and eom.forcing[1].has(tau)


def test_python_constructors_take_inputs():
    system = lg.System.from_lagrangian(
        "m*x_dot**2/2 - k*x**2/2", coordinates=["x"], inputs={"u": {"x": "2*u"}}
    )
    assert system.input_names == ("u",)
    assert system.forces["x"] == 2 * system.symbol("u")
    assert set(system.parameter_names) == {"k", "m", "u"}  # undeclared k, m: positive parameters
    assert system.symbol("u").is_positive is None


def test_without_inputs_is_the_free_system(tmp_path):
    system = load_text(tmp_path, CART)
    free = system.without_inputs()
    assert free.inputs == () and "F" not in free.parameter_names
    assert free.forces["x"] == -system.symbol("b") * system.symbol("x_dot")
    assert "theta" not in free.forces
    held = system.without_inputs({"F": 1.5})
    assert (
        held.forces["x"] - (sympy.Rational(3, 2) - system.symbol("b") * system.symbol("x_dot")) == 0
    )
    with pytest.raises(lg.ModelError, match="'G' is not an input"):
        system.without_inputs({"G": 1.0})


def test_analysis_holds_the_inputs_at_zero(tmp_path):
    """Without damping the cart's momentum p_x and the energy are conserved at u = 0."""
    system = load_text(tmp_path, CART.replace('[forces]\nx = "-b*x_dot"\n', ""))
    names = {q.name for q in system.conserved_quantities().conserved}
    assert {"p_x", "energy"} <= names
    points = [dict(e.point) for e in system.equilibria()]
    assert {"theta": 0} in points and {"theta": sympy.pi} in points


def test_simulate_with_a_constant_input_matches_the_closed_form(tmp_path):
    """m x'' = F: x(t) = x0 + v0 t + F t^2 / (2 m); without --set F the input is 0."""
    system = load_text(tmp_path, SLIDER)
    pushed = system.simulate(t_end=2.0, params={"F": 3.0}, rtol=1e-12, atol=1e-12)
    t = pushed.t
    expected = 0.5 - 1.0 * t + 3.0 * t**2 / (2 * 2.0)
    assert np.abs(pushed["x"] - expected).max() < 1e-9
    free = system.simulate(t_end=2.0, rtol=1e-12, atol=1e-12)
    assert np.abs(free["x"] - (0.5 - 1.0 * free.t)).max() < 1e-9


def test_cli_set_gives_an_input_and_derive_lists_it(tmp_path, capsys):
    path = tmp_path / "slider.toml"
    path.write_text(SLIDER)
    status = main(["simulate", str(path), "--t-end", "2", "--set", "F=3", "--rtol", "1e-12",
                   "--atol", "1e-12", "--json"])  # fmt: skip
    summary = json.loads(capsys.readouterr().out)
    assert status == 0
    assert summary["final_state"]["x"] == pytest.approx(0.5 - 2.0 + 3.0 * 4 / 4, abs=1e-8)
    assert summary["final_state"]["x_dot"] == pytest.approx(-1.0 + 3.0 * 2 / 2, abs=1e-8)
    assert main(["derive", str(path), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert "F" in document["parameters"]
    assert sympy.sympify(document["forcing"][0]) == sympy.Symbol("F")


@pytest.mark.parametrize(
    ("entry", "field", "message"),
    [
        ('F = "y"', "inputs.F", "'y' is not a coordinate"),
        ('F = {y = "F"}', "inputs.F.y", "'y' is not a coordinate"),
        ('F = {x = "2*m"}', "inputs.F.x", "does not depend on the input 'F'"),
        ("F = 3", "inputs.F", "expected the name of a coordinate or a table"),
        ("F = {}", "inputs.F", "acts on at least one coordinate"),
        ('m = "x"', "inputs.m", "declared both as a parameter and as an input"),
        ('x_dot = "x"', "inputs.x_dot", "declared twice"),
        ('t = "x"', "inputs.t", "reserved"),
        ('F = {x = "F +"}', "inputs.F.x", ""),
        ('F = {x = "G"}', "inputs.F.x", "'G'"),
    ],
)
def test_bad_inputs_are_one_line_errors_naming_file_and_field(tmp_path, entry, field, message):
    text = SLIDER.replace('F = "x"', entry)
    with pytest.raises(lg.ModelError) as caught:
        load_text(tmp_path, text)
    shown = str(caught.value)
    assert "\n" not in shown
    assert shown.startswith(f"{tmp_path / 'model.toml'}: {field}")
    assert message in shown


def test_an_input_outside_inputs_is_refused(tmp_path):
    text = SLIDER.replace('potential = "0"', 'potential = "F*x"')
    with pytest.raises(lg.ModelError, match=r"potential: the input 'F' may appear only in"):
        load_text(tmp_path, text)


def test_inputs_table_of_wrong_type_and_cli_exit_status(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    text = SLIDER.replace('[inputs]\nF = "x"', "").replace(
        "[parameters]", 'inputs = ["F"]\n[parameters]'
    )
    path.write_text(text)
    assert main(["derive", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "inputs: expected a table" in err


def test_change_of_coordinates_moves_the_inputs():
    """F along x on a particle: in polar coordinates Q_r = F cos(theta), Q_theta = -F r sin(theta)
    (F . dr/dq), for the model's forces and for the input's own table alike."""
    system = lg.System.from_particles(
        ["x", "y"],
        [lg.Particle("p", "m", ("x", "y"))],
        parameters={"m": 1.0, "g": 9.81},
        gravity=lg.Gravity("g"),
        inputs={"F": "x"},
    )
    polar = system.change_coordinates(["r", "theta"], {"x": "r*cos(theta)", "y": "r*sin(theta)"})
    F, r, theta = (polar.symbol(n) for n in ("F", "r", "theta"))
    expected = {"r": F * sympy.cos(theta), "theta": -F * r * sympy.sin(theta)}
    assert polar.input_names == ("F",)
    for table in (polar.forces, polar.inputs[0].forces):
        assert set(table) == set(expected)
        assert all(sympy.simplify(table[k] - expected[k]) == 0 for k in expected)

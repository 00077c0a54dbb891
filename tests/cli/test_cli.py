"""The command line, run in-process through ``main(argv)``."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest
import sympy

from lagrangian.cli import ExitStatus, main
from lagrangian.examples import example_names

WORKED_EXAMPLES = (
    "simple_pendulum",
    "velocity_dependent_potential",
    "harmonic_oscillator",
    "central_force",
    "spherical_pendulum",
    "double_pendulum",
    "vertical_spring",
    "free_particle_spherical",
    "planar_particle_forces",
    "rotating_wire_bead",
)


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_examples_lists_the_ten_worked_examples(capsys):
    status, out, _ = run(capsys, "examples")
    assert status == ExitStatus.SUCCESS
    for name in WORKED_EXAMPLES:
        assert name in out
    assert len(out.strip().splitlines()) == len(example_names())


def test_examples_lists_from_the_files_what_the_built_models_say(capsys, monkeypatch):
    # the listing reads each file's name and coordinates without building a model (fast);
    # what it prints must still be what the built model says
    import lagrangian.facade

    monkeypatch.setattr(lagrangian.facade, "load", None)  # not called by the listing
    status, out, _ = run(capsys, "examples")
    monkeypatch.undo()
    assert status == ExitStatus.SUCCESS
    for line, name in zip(out.splitlines(), example_names(), strict=True):
        system = lagrangian.facade.load(name)
        assert line == f"{name:30s} {system.name}  ({', '.join(system.coordinate_names)})"


def test_rotating_wire_prints_textbook_acceleration(capsys):
    status, out, _ = run(capsys, "derive", "rotating_wire_bead")
    assert status == ExitStatus.SUCCESS
    assert "r̈ = ω² r" in out


def test_derive_json_reads_back_with_sympy(capsys):
    status, out, _ = run(capsys, "derive", "double_pendulum", "--json")
    assert status == ExitStatus.SUCCESS
    document = json.loads(out)
    assert document["coordinates"] == ["theta1", "theta2"]
    assert document["parameters"] == ["g", "l1", "l2", "m1", "m2"]
    names = {n: sympy.Symbol(n) for n in ["theta1", "theta2", "theta1_dot", "theta2_dot"]}
    names |= {n: sympy.Symbol(n) for n in document["parameters"]}
    for text in document["accelerations"].values():
        expr = sympy.parse_expr(text, local_dict=names)  # trusted: our own output
        assert expr.free_symbols <= set(names.values())
    assert len(document["mass_matrix"]) == 2 and len(document["forcing"]) == 2


def test_derive_latex_uses_dot_notation(capsys):
    status, out, _ = run(capsys, "derive", "simple_pendulum", "--latex")
    assert status == ExitStatus.SUCCESS
    assert r"\ddot{\theta}" in out and r"\begin{align*}" in out


def test_steps_show_the_hand_derivation(capsys):
    status, out, _ = run(capsys, "derive", "simple_pendulum", "--steps")
    assert status == ExitStatus.SUCCESS
    for piece in ["T = ", "V = ", "L = ", "∂L/∂θ̇ = ", "d/dt(∂L/∂θ̇) = ", "∂L/∂θ = ", "θ̈ = "]:
        assert piece in out
    status, out, _ = run(capsys, "derive", "simple_pendulum", "--steps", "--latex")
    assert r"\frac{\partial L}{\partial \dot{\theta}}" in out


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["derive", "no_such_model"], "no such model file or built-in example"),
        (["derive"], "give MODEL (a model file or example) or --lagrangian"),
        (["derive", "simple_pendulum", "--json", "--latex"], "choose one of"),
        (["frobnicate"], "No such command"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(capsys, argv, fragment):
    status, out, err = run(capsys, *argv)
    assert status == ExitStatus.BAD_INPUT
    assert out == ""
    assert fragment in err
    assert len(err.strip().splitlines()) == 1


def test_console_script_exit_codes(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('coordinates = ["x"]\nlagrangian = "x_dot**2/2 - __import__(1)"\n')
    result = subprocess.run(
        [sys.executable, "-m", "lagrangian", "derive", str(bad)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2
    assert "bad.toml" in result.stderr and "lagrangian" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert result.stdout == ""


def test_derive_takes_a_lagrangian_string(capsys):
    text = "m*l^2*theta_dot^2/2 + m*g*l*cos(theta)"
    status, out, _ = run(capsys, "derive", "--lagrangian", text, "--coordinates", "theta", "--json")
    assert status == ExitStatus.SUCCESS
    document = json.loads(out)
    assert document["coordinates"] == ["theta"]
    assert document["parameters"] == ["g", "l", "m"]
    assert document["accelerations"] == {"theta": "-g*sin(theta)/l"}


def test_analyze_and_simulate_take_a_lagrangian_string(capsys):
    two = ("--lagrangian", "x_dot^2/2 + y_dot^2/2 - k*(x^2 + y^2)/2", "--coordinates", "x, y")
    status, out, _ = run(capsys, "analyze", *two, "--json", "--timeout", "120")
    assert status == ExitStatus.SUCCESS
    assert json.loads(out)["equilibria"][0]["omega_squared"] == ["k", "k"]
    status, out, _ = run(capsys, "simulate", *two, "--set", "k=1", "--set", "x=1", "--json")
    assert status == ExitStatus.SUCCESS
    assert set(json.loads(out)["final_state"]) == {"x", "y", "x_dot", "y_dot"}


COUPLED = "x_dot^2/2 + y_dot^2/2 - k*(x^2 + y^2)/2 - c*(x - y)^2/2"


def test_analyze_prints_the_modes_as_numbers_at_the_set_values(capsys):
    # two oscillators coupled by a spring: ω² = k and k + 2c, shapes (1, 1) and (1, -1)
    given = ("--lagrangian", COUPLED, "--coordinates", "x,y", "--set", "k=4", "--set", "c=0.5")
    status, out, _ = run(capsys, "analyze", *given, "--json", "--timeout", "120")
    assert status == ExitStatus.SUCCESS
    (rest,) = json.loads(out)["equilibria"]
    numbers = rest["at_parameter_values"]
    assert numbers["parameters"] == {"c": 0.5, "k": 4.0}
    assert numbers["omega_squared"] == pytest.approx([4.0, 5.0])
    assert numbers["omega"] == pytest.approx([2.0, 5**0.5])
    assert numbers["periods"] == pytest.approx([math.pi, 2 * math.pi / 5**0.5])
    shapes = [x for shape in numbers["mode_shapes"] for x in shape]
    assert shapes == pytest.approx([1.0, 1.0, 1.0, -1.0])
    status, out, _ = run(capsys, "analyze", *given, "--timeout", "120")
    assert (
        "    at c = 0.5, k = 4: ω² = 4, 5\n      ω = 2, 2.23607;  periods 3.14159, 2.80993" in out
    )
    assert "      mode shapes: (1, 1), (1, -1)" in out


def test_analyze_set_is_checked_as_the_run_commands_check_it(capsys):
    status, _, err = run(capsys, "analyze", "simple_pendulum", "--set", "l=-2")
    assert status == ExitStatus.BAD_INPUT
    assert "parameter l = -2 breaks the model's assumption that l is positive" in err


def test_derive_steps_says_where_an_equation_is_divided_by_a_common_factor(capsys):
    status, out, _ = run(capsys, "derive", "simple_pendulum", "--steps")
    assert status == ExitStatus.SUCCESS
    assert "  equation: l θ̈ + g sin(θ) = 0   (divided by l m)\n" in out
    status, out, _ = run(capsys, "derive", "harmonic_oscillator", "--steps")
    assert "  equation: m ẍ + k x = 0\n" in out  # nothing divided: nothing said
    status, out, _ = run(capsys, "derive", "simple_pendulum", "--steps", "--latex")
    assert r"&&\text{(divided by } l m\text{)}" in out

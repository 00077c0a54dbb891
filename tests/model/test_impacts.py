"""``[[impacts]]`` in model files: read, checked, and refused with one line naming the field."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.cli import main
from lagrangian.errors import ModelError

BALL = """
name = "Ball"
coordinates = ["y"]
kinetic = "m*y_dot^2/2"
potential = "m*g*y"
[parameters]
m = 1.0
g = 9.81
e = 0.9
[[impacts]]
gap = "y"
restitution = "e"
[initial]
y = 1.0
"""


def write(tmp_path, text):
    path = tmp_path / "ball.toml"
    path.write_text(text)
    return path


def test_an_impact_is_read_with_its_default_name_and_parsed_expressions(tmp_path):
    system = lg.load(write(tmp_path, BALL))
    (contact,) = system.impacts
    assert contact.name == "contact1"
    assert contact.gap == system.symbol("y")
    assert contact.restitution == system.symbol("e")


@pytest.mark.parametrize(
    "old, new, line",
    [
        ('gap = "y"', 'gap = "m - 1"',
         "impacts[0].gap: the gap does not depend on the coordinates: it can never close in "
         "'m - 1'"),
        ("e = 0.9", "e = 1.5",
         "impacts[0].restitution: the restitution must be from 0 to 1, not 1.5 in 'e'"),
        ('restitution = "e"', 'restitution = "-0.25"',
         "impacts[0].restitution: the restitution must be from 0 to 1, not -0.25 in '-1/4'"),
        ("y = 1.0", "y = -0.5",
         "impacts[0].gap: the initial state penetrates the contact 'contact1': its gap is "
         "-0.5 < 0 in 'y'"),
        ('gap = "y"', 'gap = "y + z"',
         "impacts[0].gap: unknown symbol 'z' at position 5 in 'y + z'"),
        ('gap = "y"', 'gap = "y_dot"',
         "impacts[0].gap: 'y_dot' (velocities) is not allowed here; this field may depend on "
         "coordinates, parameters, t in 'y_dot'"),
        ('restitution = "e"', 'restitution = "y"',
         "impacts[0].restitution: 'y' (coordinates) is not allowed here; this field may depend "
         "on parameters in 'y'"),
        ('restitution = "e"\n', 'restitution = "e"\nwall = 1\n',
         "impacts[0].wall: unknown key (expected one of gap, name, restitution)"),
        ('restitution = "e"\n', "", "impacts[0].restitution: missing field"),
        ('gap = "y"', "gap = true",
         "impacts[0].gap: expected an expression (text or number), got bool"),
        ('gap = "y"', 'gap = "y"\nname = "g"', "impacts[0].name: 'g' is declared twice"),
        ('gap = "y"', 'gap = "y"\nname = "no way"', "impacts[0].name: invalid name 'no way'"),
    ],
)  # fmt: skip
def test_bad_impacts_are_one_line_naming_the_field(tmp_path, capsys, old, new, line):
    assert old in BALL
    path = write(tmp_path, BALL.replace(old, new))
    status = main(["derive", str(path)])
    err = capsys.readouterr().err
    assert status == 2
    assert err == f"lagrangian: error: {path}: {line}\n"


def test_a_restitution_given_with_set_is_checked(tmp_path, capsys):
    path = write(tmp_path, BALL)
    status = main(["simulate", str(path), "--set", "e=2", "--json"])
    assert status == 2
    assert "impacts[0].restitution: the restitution must be from 0 to 1, not 2" in (
        capsys.readouterr().err
    )


def test_an_initial_state_given_with_set_that_penetrates_is_refused(tmp_path, capsys):
    path = write(tmp_path, BALL)
    status = main(["simulate", str(path), "--set", "y=-0.25", "--json"])
    err = capsys.readouterr().err
    assert status == 2
    assert err.count("\n") == 1
    assert "impacts[0].gap: the initial state penetrates the contact 'contact1'" in err


def test_a_restitution_in_units_is_dimensionless_and_the_gap_any_length(tmp_path, capsys):
    text = BALL.replace("[initial]", '[units]\ny = "m"\nm = "kg"\ng = "m/s^2"\n[initial]')
    system = lg.load(write(tmp_path, text))
    assert system.impacts[0].name == "contact1"
    bad = text.replace("e = 0.9", 'e = "0.9 m"')
    with pytest.raises(ModelError, match=r"impacts\[0\]\.restitution"):
        lg.load(write(tmp_path, bad))


@pytest.mark.parametrize(
    "argv, what",
    [
        (["ensemble", "bouncing_ball", "--grid", "y=0.5:1:3", "--t-end", "1"], "an ensemble"),
        (["lyapunov", "bouncing_ball", "--t-end", "1"], "this command"),
        (["sensitivity", "bouncing_ball", "--wrt", "g", "--t-end", "1"], "this command"),
    ],
)
def test_runs_that_would_pass_through_the_contacts_are_refused(capsys, argv, what):
    from lagrangian.examples import example_path

    status = main(argv)
    err = capsys.readouterr().err
    assert status == 2
    assert err == (
        f"lagrangian: error: {example_path('bouncing_ball')}: impacts: {what} "
        + ("(Lyapunov, sensitivities, sections, orbits, fit) " if what == "this command" else "")
        + "does not take contacts yet ([[impacts]]): its runs would pass through them; "
        "simulate, plot and animate do\n"
    )


def test_the_automatic_choice_never_gives_taylor_a_run_with_contacts():
    from lagrangian.integrate.choice import _taylor_problem
    from lagrangian.numeric import compile_equations

    compiled = compile_equations(lg.load("impact_oscillator").equations_of_motion())
    y0, p = compiled.state_vector(), compiled.parameter_vector()
    assert _taylor_problem(compiled, y0, p) == "does not stop at impacts"
    plain = compile_equations(lg.load("harmonic_oscillator").equations_of_motion())
    assert _taylor_problem(plain, plain.state_vector(), plain.parameter_vector()) is None


@pytest.mark.parametrize(
    ("gap", "factor"),
    [("y^3", "y**3"), ("y^2", "y**2"), ("(y - 1)^2", "(y - 1)**2"), ("y^2 - 2*y + 1", "(y - 1)**2"),
     ("(2 + sin(y))*sin(y)^2", "sin(y)**2")],
)  # fmt: skip
def test_a_gap_that_touches_zero_without_crossing_is_refused_at_load(tmp_path, capsys, gap, factor):
    # y^2 >= 0 everywhere: the ball would pass through the floor without an impact, silently
    path = write(tmp_path, BALL.replace('gap = "y"', f'gap = "{gap}"'))
    status = main(["simulate", str(path), "--t-end", "2", "--json"])
    err = capsys.readouterr().err
    assert status == 2
    assert err.startswith(f"lagrangian: error: {path}: impacts[0].gap: the gap's factor {factor} ")
    assert "no contact is ever seen: write a gap that crosses 0 (y, not y^2)" in err
    assert err.count("\n") == 1


def test_a_gap_crossing_zero_with_a_nonzero_gradient_is_kept(tmp_path):
    for gap in ("y", "y - sin(y)/10", "y^3 + y", "y^2 + y", "exp(y) - 1"):
        path = write(tmp_path, BALL.replace('gap = "y"', f'gap = "{gap}"'))
        assert lg.load(path).impacts[0].gap.free_symbols == {lg.load(path).coordinates[0].q}


def test_a_restitution_of_one_set_on_the_command_line_keeps_the_energy(capsys):
    import json

    status = main(["simulate", "bouncing_ball", "--set", "e=1", "--t-end", "3", "--json"])
    document = json.loads(capsys.readouterr().out)
    assert status == 0 and len(document["impacts"]) == 3
    for impact in document["impacts"]:
        assert impact["energy_after"] == pytest.approx(impact["energy_before"], rel=1e-13)
    assert "not_conserved" not in document
    assert abs(document["invariants"]["energy"]) < 1e-12

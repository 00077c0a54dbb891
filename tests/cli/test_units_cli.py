"""Values with units on the command line (issue 31): --set, --at and --grid converted to
SI, a bare number in the unit the model declares, a wrong dimension refused."""

from __future__ import annotations

import json
import math

import pytest
import xarray

from lagrangian.cli import ExitStatus, main

SPRING = """
name = "spring"
coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "k*x^2/2"
[parameters]
m = "2 kg"
k = "8 N/m"
[units]
x = "cm"
[initial]
x = 10
"""


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def final_state(capsys, *argv):
    status, out, err = run(capsys, "simulate", *argv, "--t-end", "1", "--json")
    assert status == ExitStatus.SUCCESS, err
    return json.loads(out)["final_state"]


@pytest.fixture
def spring(tmp_path):
    path = tmp_path / "spring.toml"
    path.write_text(SPRING)
    return str(path)


def test_set_with_a_unit_is_the_same_run_as_the_number_in_the_declared_unit(capsys):
    in_cm = final_state(capsys, "simple_pendulum", "--set", "l=50cm")
    in_m = final_state(capsys, "simple_pendulum", "--set", "l=0.5")
    assert in_cm == in_m
    other = final_state(capsys, "simple_pendulum", "--set", "g=32.2ft/s^2")
    in_si = final_state(capsys, "simple_pendulum", "--set", f"g={32.2 * 0.3048!r}")
    assert other == pytest.approx(in_si, rel=1e-12)  # 1 ft = 0.3048 m exactly


def test_a_bare_number_is_in_the_unit_the_model_declares(capsys, spring):
    # x is declared in cm: 5 is 5 cm; x(t) = x0 cos(2 t) with omega = sqrt(8/2) = 2
    assert final_state(capsys, spring, "--set", "x=5") == final_state(
        capsys, spring, "--set", "x=0.05m"
    )
    state = final_state(capsys, spring)  # [initial] x = 10 (cm)
    assert state["x"] == pytest.approx(0.1 * math.cos(2.0), rel=1e-6)
    assert final_state(capsys, spring, "--set", "m=2000g") == state


@pytest.mark.parametrize(
    "argv, message",
    [
        (("--set", "m=3m"), "--set m=3m: m is a mass (kg) but 3m is a length (m)"),
        (("--set", "x_dot=3kg"), "--set x_dot=3kg: x_dot is a velocity (m/s) but 3kg is a mass"),
        (("--set", "m=20degC"), "--set m=20degC: '20degC' has a unit with an offset"),
        (("--set", "m=3parsecz"), "unknown unit 'parsecz' (did you mean 'parsec'?)"),
        (("--set", "m=abc"), "expected NAME=NUMBER, got 'm=abc'"),
        (("--set", "q=3m"), "--set q: 'q' is not a parameter, coordinate or velocity of the"),
    ],
)
def test_a_value_of_the_wrong_dimension_is_one_line(capsys, spring, argv, message):
    status, out, err = run(capsys, "simulate", spring, *argv, "--t-end", "1")
    assert status == ExitStatus.BAD_INPUT
    assert message in err
    assert err.count("\n") == 1 and out == ""


def test_an_angles_rate_given_in_the_wrong_unit_is_said_in_rad_per_s(capsys, tmp_path):
    path = tmp_path / "pendulum.toml"
    path.write_text(
        'name = "pendulum"\ncoordinates = ["theta"]\nkinetic = "m*l^2*theta_dot^2/2"\n'
        'potential = "-m*g*l*cos(theta)"\n[parameters]\nm = "2 kg"\nl = "50 cm"\n'
        'g = "9.81 m/s^2"\n'
    )
    status, out, err = run(capsys, "simulate", str(path), "--set", "theta_dot=2m/s")
    assert status == ExitStatus.BAD_INPUT and out == ""
    assert err.endswith(
        "--set theta_dot=2m/s: theta_dot is an angular rate (rad/s) but 2m/s is a velocity (m/s)\n"
    )


def test_a_unit_on_a_model_without_units_makes_it_dimensioned(capsys):
    status, _, err = run(capsys, "simulate", "simple_pendulum", "--set", "l=3kg", "--t-end", "1")
    assert status == ExitStatus.BAD_INPUT
    assert err.strip().endswith(
        "particles[0].position[0]: the term l*sin(theta) is a mass (kg), expected a length (m)"
    )
    assert "--set l=3kg gives the model units" in err


def test_at_takes_degrees_exactly(capsys):
    degrees = run(capsys, "analyze", "cart_pole", "--state-space", "--at", "theta=180deg",
                  "--json")  # fmt: skip
    radians = run(capsys, "analyze", "cart_pole", "--state-space", "--at", "theta=pi", "--json")
    assert degrees[0] == ExitStatus.SUCCESS, degrees[2]
    assert json.loads(degrees[1])["state_space"] == json.loads(radians[1])["state_space"]


def test_grid_takes_units(capsys, tmp_path):
    outputs, units = [], []
    for grid in ("l=20cm:1m:3", "l=0.2:1:3"):
        out = tmp_path / f"{len(outputs)}.nc"
        status, _, err = run(capsys, "ensemble", "simple_pendulum", "--grid", grid, "--t-end",
                             "0.5", "--out", str(out))  # fmt: skip
        assert status == ExitStatus.SUCCESS, err
        with xarray.open_dataset(out) as data:
            outputs.append(data["final_theta"].values.copy())
            units.append({n: data[n].attrs.get("units") for n in ("l", "final_theta_dot")})
    assert (outputs[0] == outputs[1]).all()
    # the unit made the model dimensioned: its ensemble's netCDF says the units (CF)
    assert units == [{"l": "m", "final_theta_dot": "rad/s"}, {"l": None, "final_theta_dot": None}]
    status, _, err = run(capsys, "ensemble", "simple_pendulum", "--grid", "l=1kg:2kg:2")
    assert status == ExitStatus.BAD_INPUT
    assert "the term l*sin(theta) is a mass (kg), expected a length (m)" in err

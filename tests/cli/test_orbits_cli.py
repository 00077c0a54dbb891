"""`lagrangian orbits`: JSON, text and one-line errors."""

from __future__ import annotations

import json
import math

import pytest

from lagrangian.cli import ExitStatus, main

DRIVE = "9.42477796076938"


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.mark.slow
def test_orbits_json_has_each_orbit_once_with_its_multipliers(capsys):
    status, out, _ = run(
        capsys, "orbits", "driven_damped_pendulum", "--strobe", DRIVE, "--period", "2",
        "--set", "A=1.07", "--starts", "3", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert summary["strobe"] == float(DRIVE) and summary["phase"] == 0.0
    assert summary["period"] == 2 and summary["starts"] == 3
    (orbit,) = summary["orbits"]
    assert orbit["period"] == 2 and orbit["stable"] is True and orbit["kind"] == "node"
    assert [sorted(point) for point in orbit["points"]] == [["theta", "theta_dot"]] * 2
    first, second = orbit["multipliers"]
    assert isinstance(first, float) and 0 < second < first < 1
    assert first * second == pytest.approx(math.exp(-0.5 * 2 * float(DRIVE)), rel=1e-9)


def test_orbits_text_names_each_orbit(capsys):
    status, out, _ = run(
        capsys, "orbits", "harmonic_oscillator", "--strobe", "1", "--starts", "1",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    lines = out.splitlines()
    assert lines[0] == (
        "Harmonic oscillator: 1 periodic orbit of period dividing 1 of the strobe every 1, "
        "from 1 starts"
    )
    # x'' = -x: the rest point, turned by one radian a period (cos 1 +- i sin 1)
    assert lines[1].startswith(
        "  period 1, stable elliptic, multipliers 0.540302+0.841471i, 0.540302-0.841471i; "
        "(x, x_dot) at ("
    )


def test_orbits_through_a_section_json(capsys):
    status, out, _ = run(
        capsys, "orbits", "henon_heiles", "--section", "x = 0", "--energy", "0.125",
        "--starts", "3", "--t-end", "40", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert summary["section"] == "x = 0" and summary["energy"] == 0.125
    assert summary["orbits"] and all(orbit["time"] > 0 for orbit in summary["orbits"])
    assert all(len(orbit["multipliers"]) == 4 for orbit in summary["orbits"])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--strobe", "5"], "the equations are not periodic in t with the strobe period 5"),
        (["--strobe", DRIVE, "--period", "0"], "the period must be a whole number from 1 to 64"),
        (["--strobe", DRIVE, "--grid", "b=0:1:2"], "'b' is not a coordinate or velocity"),
        (["--strobe", DRIVE, "--grid", "theta=0:1"], "expected NAME=LO:HI:N"),
        (["--strobe", DRIVE, "--phase", "nan"], "the phase must be a finite time, not nan"),
        (["--strobe", "0"], "strobe must be a finite number > 0"),
        (["--strobe", DRIVE, "--starts", "0"], "give from 1 to 100,000 starts, not 0"),
        ([], "give --section or --strobe (one of them)"),
        (["--strobe", DRIVE, "--energy", "1"], "--energy and --t-end go with --section"),
        (["--section", "theta = 0", "--grid", "theta=0:1:2"], "--grid and --transient go with"),
        (["--section", "theta = 0"], "need the energy of their shell"),
    ],
)
def test_orbits_errors_are_one_line(capsys, argv, message):
    status, out, err = run(capsys, "orbits", "driven_damped_pendulum", *argv)
    assert status == ExitStatus.BAD_INPUT
    assert message in err
    assert len(err.strip().splitlines()) == 1 and out == ""

"""`lagrangian orbits --vary`: the branches as JSON (the orbits JSON extended), text, CSV
and a picture, and one-line errors."""

from __future__ import annotations

import csv
import json
import re

import pytest

from lagrangian.cli import ExitStatus, main

DRIVE = "9.42477796076938"


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.mark.parametrize(
    ("arguments", "error"),
    [
        (["--vary", "B=1:2:5"], "Invalid value for --vary: 'B' is not a parameter of the model "
         "(parameters: m, l, g, b, A, omega)"),
        (["--vary", "theta=1:2:5"], "Invalid value for --vary: 'theta' is not a parameter of "
         "the model (parameters: m, l, g, b, A, omega)"),
        (["--vary", "A=2:1:5"], "Invalid value for --vary: 'A' from 2 to 1: LO must be below HI"),
        (["--vary", "A=1:1:5"], "Invalid value for --vary: 'A' from 1 to 1: LO must be below HI"),
        (["--vary", "A=1:2:1"], "Invalid value for --vary: N must be a whole number >= 2 (the "
         "number of values of A the steps are sized by), got '1'"),
        (["--vary", "A=1:2"], "Invalid value for --vary: expected NAME=LO:HI:N, got 'A=1:2'"),
        (["--vary", "A=1:2:5", "--out", "branches.txt"],
         "Invalid value for --out: the output file must end in .png or .csv"),
        (["--vary", "A=1:2:5", "--axis", "phi"],
         "Invalid value for --axis: 'phi' is not a coordinate or velocity (theta, theta_dot)"),
        (["--out", "branches.png"], "Invalid value for --out: --out goes with --vary"),
    ],
)  # fmt: skip
def test_bad_ranges_and_outputs_exit_2_with_one_line(
    capsys, tmp_path, monkeypatch, arguments, error
):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(
        capsys, "orbits", "driven_damped_pendulum", "--strobe", DRIVE, *arguments
    )
    assert status == ExitStatus.BAD_INPUT
    assert err == f"lagrangian: error: {error}\n" and out == ""
    assert list(tmp_path.iterdir()) == []


def test_vary_goes_with_a_strobe(capsys):
    status, _, err = run(
        capsys, "orbits", "henon_heiles", "--section", "x = 0", "--energy", "0.1", "--vary",
        "A=1:2:3",
    )  # fmt: skip
    assert status == ExitStatus.BAD_INPUT
    assert err == ("lagrangian: error: Invalid value for --section: --vary goes with --strobe\n")


@pytest.mark.slow
def test_the_branches_as_json_csv_and_picture(capsys, tmp_path):
    import lagrangian as lg

    table, picture = tmp_path / "branches.csv", tmp_path / "branches.png"
    status, out, _ = run(
        capsys, "orbits", "driven_damped_pendulum", "--strobe", DRIVE, "--vary",
        "A=1.05:1.07:11", "--max-doublings", "1", "--starts", "3", "--json", "--out",
        str(table), "--out", str(picture), "--no-background",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    # the orbits JSON of the orbits found at the low end, unchanged, is part of it
    (orbit,) = summary["orbits"]
    assert orbit["period"] == 1 and orbit["stable"] is True
    assert summary["parameter"] == "A" and summary["low"] == 1.05 and summary["high"] == 1.07
    assert summary["out"] == [str(table), str(picture)]
    first, second = summary["branches"]
    assert (first["period"], first["parent"], second["period"], second["parent"]) == (1, None, 2, 0)
    assert first["points"][0]["point"] == orbit["points"][0]
    assert first["points"][0]["parameter"] == 1.05 and first["points"][-1]["parameter"] == 1.07
    (doubling,) = first["bifurcations"]
    assert doubling["kind"] == "period doubling" and sorted(doubling["point"]) == [
        "theta",
        "theta_dot",
    ]
    assert min(abs(m + 1) for m in doubling["multipliers"]) < 1e-6
    # the same as the library's, which tests/integrate/test_continuation.py checks
    library = lg.load("driven_damped_pendulum").continuation(
        vary={"A": (1.05, 1.07, 11)}, strobe=float(DRIVE), attractor=3, max_doublings=1
    )
    assert doubling["parameter"] == library.branches[0].bifurcations[0].value
    stable = [p["stable"] for p in first["points"]]
    assert stable[0] and not stable[-1]
    # the CSV: one row per orbit point of every branch point
    with open(table, encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert list(rows[0]) == ["branch", "period", "A", "orbit_point", "theta", "theta_dot", "stable"]
    points = len(first["points"]) + 2 * len(second["points"])
    assert len(rows) == points
    assert float(rows[0]["theta"]) == first["points"][0]["point"]["theta"]
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_the_branches_as_text(capsys):
    status, out, _ = run(
        capsys, "orbits", "driven_damped_pendulum", "--strobe", DRIVE, "--vary",
        "A=1.05:1.07:11", "--max-doublings", "0", "--starts", "3",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    lines = out.splitlines()
    assert lines[0] == (
        "Driven damped pendulum: 1 branch of periodic orbits of the strobe every 9.42478 "
        "followed in A from 1.05 to 1.07"
    )
    assert re.fullmatch(
        r"  branch 1: period 1, found at A = 1.05, \d+ points from 1.05 to 1.07 \(to the end "
        r"of the range\), \d+ stable",
        lines[1],
    )
    assert lines[2].startswith("    period doubling at A = 1.066372862: (theta, theta_dot) = (")
    assert len(lines) == 3

"""`lagrangian basins`: the csv, the JSON and one-line errors."""

from __future__ import annotations

import csv
import json

import pytest

from ensemble.test_basins import DOUBLE_WELL as WELL  # two wells, smooth basins
from lagrangian.cli import ExitStatus, main

DRIVE = "9.42477796076938"
PENDULUM = ("basins", "driven_damped_pendulum")


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.mark.slow
def test_basins_csv_and_json(capsys, tmp_path):
    out = tmp_path / "b.csv"
    status, text, _ = run(
        capsys, *PENDULUM, "--grid", "theta=-3.14159:3.14159:12", "--grid", "theta_dot=-3:3:10",
        "--strobe", DRIVE, "--set", "A=1.073", "--out", str(out), "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(text)
    assert summary["period"] == float(DRIVE) and summary["starts"] == 120
    kinds = [(a["kind"], a["period"], len(a["points"])) for a in summary["attractors"]]
    assert kinds == [("periodic", 2, 2)] * 2
    assert sorted(summary["attractors"][0]["points"][0]) == ["theta", "theta_dot"]
    with open(out, newline="") as stream:
        rows = list(csv.DictReader(stream))
    assert list(rows[0]) == ["theta", "theta_dot", "attractor"] and len(rows) == 120
    labels = [int(row["attractor"]) for row in rows]
    for label, count in summary["counts"].items():
        assert labels.count(int(label)) == count


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (
            ("--grid", "theta=-3:3:10", "--strobe", DRIVE),
            "the grid must cover the whole state (theta, theta_dot): give --grid theta_dot=LO:HI:N",
        ),
        (
            ("--grid", "theta=-3:3:10", "--grid", "theta_dot=-3:3:10"),
            "the equations depend on t: give the drive's period as --strobe",
        ),
        (
            ("--grid", "theta=-3:3:10", "--grid", "theta_dot=-3:3:10", "--strobe", "9"),
            "the equations are not periodic in t with the strobe period 9: give the drive's "
            "period as --strobe",
        ),
        (
            ("--grid", "theta=-3:3:10", "--grid", "theta_dot=-3:3:1", "--strobe", DRIVE),
            "--grid 'theta_dot' needs at least 2 values, not 1",
        ),
        (
            (
                "--grid",
                "theta=-3:3:10",
                "--grid",
                "theta_dot=-3:3:10",
                "--set",
                "theta=1",
                "--strobe",
                DRIVE,
            ),
            "Invalid value for --set: 'theta' is a coordinate or velocity: its values come "
            "from --grid",
        ),
        (
            ("--grid", "theta=-3:3:10", "--grid", "theta_dot=-3:3:10", "--phase", "1"),
            "Invalid value for --phase: --phase goes with --strobe",
        ),
        (
            ("--grid", "theta=-1e308:1e308:10", "--grid", "theta_dot=-3:3:10", "--strobe", DRIVE),
            "Invalid value for --grid: 'theta' from -1e+308 to 1e+308: the range's width overflows",
        ),
        (
            (
                "--grid",
                "theta=-3:3:10",
                "--grid",
                "theta_dot=-3:3:10",
                "--strobe",
                DRIVE,
                "--basin-hits",
                "0",
            ),
            "basin_hits must be a whole number >= 1, not 0",
        ),
        (
            ("--grid", "theta=-3:3:10", "--grid", "theta_dot=-3:3:10", "--backend", "cuda"),
            "Invalid value for '--backend': 'cuda' is not one of 'numba', 'jax'.",
        ),
        (
            ("--grid", "theta=-3:3:10", "--grid", "theta_dot=-3:3:10", "--out", "b.txt"),
            "Invalid value for --out: the output file must end in .csv or .nc or .png",
        ),
    ],
)
def test_bad_input_is_one_line(capsys, arguments, message):
    status, out, err = run(capsys, *PENDULUM, *arguments)
    assert status == ExitStatus.BAD_INPUT and out == ""
    assert err == f"lagrangian: error: {message}\n"


def test_a_huge_grid_is_refused_in_one_line(capsys):
    status, _, err = run(
        capsys, *PENDULUM, "--grid", "theta=-3:3:1000000", "--grid", "theta_dot=-3:3:1000000",
        "--strobe", DRIVE,
    )  # fmt: skip
    assert status == ExitStatus.BAD_INPUT
    assert err.startswith("lagrangian: error: a basin map of 1,000,000,000,000 starts needs ")
    assert err.endswith(": use fewer points per --grid\n") and err.count("\n") == 1


@pytest.mark.slow
def test_backend_jax_writes_the_csv_numba_writes(capsys, tmp_path):
    pytest.importorskip("jax")
    model = tmp_path / "well.toml"
    model.write_text(WELL)
    tables = {}
    for backend in ("numba", "jax"):
        out = tmp_path / f"{backend}.csv"
        status, text, _ = run(
            capsys, "basins", str(model), "--grid", "x=-2:2:10", "--grid", "x_dot=-2:2:10",
            "--interval", "1", "--backend", backend, "--out", str(out), "--json",
        )  # fmt: skip
        assert status == ExitStatus.SUCCESS
        summary = json.loads(text)
        assert summary["backend"] == backend and summary["counts"]["-1"] == 0
        assert [a["kind"] for a in summary["attractors"]] == ["fixed point"] * 2
        tables[backend] = out.read_text()
    assert tables["jax"] == tables["numba"]

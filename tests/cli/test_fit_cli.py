"""``lagrangian fit``: the table, the JSON summary and the picture of a fit to data made
by SciPy from a hand-written equation; each problem one line and exit 2."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from lagrangian.cli import ExitStatus, main

#: m x'' = -k x - c x' (the model's values are the start guesses of what is fitted)
SPRING = """
name = "Damped spring"
coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "k*x^2/2"
dissipation = "c*x_dot^2/2"
[parameters]
m = 1.0
k = 3.0
c = 0.1
[initial]
x = 1.0
"""
K, C = 4.0, 0.3


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.fixture
def files(tmp_path):
    model = tmp_path / "spring.toml"
    model.write_text(SPRING)
    t = np.linspace(0.0, 6.0, 121)
    motion = solve_ivp(
        lambda t, y: [y[1], -K * y[0] - C * y[1]], (0, 6), [1.0, 0.0], t_eval=t, rtol=1e-12,
        atol=1e-12,
    )  # fmt: skip
    noise = np.random.default_rng(5).standard_normal((2, t.size))
    x, x_cm = motion.y[0] + 0.005 * noise[0], 100 * motion.y[0] + 0.5 * noise[1]
    data = tmp_path / "data.csv"
    rows = "".join(f"{a:.17g},{b:.17g},{c:.17g}\n" for a, b, c in zip(t, x, x_cm, strict=True))
    data.write_text("t,x,x_cm\n" + rows)
    return str(model), str(data)


@pytest.mark.slow
def test_json_summary(capsys, files):
    model, data = files
    status, out, err = run(
        capsys, "fit", model, data, "--vary", "k,c", "--observe", "x_cm = 100*x",
        "--noise", "x=0.005,x_cm=0.5", "--backend", "llvm", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS, err
    summary = json.loads(out)
    assert set(summary["parameters"]) == {"k", "c"}
    for name, truth in (("k", K), ("c", C)):
        entry = summary["parameters"][name]
        assert abs(entry["value"] - truth) < 0.01 * truth
        assert abs(entry["value"] - truth) < 2 * entry["stderr"]
    assert summary["correlation"]["k"]["k"] == 1.0
    assert summary["correlation"]["k"]["c"] == summary["correlation"]["c"]["k"]
    assert summary["chi2_per_dof"] is not None and summary["warnings"] == []
    assert summary["columns"] == ["x", "x_cm"] and summary["samples"] == 121
    assert {"rms", "starts", "iterations", "evaluations", "converged"} <= set(summary)


@pytest.mark.slow
def test_text_table_and_picture(capsys, files, tmp_path):
    model, data = files
    picture = tmp_path / "fit.png"
    status, out, err = run(
        capsys, "fit", model, data, "--vary", "k=3.5", "--vary", "c", "--observe",
        "x_cm = 100*x", "--backend", "llvm", "--out", str(picture), "--plot-residuals",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS, err
    lines = out.splitlines()
    assert lines[0] == f"Damped spring fitted to {data} (121 times, columns x, x_cm)"
    assert lines[2].startswith("k ") and lines[3].startswith("c ")
    assert "correlation:" in lines and any(
        line.startswith("rms of the residuals") for line in lines
    )
    assert "chi^2" not in out  # no noise level given
    assert picture.read_bytes().startswith(b"\x89PNG") and lines[-1] == f"wrote {picture}"


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (("--vary", "z"), "--vary: 'z' is neither a parameter nor a coordinate or velocity"),
        (
            ("--vary", "k", "--observe", "x_cm"),
            "--observe: an observed expression is 'NAME = EXPR'",
        ),
        (("--vary", "k", "--observe", "x_cm = 100*y"), "--observe x_cm: unknown symbol 'y'"),
        (("--vary", "k", "--noise", "-1"), "--noise: the noise level must be a positive number"),
        (("--vary", "k", "--starts", "0"), "--starts: starts must be a whole number >= 1"),
        (("--vary", "k", "--noise", "x"), "--noise: the noise level must be a positive number"),
        (
            ("--vary", "k", "--observe", "x_cm = 100*x", "--noise", "x=1,y=2"),
            "--noise: 'y' is not a measured column",
        ),
    ],
)
def test_bad_options_are_one_line(capsys, files, extra, message):
    model, data = files
    status, out, err = run(capsys, "fit", model, data, *extra, "--backend", "llvm")
    assert status == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and message in err, err


def test_a_data_problem_names_the_file_and_row(capsys, files, tmp_path):
    model, _ = files
    data = tmp_path / "bad.csv"
    data.write_text("t,x\n0,1\n0.1,one\n")
    status, out, err = run(capsys, "fit", model, str(data), "--vary", "k")
    assert status == 2 and out == ""
    assert err.strip() == f"lagrangian: error: {data}: row 3, column 'x': 'one' is not a number"


def test_dropped_rows_are_said_on_stderr(capsys, files, tmp_path):
    model, data = files
    with open(data) as handle:
        lines = handle.read().splitlines()
    lines[5] = lines[5].split(",")[0] + ",nan,"
    holed = tmp_path / "holed.csv"
    holed.write_text("\n".join(lines) + "\n")
    status, out, err = run(
        capsys, "fit", model, str(holed), "--vary", "k", "--observe", "x_cm = 100*x",
        "--backend", "llvm", "--json",
    )  # fmt: skip
    assert status == 0
    assert err.strip() == f"{holed}: 1 rows with a missing value (empty or NaN) dropped (rows 6)"
    assert json.loads(out)["samples"] == 120


def test_plot_residuals_needs_a_picture(capsys, files):
    model, data = files
    status, _, err = run(capsys, "fit", model, data, "--vary", "k", "--plot-residuals")
    assert status == 2 and "--plot-residuals: give the picture's file with --out" in err

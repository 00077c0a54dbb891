"""``lagrangian sensitivity``: outputs checked against a closed form, errors one line."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from lagrangian.cli import ExitStatus, main

#: x = x0 cos(w t), w = sqrt(k / m): dx/dk = -x0 t sin(w t) / (2 sqrt(k m)), dx/dx0 = cos(w t)
SPRING = """
name = "Spring"
coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "k*x^2/2"
[parameters]
m = 2.0
k = 5.0
[initial]
x = 0.7
"""
OMEGA = np.sqrt(5.0 / 2.0)


def exact_dx_dk(t):
    return -0.7 * t * np.sin(OMEGA * t) / (2 * np.sqrt(5.0 * 2.0))


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.fixture
def spring(tmp_path):
    path = tmp_path / "spring.toml"
    path.write_text(SPRING)
    return str(path)


@pytest.mark.slow
def test_json_gives_the_sensitivities_at_t_end(capsys, spring):
    status, out, _ = run(capsys, "sensitivity", spring, "--wrt", "k,x", "--t-end", "3", "--json")
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert summary["wrt"] == ["k", "x"] and summary["states"] == ["x", "x_dot"]
    assert summary["t_end"] == 3.0 and summary["points"] == 201 and summary["rtol"] == 1e-10
    assert summary["final"]["x"]["k"] == pytest.approx(exact_dx_dk(3.0), rel=1e-8)
    assert summary["final"]["x"]["x"] == pytest.approx(np.cos(OMEGA * 3.0), rel=1e-8)
    assert summary["final"]["x_dot"]["x"] == pytest.approx(-OMEGA * np.sin(OMEGA * 3.0), rel=1e-8)
    assert summary["parameters"] == {"m": 2.0, "k": 5.0}


@pytest.mark.slow
def test_csv_netcdf_and_picture(capsys, spring, tmp_path):
    table, dataset, picture = tmp_path / "s.csv", tmp_path / "s.nc", tmp_path / "s.png"
    argv = ["sensitivity", spring, "--wrt", "k,x", "--t-end", "3", "--points", "31"]
    status, out, _ = run(capsys, *argv, "--out", str(table), "--plot", str(picture))
    assert status == ExitStatus.SUCCESS
    assert out.startswith("Spring: d state(t) / d w at t = 3\n")
    assert f"wrote {table}" in out and f"wrote {picture}" in out
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    header = table.read_text().splitlines()[0]
    assert header == ("t,x,x_dot,d(x)/d(k),d(x)/d(x(0)),d(x_dot)/d(k),d(x_dot)/d(x(0))")
    rows = np.loadtxt(table, delimiter=",", skiprows=1)
    t = rows[:, 0]
    np.testing.assert_allclose(rows[:, 1], 0.7 * np.cos(OMEGA * t), atol=1e-9)
    np.testing.assert_allclose(rows[:, 3], exact_dx_dk(t), atol=1e-9)
    np.testing.assert_allclose(rows[:, 4], np.cos(OMEGA * t), atol=1e-9)
    assert run(capsys, *argv, "--out", str(dataset))[0] == ExitStatus.SUCCESS
    with xr.open_dataset(dataset) as back:
        assert back["sensitivity"].dims == ("time", "state", "wrt")
        values = back["sensitivity"].sel(state="x", wrt="k").values
        np.testing.assert_allclose(values, exact_dx_dk(back["time"].values), atol=1e-9)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["--wrt", "k,spring"],
            "--wrt: 'spring' is neither a parameter nor a coordinate or velocity "
            "(parameters: m, k; initial values: x, x_dot)",
        ),
        (["--wrt", "k,"], "expected names separated by commas, got 'k,'"),
        (["--wrt", "k,k"], "--wrt: 'k' is given twice"),
        (["--wrt", "k", "--out", "s.txt"], "the output file must end in .nc or .csv"),
        (["--wrt", "k", "--plot", "s.pdf"], "the picture must be a .png file"),
        (["--wrt", "k", "--points", "1"], "--points: the number of output times must be"),
        (["--wrt", "k", "--set", "q=1"], "'q' is neither a parameter nor a coordinate"),
    ],
)
def test_errors_are_one_line_and_write_nothing(capsys, spring, tmp_path, argv, message):
    table = tmp_path / "never.csv"
    out = [] if "--out" in argv else ["--out", str(table)]
    status, printed, err = run(capsys, "sensitivity", spring, *argv, *out)
    assert status == ExitStatus.BAD_INPUT
    assert message in err
    assert len(err.strip().splitlines()) == 1 and printed == ""
    assert not table.exists()


def test_constrained_models_are_refused(capsys):
    status, _, err = run(capsys, "sensitivity", "cartesian_pendulum", "--wrt", "g")
    assert status == ExitStatus.BAD_INPUT
    assert "sensitivities of constrained systems are not supported" in err

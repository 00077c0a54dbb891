"""`lagrangian lyapunov`: text, JSON, the convergence plot and one-line errors."""

from __future__ import annotations

import json

import pytest

from lagrangian.cli import ExitStatus, main


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    return status, captured.out, captured.err


@pytest.mark.slow
def test_lyapunov_json_has_the_spectrum_and_settings(capsys):
    status, out, _ = run(
        capsys, "lyapunov", "driven_damped_pendulum", "--t-end", "20", "--transient", "5",
        "--set", "b=0.4", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert len(summary["exponents"]) == 2
    assert summary["sum"] == pytest.approx(-0.4, abs=1e-6)  # the divergence -b / (m l^2)
    assert summary["transient"] == 5.0 and summary["interval"] == 1.0
    assert summary["parameters"]["b"] == 0.4
    assert summary["reorthonormalisations"] == 20


@pytest.mark.slow
def test_lyapunov_text_and_plot(capsys, tmp_path):
    picture = tmp_path / "convergence.png"
    status, out, _ = run(
        capsys, "lyapunov", "henon_heiles", "--t-end", "4", "--largest", "--plot", str(picture)
    )
    assert status == ExitStatus.SUCCESS
    assert out.startswith("Henon-Heiles system: largest Lyapunov exponent over t = 4")
    assert "lambda1 =" in out and "lambda2" not in out
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["cartesian_pendulum", "--t-end", "1"],
            "Lyapunov exponents of constrained systems are not supported",
        ),
        (["henon_heiles", "--count", "5"], "must be from 1 to 4 (twice the coordinates), not 5"),
        (["henon_heiles", "--plot", "x.pdf"], "the picture must be a .png file"),
        (["henon_heiles", "--largest", "--count", "2"], "--largest is --count 1"),
        (["henon_heiles", "--set", "q=1"], "'q' is neither a parameter nor a coordinate"),
    ],
)
def test_lyapunov_errors_are_one_line(capsys, argv, message):
    status, out, err = run(capsys, "lyapunov", *argv)
    assert status == ExitStatus.BAD_INPUT
    assert message in err
    assert len(err.strip().splitlines()) == 1 and out == ""


@pytest.mark.slow
def test_poincare_writes_points_and_picture(capsys, tmp_path):
    table, picture = tmp_path / "points.csv", tmp_path / "section.png"
    status, out, _ = run(
        capsys, "poincare", "henon_heiles", "--section", "x = 0", "--axes", "y,p_y",
        "--energy", "0.125", "--orbits", "2", "--t-end", "20", "--out", str(table),
        "--plot", str(picture),
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    assert out.startswith("Henon-Heiles system: section x = 0, 2 orbits to t = 20,")
    assert table.read_text().splitlines()[0] == "orbit,t,x,y,x_dot,y_dot,p_y,energy"
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_poincare_json_with_a_strobe(capsys):
    status, out, _ = run(
        capsys, "poincare", "driven_damped_pendulum", "--strobe", "9.42477796076938",
        "--transient", "10", "--t-end", "60", "--axes", "theta,theta_dot", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert summary["orbits"] == 1 and summary["points"] == 5
    assert summary["strobe"] == pytest.approx(9.42477796076938)
    assert summary["phase"] == 0.0  # at whole periods from t = 0, not from the transient
    assert summary["method"] == "dop853"


def test_poincare_at_a_phase(capsys, tmp_path):
    # t = 4.712 + 9.425 k after the transient 10 up to 40: 14.1, 23.6, 33.0
    table = tmp_path / "points.csv"
    status, out, _ = run(
        capsys, "poincare", "driven_damped_pendulum", "--strobe", "9.42477796076938",
        "--phase", "4.71238898038469", "--transient", "10", "--t-end", "40",
        "--axes", "theta,theta_dot", "--out", str(table),
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    assert out.startswith("Driven damped pendulum: strobe 9.42478 at phase 4.71239, 1 orbits")
    times = [float(row.split(",")[1]) for row in table.read_text().splitlines()[1:]]
    assert times == pytest.approx([4.71238898038469 + 9.42477796076938 * k for k in (1, 2, 3)])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--axes", "y"], "give two names, e.g. y,p_y"),
        (["--axes", "y,p_y"], "give --section or --strobe (one of them)"),
        (["--axes", "y,p_y", "--section", "x = 0", "--strobe", "1"], "one of them"),
        (["--axes", "y,q_y", "--section", "x = 0"], "unknown axis 'q_y'"),
        (["--axes", "y,p_y", "--section", "x = 0", "--out", "p.txt"], "must end in .csv or .nc"),
        (["--axes", "y,p_y", "--section", "x = 0", "--spread", "y=1"], "expected NAME=LO:HI"),
        (["--axes", "y,p_y", "--section", "x + y = 0", "--energy", "0.1"], "'coordinate = number'"),
        (
            ["--axes", "y,p_y", "--section", "x = 0", "--energy", "0.1", "--orbits", "10000000"],
            "give from 1 to 100,000 orbits, not 10000000",
        ),
        (["--axes", "y,p_y", "--strobe", "1e-300"], "strobe times per orbit needs about"),
        (["--axes", "y,p_y", "--section", "x = 0", "--phase", "1"], "--phase goes with --strobe"),
        (["--axes", "y,p_y", "--strobe", "1", "--phase", "nan"], "the phase must be a finite time"),
    ],
)
def test_poincare_errors_are_one_line(capsys, argv, message):
    status, out, err = run(capsys, "poincare", "henon_heiles", "--t-end", "1", *argv)
    assert status == ExitStatus.BAD_INPUT
    assert message in err
    assert len(err.strip().splitlines()) == 1 and out == ""


def test_bifurcation_writes_points_and_picture(capsys, tmp_path):
    table, picture = tmp_path / "points.csv", tmp_path / "diagram.png"
    status, out, _ = run(
        capsys, "bifurcation", "driven_damped_pendulum", "--vary", "A=1.0:1.1:3",
        "--strobe", "9.42477796076938", "--axis", "theta_dot", "--samples", "2",
        "--steps-per-period", "50", "--out", str(table), "--plot", str(picture),
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    assert out.startswith("Driven damped pendulum: theta_dot every 9.42478 for 3 values of A")
    rows = table.read_text().splitlines()
    assert rows[0] == "A,t,theta_dot" and len(rows) == 1 + 3 * 2
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bifurcation_at_a_phase(capsys):
    status, out, _ = run(
        capsys, "bifurcation", "driven_damped_pendulum", "--vary", "A=1.0:1.1:2",
        "--strobe", "9.42477796076938", "--phase", "1.5", "--transient", "20", "--axis",
        "theta_dot", "--samples", "2", "--steps-per-period", "50", "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert summary["period"] == 9.42477796076938 and summary["phase"] == 1.5
    assert summary["transient"] == 20.0 and summary["samples"] == 2


def test_bifurcation_from_a_section(capsys, tmp_path):
    table = tmp_path / "points.csv"
    status, out, _ = run(
        capsys, "bifurcation", "driven_damped_pendulum", "--vary", "A=1.0:1.1:3",
        "--section", "theta_dot = 0", "--direction", "-", "--axis", "theta", "--samples", "2",
        "--transient", "10", "--t-end", "20", "--dt", "0.05", "--out", str(table), "--json",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    summary = json.loads(out)
    assert summary["section"] == "theta_dot = 0" and summary["direction"] == "-"
    assert summary["t_end"] == 20.0 and summary["dt"] == 0.05 and summary["values"] == 3
    rows = [row.split(",") for row in table.read_text().splitlines()]
    assert rows[0] == ["A", "t", "theta"] and len(rows) <= 1 + 3 * 2  # 2 at most per value
    assert len({a for a, _, _ in rows[1:]}) == 3
    assert all(10.0 < float(t) <= 30.0 for _, t, _ in rows[1:])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--vary", "A=1:2:3", "--section", "theta = 0"], "give --section or --strobe"),
        (["--vary", "A=1:2:3", "--t-end", "5"], "--t-end and --dt go with --section"),
        (["--vary", "A=1:2"], "expected NAME=LO:HI:N"),
        (["--vary", "A=1:2:3", "--out", "x.nc"], "must end in .csv"),
        (["--vary", "omega=1:2:3", "--axis", "x"], "'x' is not a coordinate or velocity"),
        (["--vary", "A=1:2:3", "--phase", "inf"], "the phase must be a finite time, not inf"),
    ],
)
def test_bifurcation_errors_are_one_line(capsys, argv, message):
    status, out, err = run(
        capsys, "bifurcation", "driven_damped_pendulum", "--strobe", "1", "--axis", "theta",
        *argv,
    )  # fmt: skip
    assert status == ExitStatus.BAD_INPUT
    assert message in err
    assert len(err.strip().splitlines()) == 1 and out == ""


@pytest.mark.slow
def test_ensemble_lyapunov_map(capsys, tmp_path):
    picture = tmp_path / "map.png"
    status, out, _ = run(
        capsys, "ensemble", "henon_heiles", "--grid", "y=-0.3:0.3:3", "--grid", "x_dot=0.3:0.4:2",
        "--t-end", "2", "--observable", "lyapunov", "--out", str(picture),
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS
    assert "lyapunov: median" in out
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    ("argv", "warning"),
    [
        (
            ["poincare", "harmonic_oscillator", "--axes", "x,x_dot", "--section", "x = 5"],
            "the orbit does not cross the section x = 5 (direction +) up to t = 20: no points",
        ),
        (
            ["bifurcation", "harmonic_oscillator", "--vary", "k=1:2:2", "--axis", "x",
             "--section", "x = 5", "--direction", "both", "--t-end", "5"],
            "the motion crosses the section x = 5 (direction both) for none of the 2 values of "
            "k between t = 0 and 5: no points",
        ),
    ],
    ids=["poincare", "bifurcation"],
)  # fmt: skip
@pytest.mark.slow
def test_a_section_never_crossed_is_said_and_not_drawn(capsys, tmp_path, argv, warning):
    # x = cos(sqrt(k) t) never reaches 5: the command said "0 points", wrote an empty CSV
    # and an empty picture, and warned of nothing
    table, picture = tmp_path / "points.csv", tmp_path / "points.png"
    status, out, err = run(capsys, *argv, "--out", str(table), "--plot", str(picture))
    assert status == ExitStatus.SUCCESS
    assert err.splitlines() == [
        f"lagrangian: warning: {warning}",
        f"lagrangian: warning: no points to draw: {picture} was not written",
    ]
    assert not picture.exists() and f"wrote {picture}" not in out
    assert len(table.read_text().splitlines()) == 1  # the header: no rows, said above


@pytest.mark.slow
def test_orbits_that_never_cross_are_counted(capsys):
    # x = x0 cos t from x0 = 0, 0.2 and 0.4 stays below 0.5; from 0.6 to 1 it crosses
    status, out, err = run(
        capsys, "poincare", "harmonic_oscillator", "--axes", "x,x_dot", "--section", "x = 0.5",
        "--spread", "x=0:1", "--orbits", "6",
    )  # fmt: skip
    assert status == ExitStatus.SUCCESS and "(0 to 3 per orbit)" in out
    assert err == (
        "lagrangian: warning: 3 of the 6 orbits do not cross the section x = 0.5 "
        "(direction +) up to t = 20: they have no points\n"
    )

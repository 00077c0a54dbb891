"""The chaos outputs of a dimensioned model say their units (issue 31): lyapunov's
exponents in 1/s, the CSV headers, netCDF attributes and plot axes of poincare and
bifurcation; a model without units writes what it did."""

from __future__ import annotations

import json

import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main

#: Baker and Gollub's driven damped pendulum (the example driven_damped_pendulum), in SI.
DRIVEN = """
name = "driven"
coordinates = ["theta"]
kinetic = "m*l^2*theta_dot^2/2"
potential = "-m*g*l*cos(theta)"
[parameters]
m = "1 kg"
l = "1 m"
g = "1 m/s^2"
b = "0.5 N*m*s"
A = "1.5 N*m"
omega = "0.6666666666666666 rad/s"
[forces]
theta = "A*cos(omega*t) - b*theta_dot"
[initial]
theta = 0.2
"""

PERIOD = "9.42477796076938"  # 2 pi / omega


@pytest.fixture
def driven(tmp_path):
    path = tmp_path / "driven.toml"
    path.write_text(DRIVEN)
    return str(path)


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    assert status == ExitStatus.SUCCESS, captured.err
    return captured.out


@pytest.mark.slow
def test_lyapunov_exponents_are_in_inverse_seconds(capsys, driven):
    argv = ("lyapunov", driven, "--t-end", "20", "--transient", "5")
    lines = run(capsys, *argv).splitlines()
    assert lines[0] == "driven: 2 Lyapunov exponents over t = 20 s (after a transient of 5 s), 1/s:"
    assert lines[3] == "  sum = -0.5"  # the divergence -b / (m l^2) in 1/s
    summary = json.loads(run(capsys, *argv, "--json"))
    assert summary["units"] == {"exponents": "1/s", "t": "s"}
    assert sum(summary["exponents"]) == pytest.approx(-0.5, abs=1e-6)


def test_lyapunov_plot_axes_say_seconds(driven):
    from lagrangian.output.lyapunov import plot_lyapunov

    system = lg.load(driven)
    spectrum = system.lyapunov(t_end=3.0)
    for figure in (plot_lyapunov(spectrum, system), spectrum.plot()):  # the spectrum's model
        axis = figure.axes[0]
        assert (axis.get_xlabel(), axis.get_ylabel()) == (
            "averaging time $t$ [s]", "estimate [1/s]"
        )  # fmt: skip
    plain = lg.load("driven_damped_pendulum").lyapunov(t_end=3.0).plot().axes[0]
    assert (plain.get_xlabel(), plain.get_ylabel()) == (
        "averaging time $t$", "estimate (1 / time unit)"
    )  # fmt: skip


def test_a_unitless_lyapunov_is_as_it_was(capsys):
    argv = ("lyapunov", "driven_damped_pendulum", "--t-end", "20", "--transient", "5")
    out = run(capsys, *argv)
    assert out.splitlines()[0] == (
        "Driven damped pendulum: 2 Lyapunov exponents over t = 20 (after a transient of 5), "
        "1 / time unit:"
    )
    assert "units" not in json.loads(run(capsys, *argv, "--json"))


@pytest.mark.slow
def test_poincare_files_and_axes_carry_units(capsys, driven, tmp_path):
    table, data = tmp_path / "points.csv", tmp_path / "points.nc"
    section = ("poincare", driven, "--strobe", PERIOD, "--transient", "10", "--t-end", "60")
    run(capsys, *section, "--axes", "theta,theta_dot", "--out", str(table))
    header = table.read_text().splitlines()[0]
    assert header == "orbit,t [s],theta [rad],theta_dot [rad/s],energy [J]"
    run(capsys, *section, "--axes", "theta,p_theta", "--out", str(data))
    import xarray

    with xarray.open_dataset(data) as points:
        units = {name: points[name].attrs.get("units") for name in points.variables}
    # p_theta = m l^2 theta_dot: kg m^2 / s
    assert units == {
        "t": "s", "theta": "rad", "theta_dot": "rad/s", "p_theta": "kg*m^2/s",
        "energy": "J", "orbit": None,
    }  # fmt: skip
    from lagrangian.output.sections import plot_section

    points = lg.load(driven).poincare(axes=("theta", "theta_dot"), strobe=float(PERIOD), t_end=30.0)
    axis = plot_section(points).axes[0]
    assert (axis.get_xlabel(), axis.get_ylabel()) == (r"$\theta$ [rad]", r"$\dot{\theta}$ [rad/s]")


def test_a_unitless_poincare_file_is_as_it_was(capsys, tmp_path):
    table, data = tmp_path / "points.csv", tmp_path / "points.nc"
    section = ("poincare", "driven_damped_pendulum", "--strobe", PERIOD, "--t-end", "30")
    run(capsys, *section, "--axes", "theta,theta_dot", "--out", str(table))
    assert table.read_text().splitlines()[0] == "orbit,t,theta,theta_dot,energy"
    run(capsys, *section, "--axes", "theta,theta_dot", "--out", str(data))
    import xarray

    with xarray.open_dataset(data) as points:
        assert not any("units" in points[name].attrs for name in points.variables)


@pytest.mark.filterwarnings("ignore::lagrangian.integrate.step_size.CoarseStepWarning")
def test_bifurcation_csv_and_axes_carry_units(capsys, driven, tmp_path):
    table = tmp_path / "points.csv"
    diagram = ("bifurcation", "--vary", "A=1.0:1.1:3", "--strobe", PERIOD, "--axis",
               "theta_dot", "--samples", "2", "--steps-per-period", "50")  # fmt: skip
    run(capsys, diagram[0], driven, *diagram[1:], "--out", str(table))
    rows = table.read_text().splitlines()
    assert rows[0] == "A [J],t [s],theta_dot [rad/s]" and len(rows) == 1 + 3 * 2  # A: N m
    run(capsys, diagram[0], "driven_damped_pendulum", *diagram[1:], "--out", str(table))
    assert table.read_text().splitlines()[0] == "A,t,theta_dot"
    from lagrangian.output.bifurcation import plot_bifurcation

    system = lg.load(driven)
    found = system.bifurcation(
        vary={"A": [1.0, 1.1]}, variable="theta", period=float(PERIOD), samples=2,
        steps_per_period=50,
    )  # fmt: skip
    axis = plot_bifurcation(found).axes[0]
    assert (axis.get_xlabel(), axis.get_ylabel()) == ("$A$ [J]", r"$\theta$ [rad]")


def _drawn_figure(capsys, monkeypatch, tmp_path, *argv):
    """The figure an ``ensemble ... --out map.png`` saves (its labels are not in the PNG)."""
    import lagrangian.output.plots as plots

    saved = []
    monkeypatch.setattr(plots, "save_figure", lambda figure, path, **_: saved.append(figure))
    run(capsys, "ensemble", *argv, "--out", str(tmp_path / "map.png"))
    (figure,) = saved
    return figure


@pytest.mark.slow
@pytest.mark.parametrize(
    ("observable", "colour_bar"),
    [("lyapunov", "lyapunov [1/s]"), ("final_state", "final theta [rad]")],
)
def test_ensemble_maps_say_their_units(
    capsys, monkeypatch, tmp_path, driven, observable, colour_bar
):
    grid = ("--grid", "theta=-1:1:3", "--grid", "A=1:1.5:2", "--t-end", "0.5")
    figure = _drawn_figure(capsys, monkeypatch, tmp_path, driven, *grid, "--observable", observable)
    axis, bar = figure.axes
    assert (axis.get_xlabel(), axis.get_ylabel()) == ("$A$ [J]", r"$\theta$ [rad]")
    assert bar.get_ylabel() == colour_bar
    line = _drawn_figure(
        capsys, monkeypatch, tmp_path, driven, "--grid", "A=1:1.5:3", "--t-end", "0.5",
        "--observable", observable,
    ).axes[0]  # fmt: skip
    assert line.get_ylabel() == colour_bar  # against the members: no unit


@pytest.mark.slow
def test_a_unitless_ensemble_map_is_as_it_was(capsys, monkeypatch, tmp_path):
    figure = _drawn_figure(
        capsys, monkeypatch, tmp_path, "driven_damped_pendulum", "--grid", "theta=-1:1:3",
        "--grid", "A=1:1.5:2", "--t-end", "0.5", "--observable", "lyapunov",
    )  # fmt: skip
    axis, bar = figure.axes
    assert (axis.get_xlabel(), axis.get_ylabel(), bar.get_ylabel()) == (
        "$A$", r"$\theta$", "lyapunov"
    )  # fmt: skip

"""The outputs of a dimensioned model say their units (issue 31): text, LaTeX and JSON of
derive and analyze, simulate's summary, CSV headers and netCDF attributes (CF), plot
axes; a model without units prints exactly what it did."""

from __future__ import annotations

import json
import math

import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.output.plots import plot_timeseries
from lagrangian.trajectory import Trajectory

PENDULUM = """
name = "pendulum"
coordinates = ["theta"]
[parameters]
m = "2 kg"
l = "50 cm"
g = "9.81 m/s^2"
[[particles]]
name = "bob"
mass = "m"
position = ["l*sin(theta)", "-l*cos(theta)"]
[gravity]
g = "g"
[initial]
theta = 0.5
"""


@pytest.fixture
def pendulum(tmp_path):
    path = tmp_path / "pendulum.toml"
    path.write_text(PENDULUM)
    return str(path)


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    assert status == ExitStatus.SUCCESS, captured.err
    return captured.out


def test_derive_json_has_a_units_section_with_what_was_inferred(capsys, pendulum):
    document = json.loads(run(capsys, "derive", pendulum, "--json"))
    assert document["units"] == {
        "names": {"theta": "rad", "theta_dot": "rad/s", "m": "kg", "l": "m", "g": "m/s^2"},
        "inferred": ["theta"],
        "time": "s",
        "energy": "J",
    }
    assert "Units (SI): theta rad (inferred), m kg, l m, g m/s^2" in run(capsys, "derive", pendulum)


def test_analyze_names_the_units_of_its_quantities(capsys, pendulum):
    document = json.loads(run(capsys, "analyze", pendulum, "--json"))
    assert document["conserved"][0]["units"] == "J"
    assert document["hamiltonian_units"] == "J"
    bottom = document["equilibria"][0]
    assert bottom["units"] == {"omega_squared": "1/s^2", "omega": "rad/s", "periods": "s"}
    omega = math.sqrt(9.81 / 0.5)  # small oscillations of a pendulum of 50 cm
    assert bottom["at_parameter_values"]["omega"][0] == pytest.approx(omega)
    text = run(capsys, "analyze", pendulum)
    assert f"ω = {omega:.6g} rad/s;  periods {2 * math.pi / omega:.6g} s" in text
    assert "at g = 9.81 m/s^2, l = 0.5 m: ω² = 19.62 1/s^2" in text
    assert "(h = T + V, the total energy) [J]" in text
    latex = run(capsys, "analyze", pendulum, "--latex")
    assert r"\quad [\mathrm{J}]" in latex and r"\quad [\mathrm{1/s^2}]" in latex


def test_a_model_without_units_prints_no_units(capsys):
    text = run(capsys, "analyze", "simple_pendulum")
    assert "Units" not in text and "[J]" not in text and "rad/s" not in text
    assert "units" not in json.loads(run(capsys, "derive", "simple_pendulum", "--json"))


def test_files_carry_units_and_read_back(capsys, pendulum, tmp_path):
    csv_path, nc_path = tmp_path / "run.csv", tmp_path / "run.nc"
    summary = json.loads(run(capsys, "simulate", pendulum, "--t-end", "1", "--json",
                             "--out", str(csv_path)))  # fmt: skip
    assert summary["units"] == {"t": "s", "theta": "rad", "theta_dot": "rad/s", "energy": "J"}
    header = csv_path.read_text().splitlines()[0]
    assert header == "t [s],theta [rad],theta_dot [rad/s],energy [J]"
    back = Trajectory.load(csv_path)
    assert back.coordinates == ("theta",)
    assert back.dataset["theta_dot"].attrs["units"] == "rad/s"
    run(capsys, "simulate", pendulum, "--t-end", "1", "--out", str(nc_path))
    import xarray

    with xarray.open_dataset(nc_path) as data:
        assert {name: data[name].attrs.get("units") for name in data.variables} == {
            "t": "s", "theta": "rad", "theta_dot": "rad/s", "energy": "J"
        }  # fmt: skip
    plain = tmp_path / "plain.csv"
    run(capsys, "simulate", "simple_pendulum", "--t-end", "1", "--out", str(plain))
    assert plain.read_text().splitlines()[0] == "t,theta,theta_dot,energy"


def test_plot_axes_say_the_units(pendulum):
    system = lg.load(pendulum)
    figure = plot_timeseries(system.simulate(t_end=1.0), system)
    labels = [(ax.get_xlabel(), ax.get_ylabel()) for ax in figure.axes]
    assert labels == [(r"$t$ [s]", r"$\theta$ [rad]"), (r"$t$ [s]", r"$\dot{\theta}$ [rad/s]")]


def test_exported_code_says_its_units_in_its_header(pendulum):
    from lagrangian.export import export_code

    text = export_code(lg.load(pendulum), "numpy")
    line = (
        "# Units (SI base units, t in s): theta [rad], theta_dot [rad/s], m [kg], l [m], g [m/s^2]."
    )
    assert line in text.splitlines()[:8]
    assert "params[1] = l  (0.5)" in text  # 50 cm, in the unit the header says
    assert "Units" not in export_code(lg.load("simple_pendulum"), "c")


def test_latex_of_derive_and_analyze_says_the_units(capsys, pendulum):
    units = (
        r"&\text{Units (SI): } \theta\ [\mathrm{rad}]\ \text{(inferred)},\ m\ [\mathrm{kg}],"
        r"\ l\ [\mathrm{m}],\ g\ [\mathrm{m/s^2}]"
    )
    for argv in (("derive",), ("derive", "--steps"), ("analyze",)):
        latex = run(capsys, argv[0], pendulum, "--latex", *argv[1:]).splitlines()
        assert latex[:2] == [r"\begin{align*}", units + r" \\"], argv
    omega = math.sqrt(9.81 / 0.5)  # small oscillations of a pendulum of 50 cm
    at_bottom = (
        r"&\quad\text{at } g = 9.81\ \mathrm{m/s^2},\ l = 0.5\ \mathrm{m}: \ \omega^2 = 19.62\ "
        rf"\mathrm{{1/s^2}};\ \omega = {omega:.6g}\ \mathrm{{rad/s}};\ \text{{periods }} "
        rf"{2 * math.pi / omega:.6g}\ \mathrm{{s}} \\"
    )
    assert at_bottom in run(capsys, "analyze", pendulum, "--latex").splitlines()


def test_a_unit_in_latex_is_upright_with_dots_and_grouped_exponents():
    from lagrangian.output.units import latex_unit

    assert latex_unit("kg*m^2") == r"\mathrm{kg\cdot m^2}"
    assert latex_unit("kg/(m*s^2)") == r"\mathrm{kg/(m\cdot s^2)}"
    assert latex_unit("m^(1/2)/s^12") == r"\mathrm{m^{1/2}/s^{12}}"


def test_latex_of_a_model_without_units_is_as_it_was(capsys):
    assert run(capsys, "analyze", "simple_pendulum", "--latex") == (
        "\\begin{align*}\n"
        r"h &= \frac{l^{2} m \dot{\theta}^{2}}{2} - g l m \cos{\left(\theta \right)} + g l m \\"
        "\n"
        r"H &= - g l m \cos{\left(\theta \right)} + g l m + \frac{p_{\theta}^{2}}{2 l^{2} m} \\"
        "\n"
        r"&\theta = 0: \ \omega^2 \in \{\frac{g}{l}\}\ \text{(stable)} \\"
        "\n"
        r"&\theta = \pi: \ \omega^2 \in \{- \frac{g}{l}\}\ \text{(unstable)}"
        "\n\\end{align*}\n"
    )
    assert run(capsys, "derive", "simple_pendulum", "--latex") == (
        "\\begin{align*}\n"
        r"L &= \frac{l^{2} m \dot{\theta}^{2}}{2} + g l m \cos{\left(\theta \right)} - g l m \\"
        "\n"
        r"0 &= l \ddot{\theta} + g \sin{\left(\theta \right)} \\"
        "\n"
        r"\ddot{\theta} &= - \frac{g \sin{\left(\theta \right)}}{l}"
        "\n\\end{align*}\n"
    )

"""`lagrangian sensitivity` of a dimensioned model says its units (issue 31): CSV headers
with each quotient's SI unit, netCDF attributes, JSON; a model without units writes what
it did."""

from __future__ import annotations

import json
import math

import pytest

from lagrangian.cli import ExitStatus, main

SPRING = """
name = "spring"
coordinates = ["x"]
kinetic = "m*x_dot^2/2"
potential = "k*x^2/2"
[parameters]
m = "500 g"
k = "2 N/cm"
[initial]
x = "10 cm"
"""


@pytest.fixture
def spring(tmp_path):
    path = tmp_path / "spring.toml"
    path.write_text(SPRING)
    return str(path)


def run(capsys, *argv):
    status = main(list(argv))
    captured = capsys.readouterr()
    assert status == ExitStatus.SUCCESS, captured.err
    return captured.out


def _base_units(text: str):
    """pint's reading of ``text`` in SI base units, as a dimensionality to compare."""
    import pint

    return pint.UnitRegistry().Quantity(1, text).to_base_units().dimensionality


@pytest.mark.slow
def test_sensitivity_csv_heads_each_column_with_its_unit(capsys, spring, tmp_path):
    table = tmp_path / "sensitivity.csv"
    run(capsys, "sensitivity", spring, "--wrt", "k,m,x", "--t-end", "1", "--out", str(table))
    header = table.read_text().splitlines()[0].split(",")
    assert header == [
        "t [s]", "x [m]", "x_dot [m/s]", "d(x)/d(k) [m*s^2/kg]", "d(x)/d(m) [m/kg]",
        "d(x)/d(x(0)) [1]", "d(x_dot)/d(k) [m*s/kg]", "d(x_dot)/d(m) [m/(kg*s)]",
        "d(x_dot)/d(x(0)) [1/s]",
    ]  # fmt: skip
    # each quotient as pint reads it: x in m over k in N/m, and so on
    for column, quotient in [(3, "m / (N/m)"), (4, "m / kg"), (6, "(m/s) / (N/m)"),
                             (7, "(m/s) / kg"), (8, "(m/s) / m")]:  # fmt: skip
        unit = header[column].partition(" [")[2].removesuffix("]").replace("^", "**")
        assert _base_units(unit) == _base_units(quotient), header[column]
    last = [float(cell) for cell in table.read_text().splitlines()[-1].split(",")]
    assert last[5] == pytest.approx(math.cos(20.0), abs=1e-7)  # omega = sqrt(200 / 0.5)


def test_sensitivity_json_and_netcdf_say_the_units(capsys, spring, tmp_path):
    data = tmp_path / "sensitivity.nc"
    argv = ("sensitivity", spring, "--wrt", "k,x", "--t-end", "1")
    summary = json.loads(run(capsys, *argv, "--out", str(data), "--json"))
    assert summary["units"] == {
        "t": "s",
        "states": {"x": "m", "x_dot": "m/s"},
        "sensitivities": {"x": {"k": "m*s^2/kg", "x": "1"}, "x_dot": {"k": "m*s/kg", "x": "1/s"}},
    }
    import xarray

    with xarray.open_dataset(data) as dataset:
        assert dataset["time"].attrs["units"] == "s"
        assert dataset["y"].attrs["state_units"] == "m,m/s"
        assert dataset["sensitivity"].attrs["units_by_state_and_wrt"] == "m*s^2/kg,1,m*s/kg,1/s"
    assert run(capsys, *argv).startswith("spring: d state(t) / d w at t = 1 s\n")


def test_a_unitless_sensitivity_is_as_it_was(capsys, tmp_path):
    table, data = tmp_path / "sensitivity.csv", tmp_path / "sensitivity.nc"
    argv = ("sensitivity", "harmonic_oscillator", "--wrt", "k,x", "--t-end", "1")
    run(capsys, *argv, "--out", str(table))
    assert table.read_text().splitlines()[0] == (
        "t,x,x_dot,d(x)/d(k),d(x)/d(x(0)),d(x_dot)/d(k),d(x_dot)/d(x(0))"
    )
    assert "units" not in json.loads(run(capsys, *argv, "--out", str(data), "--json"))
    import xarray

    with xarray.open_dataset(data) as dataset:
        attributes = [dataset[name].attrs for name in ("time", "y", "sensitivity")]
    assert attributes == [{}, {}, {}]
    assert run(capsys, *argv).splitlines()[0].endswith("at t = 1")

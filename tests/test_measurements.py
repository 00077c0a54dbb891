"""Measured data for a fit: each problem of a file is one line naming the file and the
row or column; units in the header are converted to the model's SI units."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

import lagrangian as lg
from lagrangian.errors import FileError
from lagrangian.integrate.observation import observed_expressions
from lagrangian.measurements import noise_levels, read_measurements

PENDULUM = lg.System.from_lagrangian(
    "m*l**2*theta_dot**2/2 + m*g*l*cos(theta)", coordinates=["theta"]
)
DIMENSIONED = lg.loads(
    """
name = "cart"
coordinates = ["x"]
lagrangian = "m*x_dot^2/2 - k*x^2/2"
[parameters]
m = "2 kg"
k = "3 N/m"
[units]
x = "m"
"""
)


def read(tmp_path, text, system=PENDULUM, observe=None, name="data.csv"):
    path = tmp_path / name
    path.write_text(text)
    expressions = observed_expressions(system, observe or {})
    return read_measurements(str(path), system, expressions), str(path)


def error_of(tmp_path, text, system=PENDULUM, observe=None):
    with pytest.raises(FileError) as caught:
        read(tmp_path, text, system, observe)
    return str(caught.value).removeprefix(str(tmp_path / "data.csv") + ": ")


def test_a_clean_file_is_read_in_order(tmp_path):
    found, path = read(
        tmp_path, "t,theta,x_tip\n0,0.5,0.1\n0.1,0.4,0.2\n", observe={"x_tip": "l*sin(theta)"}
    )
    assert found.source == path and found.dropped == ()
    assert np.array_equal(found.times, [0.0, 0.1])
    assert list(found.columns) == ["theta", "x_tip"]
    assert np.array_equal(found.columns["x_tip"], [0.1, 0.2])


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "the file is empty (expected a header such as 't,x')"),
        ("\n \n", "the file is empty (expected a header such as 't,x')"),
        ("t,theta\n", "no data rows after the header"),
        ("time,theta\n0,1\n", "no column 't' (the columns there: time, theta)"),
        ("t\n0\n1\n", "no measured column besides 't'"),
        ("t,phi\n0,1\n", "column 'phi' is neither a coordinate or velocity of the model"),
        ("t,theta\n0,1\n0.1,abc\n", "row 3, column 'theta': 'abc' is not a number"),
        ("t,theta\n0,1\n0.1,inf\n", "row 3, column 'theta': inf is not finite"),
        ("t,theta\n0,1\n0.1\n", "row 3 has 1 cells, the header 2"),
        (
            "t,theta\n0,1\n0.2,1\n0.1,1\n",
            "row 4: t = 0.1 is not after t = 0.2 of row 3 (times must increase)",
        ),
        ("t,theta\n0,1\n0,1\n", "row 3: t = 0 is not after t = 0 of row 2 (times must increase)"),
        ("t,theta\n-1,1\n0,1\n", "row 2: t = -1 is before 0, where the model's initial values are"),
        ("t,theta,theta\n0,1,1\n", "column 'theta' appears twice in the header"),
        ("t,,theta\n0,1,1\n", "column 2 of the header, '', is not 'NAME' or 'NAME [unit]'"),
        ("t,theta\n0,\nnan,1\n", "every row has a missing value (empty or NaN)"),
        ("t [s],theta\n0,1\n", "column 't [s]' has a unit but the model has none"),
    ],
)
def test_each_problem_is_one_line_naming_the_file_and_place(tmp_path, text, message):
    assert error_of(tmp_path, text).startswith(message)


def test_a_missing_observed_column_is_named_with_the_columns_there(tmp_path):
    message = error_of(tmp_path, "t,theta\n0,1\n", observe={"x_tip": "l*sin(theta)"})
    assert message == "no column 'x_tip' to compare with (the columns there: t, theta)"


def test_rows_with_a_missing_value_are_dropped_and_listed(tmp_path):
    found, _ = read(tmp_path, "t,theta\n0,1\n0.1,\n0.2,NaN\n0.3,2\n")
    assert found.dropped == (3, 4)  # the header is row 1
    assert np.array_equal(found.times, [0.0, 0.3])


def test_units_in_the_header_are_converted_to_the_models(tmp_path):
    found, _ = read(tmp_path, "t [ms],x [cm],x_dot [km/h]\n0,150,36\n500,-20,0\n", DIMENSIONED)
    assert np.allclose(found.times, [0.0, 0.5])
    assert np.allclose(found.columns["x"], [1.5, -0.2])
    assert np.allclose(found.columns["x_dot"], [10.0, 0.0])
    assert found.units == {"t": "ms", "x": "cm", "x_dot": "km/h"}


def test_an_angle_in_degrees_becomes_radians(tmp_path):
    pendulum = lg.loads(
        'coordinates = ["theta"]\nlagrangian = "m*l^2*theta_dot^2/2 + m*g*l*cos(theta)"\n'
        '[parameters]\nm = "1 kg"\nl = "1 m"\ng = "9.81 m/s^2"\n'
    )
    found, _ = read(tmp_path, "t [s],theta [deg]\n0,90\n", pendulum)
    assert math.isclose(found.columns["theta"][0], math.pi / 2)


@pytest.mark.parametrize(
    ("header", "message"),
    [
        ("t,x [s]", "column 'x [s]': x is a length (m), but s is a time (s)"),
        ("t [m],x", "column 't [m]': t is a time (s), but m is a length (m)"),
        ("t,x_tip [kg]", "column 'x_tip [kg]': x_tip is a length (m), but kg is a mass (kg)"),
        ("t,x [parsecz]", "column 'x': unknown unit 'parsecz'"),
    ],
)
def test_a_unit_of_another_dimension_is_refused_naming_the_column(tmp_path, header, message):
    text = f"{header}\n0,1\n"
    observe = {"x_tip": "2*x"} if "x_tip" in header else {}
    assert error_of(tmp_path, text, DIMENSIONED, observe).startswith(message)


def test_netcdf_with_a_time_coordinate_and_units(tmp_path):
    dataset = xr.Dataset(
        {"x": ("time", [100.0, 50.0], {"units": "cm"})}, coords={"time": [0.0, 2.0]}
    )
    path = tmp_path / "data.nc"
    dataset.to_netcdf(path, engine="scipy")
    found = read_measurements(str(path), DIMENSIONED)
    assert np.allclose(found.columns["x"], [1.0, 0.5]) and np.allclose(found.times, [0, 2])


def test_a_file_that_is_not_there(tmp_path):
    with pytest.raises(FileError, match="no such file"):
        read_measurements(str(tmp_path / "none.csv"), PENDULUM)


DEGREES = lg.loads(
    'coordinates = ["theta"]\nlagrangian = "m*l^2*theta_dot^2/2 + m*g*l*cos(theta)"\n'
    '[parameters]\nm = "1 kg"\nl = "1 m"\ng = "9.81 m/s^2"\n[units]\ntheta = "deg"\n'
)


def test_a_column_without_a_unit_is_in_the_unit_the_model_declares(tmp_path):
    found, _ = read(tmp_path, "t,theta,theta_dot\n0,90,180\n", DEGREES)
    assert math.isclose(found.columns["theta"][0], math.pi / 2)
    assert math.isclose(found.columns["theta_dot"][0], math.pi)  # deg/s


def test_noise_levels_in_the_columns_units():
    assert np.allclose(noise_levels("0.5 cm", ["x"], DIMENSIONED), [0.005])
    both = noise_levels({"x": "2 mm", "x_dot": 0.1}, ["x", "x_dot"], DIMENSIONED)
    assert np.allclose(both, [0.002, 0.1])
    assert np.allclose(noise_levels(0.3, ["theta"], DEGREES), [0.3 * math.pi / 180])
    with pytest.raises(lg.ModelError) as error:
        noise_levels("1 s", ["x"], DIMENSIONED)
    assert str(error.value) == (
        "noise: the noise of column 'x [s]': x is a length (m), but s is a time (s)"
    )


def test_an_xarray_dataset_in_memory():
    dataset = xr.Dataset({"theta": ("t", [0.5, 0.4, np.nan])}, coords={"t": [0.0, 0.1, 0.2]})
    found = read_measurements(dataset, PENDULUM)
    assert found.source == "<data>" and found.dropped == (2,) and found.place == "index"
    assert np.array_equal(found.columns["theta"], [0.5, 0.4])


def test_times_out_of_order_in_a_dataset_name_the_index():
    dataset = xr.Dataset({"theta": ("t", [0.5, 0.4, 0.3])}, coords={"t": [0.0, 0.2, 0.1]})
    with pytest.raises(FileError) as error:
        read_measurements(dataset, PENDULUM)
    assert str(error.value) == (
        "<data>: index 2: t = 0.1 is not after t = 0.2 of index 1 (times must increase)"
    )

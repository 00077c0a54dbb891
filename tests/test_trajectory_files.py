"""Reading trajectory files that are not what they claim: one FileError naming the file."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from lagrangian.errors import FileError
from lagrangian.trajectory import Trajectory
from lagrangian.trajectory_files import MAX_TRAJECTORY_BYTES

HEADER = "t,x,x_dot,energy\n"


def make() -> Trajectory:
    t = np.linspace(0.0, 1.0, 5)
    return Trajectory.build(
        t=t, coordinates=["x"], y=np.array([np.cos(t), -np.sin(t)]), energy=np.full(5, 0.5)
    )


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "is empty, not a trajectory file"),
        ("a,b\n1,2\n", r"is not a trajectory CSV file \(first column must be t\)"),
        ("t,x,x_dot\n0,1,0\n", "has no column 'energy'"),
        ("t,x,energy\n0,1,0\n", r"has no coordinate columns \(a q with its q_dot\)"),
        ("t,x,x,x_dot,energy\n0,1,1,0,0\n", "has the column 'x' twice"),
        (HEADER, "has a header but no rows"),
        (HEADER + "0,1,0,0.5\n0.1,1,0\n", "line 3 has 3 values, the header 4"),
        (HEADER + "0,1,0,0.5\n0.1,one,0,0.5\n", "line 3, column 2: 'one' is not a number"),
        (HEADER + "0,1,0,0.5\nnan,1,0,0.5\n", r"has a time t that is not finite \(nan in row 2\)"),
        (HEADER + "inf,1,0,0.5\n", r"has a time t that is not finite \(inf in row 1\)"),
        ("t,x,x_dot,energy,extra\n0,1,0,0.5\n", "has 4 values per row but 5 column names"),
    ],
)
def test_malformed_csv_files_are_refused_naming_the_file(tmp_path, text, message):
    path = tmp_path / "run.csv"
    path.write_text(text)
    with pytest.raises(FileError, match=rf"^{tmp_path}/run\.csv: {message}") as raised:
        Trajectory.load(path)
    assert "\n" not in str(raised.value)


def test_a_binary_csv_is_refused(tmp_path):
    path = tmp_path / "run.csv"
    path.write_bytes(b"t,x\n\xff\xfe\x00\x81")
    with pytest.raises(FileError, match=r"run\.csv: is not a text file"):
        Trajectory.load(path)


@pytest.mark.parametrize(
    ("data", "message"),
    [
        (b"", "is empty"),
        (bytes(range(256)), "is not a netCDF file"),
        (b"CDF\x01\x00\x00\x00\x03\x00\x00", "is a damaged netCDF file"),
        (b"\x89HDF\r\n\x1a\n" + bytes(100), "is netCDF-4"),
    ],
)
def test_damaged_netcdf_files_are_refused(tmp_path, data, message):
    path = tmp_path / "run.nc"
    path.write_bytes(data)
    with pytest.raises(FileError, match=rf"run\.nc: {message}"):
        Trajectory.load(path)


def test_a_truncated_netcdf_of_ours_is_refused(tmp_path):
    path = make().to_netcdf(tmp_path / "run.nc")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(FileError, match=r"run\.nc: is a damaged netCDF file"):
        Trajectory.load(path)


def test_another_programs_netcdf_is_refused(tmp_path):
    path = tmp_path / "weather.nc"
    xr.Dataset({"temperature": ("time", [280.0, 281.0])}).to_netcdf(path, engine="scipy")
    with pytest.raises(FileError, match=r"weather\.nc: holds no trajectory of lagrangian"):
        Trajectory.load(path)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda d: d.drop_vars("energy"), "has no variable 'energy'"),
        (lambda d: d.drop_vars("x_dot"), "has no variable 'x_dot'"),
        (lambda d: d.assign_attrs(invariants="p_x"), "has no variable 'p_x'"),
        (lambda d: d.assign_attrs(coordinate_names=""), "lists no coordinates"),
        (lambda d: d.assign_coords(t=[0, 1, np.nan, 3, 4]), "has a time t that is not finite"),
        (lambda d: d.assign(x=("t", ["a"] * 5)), "has a variable 'x' that is not numbers along t"),
    ],
)
def test_a_netcdf_missing_what_its_attributes_promise_is_refused(tmp_path, change, message):
    path = tmp_path / "run.nc"
    change(make().dataset).to_netcdf(path, engine="scipy")
    with pytest.raises(FileError, match=rf"run\.nc: {message}"):
        Trajectory.load(path)


def test_a_folder_and_a_huge_file_are_refused(tmp_path):
    (tmp_path / "folder.nc").mkdir()
    with pytest.raises(FileError, match=r"folder\.nc: is a folder, not a trajectory file"):
        Trajectory.load(tmp_path / "folder.nc")
    with open(tmp_path / "huge.csv", "wb") as stream:  # sparse: no disk used
        stream.truncate(MAX_TRAJECTORY_BYTES + 1)
    with pytest.raises(FileError, match=r"huge\.csv: is too large to be read \(1024 MiB"):
        Trajectory.load(tmp_path / "huge.csv")


def test_good_files_still_round_trip(tmp_path):
    for suffix in (".csv", ".nc"):
        loaded = Trajectory.load(make().save(tmp_path / f"run{suffix}"))
        np.testing.assert_array_equal(loaded["x"], make()["x"])


def test_ensemble_files_are_checked_too(tmp_path):
    import lagrangian as lg
    from lagrangian.ensemble import EnsembleTrajectory, ensemble_of_system

    result = ensemble_of_system(lg.load("simple_pendulum"), initial={"theta": [0.1]}, t_end=0.2)
    loaded = EnsembleTrajectory.load(result.to_netcdf(tmp_path / "runs.nc"))
    assert loaded.attrs["members"] == 1
    (tmp_path / "empty.nc").write_bytes(b"")
    with pytest.raises(FileError, match=r"empty\.nc: is empty, not an ensemble file"):
        EnsembleTrajectory.load(tmp_path / "empty.nc")
    (tmp_path / "noise.nc").write_bytes(bytes(range(256)))
    with pytest.raises(FileError, match=r"noise\.nc: is not a readable netCDF file"):
        EnsembleTrajectory.load(tmp_path / "noise.nc")
    make().to_netcdf(tmp_path / "single.nc")
    with pytest.raises(FileError, match=r"single\.nc: holds no ensemble of lagrangian"):
        EnsembleTrajectory.load(tmp_path / "single.nc")

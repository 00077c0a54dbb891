"""`Trajectory`: layout, CSV / NetCDF round trips, atomic writes, drift and summary."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
import xarray as xr

from lagrangian.errors import FileError, ModelError
from lagrangian.trajectory import EventRecord, Trajectory


def make(*, events=True, multipliers=True) -> Trajectory:
    t = np.linspace(0.0, 1.0, 6)
    y = np.array([np.cos(t), np.sin(t), -np.sin(t), np.cos(t)]) / 3.0  # 1/3: not short in text
    return Trajectory.build(
        t=t,
        coordinates=["x", "y"],
        y=y,
        energy=np.full(6, -0.5) + np.array([0, 1e-9, -2e-9, 0, 0, 1e-9]),
        invariants={"angular_momentum": np.full(6, 1 / 9), "energy": np.zeros(6)},
        multipliers={"lambda1": -t} if multipliers else {},
        events=[
            EventRecord("apex", np.array([0.25, 0.75]), np.arange(8.0).reshape(4, 2)),
            EventRecord("never", np.empty(0), np.empty((4, 0))),
        ]
        if events
        else [],
        attrs={
            "model": "Test",
            "method": "rk4",
            "dt": 0.2,
            "steps": 5,
            "status": "success",
            "wall_time": 0.01,
            "parameters": {"mu": 1.0},
            "rtol": None,  # left out: not a setting of this method
            "explicit": True,
        },
    )


def test_layout_of_the_dataset():
    trajectory = make()
    dataset = trajectory.dataset
    assert set(dataset.dims) == {"t", "state", "event__apex"}  # no empty dimension
    expected = ["x", "y", "x_dot", "y_dot", "energy", "angular_momentum", "lambda1"]
    assert [name for name in dataset.data_vars if dataset[name].dims == ("t",)] == expected
    assert trajectory.coordinates == ("x", "y")
    assert trajectory.velocities == ("x_dot", "y_dot")
    assert trajectory.invariants == ("angular_momentum",)  # "energy" is there already
    assert trajectory.multipliers == ("lambda1",)
    assert dataset.attrs["method"] == "rk4"
    assert "rtol" not in dataset.attrs
    assert dataset.attrs["explicit"] == 1
    assert trajectory.parameters == {"mu": 1.0}


def test_final_state_and_events():
    trajectory = make()
    assert trajectory.final_state == pytest.approx(
        {"x": np.cos(1) / 3, "y": np.sin(1) / 3, "x_dot": -np.sin(1) / 3, "y_dot": np.cos(1) / 3}
    )
    events = trajectory.events
    assert list(events) == ["apex", "never"]
    assert events["apex"].times.tolist() == [0.25, 0.75]
    np.testing.assert_array_equal(events["apex"].states, np.arange(8.0).reshape(4, 2))
    assert events["never"].count == 0
    assert events["never"].states.shape == (4, 0)


def test_drift_is_relative_unless_the_start_is_zero():
    trajectory = make()
    assert trajectory.drift("energy") == pytest.approx(2e-9 / 0.5)
    assert trajectory.drift("lambda1") == pytest.approx(1.0)  # starts at 0: absolute
    assert trajectory.drift("angular_momentum") == 0.0
    assert trajectory.drifts() == {
        "energy": pytest.approx(4e-9),
        "angular_momentum": 0.0,
    }


def test_summary_is_the_simulate_json_document():
    summary = make().summary()
    assert list(summary) == [
        "final_state", "invariants", "method", "dt", "steps", "wall_time", "status", "events",
    ]  # fmt: skip
    assert summary["method"] == "rk4"
    assert summary["dt"] == 0.2
    assert summary["events"] == {"apex": [0.25, 0.75], "never": []}
    json.dumps(summary)  # plain Python types only


def test_energy_not_conserved_leaves_the_drifts_for_the_summary_with_its_reason():
    trajectory = make()
    trajectory.dataset.attrs["energy_not_conserved"] = "dissipation"
    assert trajectory.drifts() == {"angular_momentum": 0.0}
    summary = trajectory.summary()
    assert summary["not_conserved"] == {
        "energy": {"change": pytest.approx(4e-9), "reason": "dissipation"}
    }


# -- files ------------------------------------------------------------------------------------
def test_csv_has_the_documented_columns_and_round_trips_exactly(tmp_path):
    trajectory = make()
    path = trajectory.to_csv(tmp_path / "run.csv")
    with open(path, newline="") as stream:
        rows = list(csv.reader(stream))
    assert rows[0] == ["t", "x", "y", "x_dot", "y_dot", "energy", "angular_momentum", "lambda1"]
    assert len(rows) == 7
    assert float(rows[-1][0]) == 1.0  # the last row is the state at t_end
    loaded = Trajectory.load(path)
    for name in ["t", *rows[0][1:]]:
        np.testing.assert_array_equal(loaded[name], trajectory[name])  # %.17g: exact
    assert loaded.coordinates == ("x", "y")
    assert loaded.final_state == trajectory.final_state


def test_netcdf_round_trips_everything(tmp_path):
    trajectory = make()
    loaded = Trajectory.load(trajectory.to_netcdf(tmp_path / "run.nc"))
    xr.testing.assert_identical(loaded.dataset, trajectory.dataset)
    assert loaded.events["apex"].times.tolist() == [0.25, 0.75]
    assert loaded.parameters == {"mu": 1.0}
    assert loaded.summary() == trajectory.summary()


def test_save_picks_the_format_by_suffix(tmp_path):
    trajectory = make(events=False, multipliers=False)
    trajectory.save(tmp_path / "a.csv")
    trajectory.save(tmp_path / "a.nc")
    assert (tmp_path / "a.csv").read_text().startswith("t,x,y,x_dot,y_dot,energy")
    assert Trajectory.load(tmp_path / "a.nc").coordinates == ("x", "y")
    with pytest.raises(ModelError, match=r"unknown trajectory file type '.txt' \(use .csv, .nc\)"):
        trajectory.save(tmp_path / "a.txt")


def test_a_csv_that_is_not_a_trajectory_is_refused(tmp_path):
    path = tmp_path / "other.csv"
    path.write_text("a,b\n1,2\n")
    with pytest.raises(FileError, match=r"other\.csv: is not a trajectory CSV file"):
        Trajectory.load(path)


class Boom(RuntimeError):
    pass


@pytest.mark.parametrize("suffix", [".csv", ".nc"])
def test_a_failed_write_leaves_no_file(tmp_path, monkeypatch, suffix):
    def fail_csv(stream, *args, **kwargs):  # np.savetxt(stream, ...): half a row, then fail
        stream.write("t,x\n0.0,")
        raise Boom("disk full")

    def fail_netcdf(dataset, path, *args, **kwargs):  # Dataset.to_netcdf(path, ...)
        with open(path, "w") as stream:
            stream.write("CDF half a header")
        raise Boom("disk full")

    monkeypatch.setattr(np, "savetxt", fail_csv)
    monkeypatch.setattr(xr.Dataset, "to_netcdf", fail_netcdf)
    target = tmp_path / f"run{suffix}"
    with pytest.raises(Boom):
        make().save(target)
    assert list(tmp_path.iterdir()) == []  # neither the target nor a temporary file


@pytest.mark.parametrize("suffix", [".csv", ".nc"])
def test_a_failed_write_leaves_the_old_file_as_it_was(tmp_path, monkeypatch, suffix):
    target = tmp_path / f"run{suffix}"
    make().save(target)
    before = target.read_bytes()

    def fail(*args, **kwargs):
        raise Boom("disk full")

    monkeypatch.setattr(np, "savetxt", fail)
    monkeypatch.setattr(xr.Dataset, "to_netcdf", fail)
    with pytest.raises(Boom):
        make(events=False).save(target)
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == [target.name]


def test_written_files_get_ordinary_permissions(tmp_path):
    import os
    import stat

    path = make().to_csv(tmp_path / "run.csv")
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask

"""A trajectory built from arrays reads the same before its xarray Dataset is made (from
its :class:`~lagrangian.trajectory_table.Table`) as after (from the Dataset)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from lagrangian.trajectory import EventRecord, ImpactRecord, Trajectory
from lagrangian.trajectory_table import Table


def build(**changes) -> Trajectory:
    t = np.linspace(0.0, 2.0, 9)
    y = np.array([np.cos(t), np.sin(3 * t), -np.sin(t), 3 * np.cos(3 * t)]) / 7.0
    impacts = [
        ImpactRecord(0.5, "wall", np.array([1.0, -2.0]), np.array([-0.5, -2.0]), 3.0, 2.25),
        ImpactRecord(1.5, "floor", np.array([0.25, 2.0]), np.array([0.25, -1.0]), 2.0, 0.5),
    ]
    system = SimpleNamespace(
        impacts=[SimpleNamespace(name="floor"), SimpleNamespace(name="wall")], units=None
    )
    options = {
        "t": t,
        "coordinates": ["a", "b"],
        "y": y,
        "energy": 1.0 + t**2 * 1e-6,
        "invariants": {"p_a": np.full(9, 0.5) - t * 1e-8},
        "multipliers": {"lambda1": np.sin(t)},
        "reactions": {"R_B_x": np.cos(5 * t)},
        "events": [
            EventRecord("cross", np.array([0.3, 1.1, 1.7]), np.arange(12.0).reshape(4, 3)),
            EventRecord("none", np.empty(0), np.empty((4, 0))),
        ],
        "attrs": {"model": "m", "method": "dop853", "rtol": 1e-9, "steps": 12, "status": "success",
                  "holds": "[[\"floor\", 1.5, 2.0]]", "energy_not_conserved": "impacts"},
        "system": system,
        "impacts": impacts,
    }  # fmt: skip
    options.update(changes)
    return Trajectory.build(**options)


def readings(trajectory: Trajectory) -> dict[str, object]:
    events = trajectory.events
    return {
        "summary": trajectory.summary(),
        "t": trajectory.t.tolist(),
        "columns": {name: trajectory[name].tolist() for name in trajectory.columns()},
        "events": {k: (r.times.tolist(), r.states.tolist()) for k, r in events.items()},
        "impacts": [
            (
                r.t,
                r.contact,
                r.velocities_before.tolist(),
                r.velocities_after.tolist(),
                r.energy_before,
                r.energy_after,
            )
            for r in trajectory.impacts
        ],
        "names": (
            trajectory.coordinates,
            trajectory.invariants,
            trajectory.multipliers,
            trajectory.reactions,
            trajectory.contacts,
        ),
        "attrs": dict(trajectory.attrs),
    }


def test_every_reading_is_the_same_from_the_table_and_from_the_dataset():
    trajectory = build()
    assert isinstance(trajectory._data, Table)
    before = readings(trajectory)
    trajectory.dataset  # noqa: B018 (makes the Dataset)
    assert not isinstance(trajectory._data, Table)
    assert readings(trajectory) == before
    assert before["impacts"][1][1] == "floor"  # the contact index is read back as its name
    assert before["events"]["cross"][1][2] == [6.0, 7.0, 8.0]  # states (2n, k), not (k, 2n)


def test_attributes_added_before_the_dataset_is_made_are_in_it():
    trajectory = build()
    trajectory.attrs["compile_time"] = 0.25  # as integrate.simulate does
    assert trajectory.dataset.attrs["compile_time"] == 0.25
    assert trajectory.summary()["compile_time"] == 0.25


def test_units_are_on_the_table_and_the_dataset():
    units = SimpleNamespace(column_unit={"t": "s", "a": "m", "a_dot": "m/s"}.get)
    trajectory = build(system=SimpleNamespace(impacts=[], units=units), impacts=None)
    assert trajectory.summary()["units"] == {"t": "s", "a": "m", "a_dot": "m/s"}
    assert trajectory.dataset["a_dot"].attrs["units"] == "m/s"
    assert "units" not in trajectory.dataset["b"].attrs


def test_a_column_of_another_length_is_refused_when_built_as_xarray_refuses_it():
    with pytest.raises(ValueError, match="conflicting sizes for dimension 't'"):
        build(invariants={"p_a": np.zeros(8)})

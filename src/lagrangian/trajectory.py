"""`Trajectory`: one simulated motion, backed by an :class:`xarray.Dataset`.

The dataset has one dimension ``t`` (the output times) and the data variables

- every coordinate ``q`` and its velocity ``q_dot``,
- ``energy``, the energy function h = q'.dL/dq' - L (the Jacobi integral),
- every conserved quantity of the system (names from ``compiled.invariants``),
- the Lagrange multipliers ``lambda1, ...`` of a constrained system,
- a linkage's joint reactions ``R_<joint>_x, R_<joint>_y`` (and ``M_``, ``tau_``, ``F_``;
  :mod:`lagrangian.model.linkage_reactions`),

and the attributes ``model``, ``method``, ``status``, ``message``, ``steps``,
``rhs_evaluations``, ``wall_time`` (seconds), ``compile_time`` (CPU seconds spent making
or loading the run's compiled code: its y' and, for DOP853's compiled loop, the loop, for
taylor heyoka's integrator) and ``compiled`` (what, in words, where a compiled loop or
heyoka ran), the settings of the method
(``rtol``/``atol`` or ``dt``, ...), ``parameters`` (a JSON object of the
parameter values used) and the comma-separated name lists ``coordinate_names``
(not ``coordinates``, which netCDF's CF conventions reserve), ``invariants``,
``multipliers``, ``reactions`` and ``events``.  Each event ``e`` adds the
variables ``event__e__t`` (its times) and ``event__e__y`` (the states there)
along their own dimension ``event__e`` (and ``state``: q..., q_dot...).

Files (DESIGN section 5): ``to_csv`` writes the columns
``t, <q...>, <q_dot...>, energy`` then the invariants, multipliers and reactions, one row
per output time; ``to_netcdf`` writes the whole dataset (SciPy's netCDF-3
writer, no extra dependency).  Both write atomically: a temporary file in the
same directory, renamed over the target only when complete
(:func:`lagrangian.files.write_atomically`), so a failed write never leaves a
truncated file.  A CSV file holds no metadata; NetCDF round
trips everything.

xarray is imported only when ``dataset`` is first read (or a file is read): a trajectory
built by :meth:`Trajectory.build` holds its arrays in a
:class:`~lagrangian.trajectory_table.Table` until then, so that ``simulate --json`` (which
reads a few arrays) does not pay for the first Dataset (about 1 s of CPU).
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .errors import ModelError
from .files import write_atomically, write_csv
from .trajectory_files import name_list, read_csv, read_netcdf
from .trajectory_table import Table

if TYPE_CHECKING:
    import xarray

    from .model import System

#: Below this |X(0)| the drift of X is absolute, above it relative.
DRIFT_RELATIVE_FLOOR = 1e-12


@dataclass(frozen=True, eq=False)
class EventRecord:
    """The occurrences of one event: ``times`` (k,) and ``states`` (2n, k)."""

    name: str
    times: np.ndarray
    states: np.ndarray

    @property
    def count(self) -> int:
        return int(self.times.shape[0])


@dataclass(frozen=True, eq=False)
class ImpactRecord:
    """One impact of a run with contacts (``[[impacts]]``): its time ``t``, the ``contact``'s
    name, the velocities q' before and after (n,) and the energy before and after."""

    t: float
    contact: str
    velocities_before: np.ndarray
    velocities_after: np.ndarray
    energy_before: float
    energy_after: float


class Trajectory:
    """A simulated motion; see the module docstring for the layout of ``dataset``.

    ``system`` is the model that was simulated (kept in memory for drawing; a
    trajectory loaded from a file has none).
    """

    def __init__(self, dataset: xarray.Dataset | Table, system: System | None = None) -> None:
        self._data = dataset  # a Table until ``dataset`` is first read
        self.system = system

    @property
    def dataset(self) -> xarray.Dataset:
        if isinstance(self._data, Table):
            self._data = self._data.to_dataset()
        return self._data

    @property
    def attrs(self) -> dict[str, object]:
        """The attributes of ``dataset`` (read without making it)."""
        return self._data.attrs

    def __repr__(self) -> str:
        return f"Trajectory(dataset={self.dataset!r})"

    # -- building ---------------------------------------------------------------
    @classmethod
    def build(
        cls,
        *,
        t: np.ndarray,
        coordinates: Sequence[str],
        y: np.ndarray,
        energy: np.ndarray,
        invariants: Mapping[str, np.ndarray] | None = None,
        multipliers: Mapping[str, np.ndarray] | None = None,
        reactions: Mapping[str, np.ndarray] | None = None,
        events: Sequence[EventRecord] = (),
        attrs: Mapping[str, object] | None = None,
        system: System | None = None,
        impacts: Sequence[ImpactRecord] | None = None,
    ) -> Trajectory:
        """A trajectory from arrays: ``y`` (2n, T) holds q then q' at the times ``t`` (T,)."""
        t = np.asarray(t, dtype=float)
        y = np.asarray(y, dtype=float)
        n = len(coordinates)
        if y.shape != (2 * n, t.shape[0]):
            raise ValueError(f"y must have shape {(2 * n, t.shape[0])}, not {y.shape}")
        velocities = [f"{q}_dot" for q in coordinates]
        columns: dict[str, np.ndarray] = dict(zip([*coordinates, *velocities], y, strict=True))
        columns["energy"] = np.asarray(energy, dtype=float)
        invariants = {k: v for k, v in (invariants or {}).items() if k not in columns}
        multipliers = dict(multipliers or {})
        reactions = dict(reactions or {})
        for name, values in [*invariants.items(), *multipliers.items(), *reactions.items()]:
            if name in columns:
                raise ValueError(f"two data variables named '{name}'")
            columns[name] = np.asarray(values, dtype=float)
        data_vars: dict[str, object] = {name: ("t", values) for name, values in columns.items()}
        coords: dict[str, object] = {"t": t}
        if any(record.count for record in events):
            coords["state"] = [*coordinates, *velocities]
        for record in events:
            if record.count == 0:  # netCDF-3 has no empty dimensions: the name list says it
                continue
            dim = f"event__{record.name}"
            data_vars[f"{dim}__t"] = (dim, np.asarray(record.times, dtype=float))
            data_vars[f"{dim}__y"] = (("state", dim), np.asarray(record.states, dtype=float))
        meta = {
            "coordinate_names": ",".join(coordinates),
            "invariants": ",".join(invariants),
            "multipliers": ",".join(multipliers),
            "reactions": ",".join(reactions),
            "events": ",".join(record.name for record in events),
        }
        meta.update(_netcdf_attrs(attrs or {}))
        if impacts is not None:  # a model with contacts: its impacts, even none
            meta["contacts"] = ",".join(contact.name for contact in system.impacts)
            data_vars.update(_impact_variables(impacts, meta["contacts"]))
            if impacts:
                coords["velocity"] = velocities
        units = system.units if system is not None else None
        column_units = {}
        if units is not None:  # CF conventions: a units attribute on each variable
            for name in ["t", *columns]:
                unit = units.column_unit(name)
                if unit is not None:
                    column_units[name] = unit
        return cls(Table(data_vars, coords, meta, column_units), system)

    # -- reading ----------------------------------------------------------------
    @property
    def t(self) -> np.ndarray:
        return self._data["t"].values

    @property
    def coordinates(self) -> tuple[str, ...]:
        return name_list(self._data.attrs.get("coordinate_names", ""))

    @property
    def velocities(self) -> tuple[str, ...]:
        return tuple(f"{q}_dot" for q in self.coordinates)

    @property
    def invariants(self) -> tuple[str, ...]:
        return name_list(self._data.attrs.get("invariants", ""))

    @property
    def multipliers(self) -> tuple[str, ...]:
        return name_list(self._data.attrs.get("multipliers", ""))

    @property
    def reactions(self) -> tuple[str, ...]:
        """A linkage's joint reactions (``R_B_x``, ...; see :mod:`.model.linkage_reactions`)."""
        return name_list(self._data.attrs.get("reactions", ""))

    @property
    def status(self) -> str:
        return str(self._data.attrs.get("status", ""))

    @property
    def parameters(self) -> dict[str, float]:
        return json.loads(self._data.attrs.get("parameters", "{}"))

    def __getitem__(self, name: str) -> np.ndarray:
        """The values of one data variable along ``t``."""
        return self._data[name].values

    @property
    def final_state(self) -> dict[str, float]:
        """{q: value, q_dot: value} at the last output time."""
        return {name: float(self[name][-1]) for name in (*self.coordinates, *self.velocities)}

    @property
    def events(self) -> dict[str, EventRecord]:
        """{name: EventRecord} for every event watched, in order (empty records included)."""
        records = {}
        size = 2 * len(self.coordinates)
        for name in name_list(self._data.attrs.get("events", "")):
            dim = f"event__{name}"
            if f"{dim}__t" not in self._data:
                records[name] = EventRecord(name, np.empty(0), np.empty((size, 0)))
                continue
            states = self._data[f"{dim}__y"].transpose("state", dim).values
            records[name] = EventRecord(name, self[f"{dim}__t"], states)
        return records

    @property
    def contacts(self) -> tuple[str, ...]:
        """The names of the model's contacts (``[[impacts]]``); empty without any."""
        return name_list(self._data.attrs.get("contacts", ""))

    @property
    def impacts(self) -> list[ImpactRecord]:
        """Every impact of the run, in order of time (empty without contacts)."""
        if "impact__t" not in self._data:
            return []
        d, contacts = self._data, self.contacts
        return [
            ImpactRecord(
                float(d["impact__t"].values[i]),
                contacts[int(d["impact__contact"].values[i])],
                d["impact__velocities_before"].values[:, i],
                d["impact__velocities_after"].values[:, i],
                float(d["impact__energy_before"].values[i]),
                float(d["impact__energy_after"].values[i]),
            )
            for i in range(d["impact__t"].shape[0])
        ]

    def drift(self, name: str) -> float:
        """max_t |X(t) - X(0)| of the variable ``name``, divided by |X(0)| when |X(0)| > 1e-12.

        The relative form makes drifts of differently scaled quantities
        comparable; a quantity that starts at (nearly) zero gets the absolute one.
        """
        values = self[name]
        deviation = float(np.max(np.abs(values - values[0]))) if values.size else 0.0
        scale = abs(float(values[0])) if values.size else 0.0
        return deviation / scale if scale > DRIFT_RELATIVE_FLOOR else deviation

    @property
    def energy_not_conserved(self) -> str:
        """Why the energy is not conserved along this run ("" when it is, or not known: a
        trajectory read from CSV)."""
        return str(self._data.attrs.get("energy_not_conserved", ""))

    @property
    def conserved_here(self) -> dict[str, str]:
        """The quantities conserved in this run though not in general, name -> why not in
        general (the causes vanish at its parameter values: an input 0, an amplitude 0)."""
        return json.loads(self._data.attrs.get("conserved_here", "{}"))

    def drifts(self) -> dict[str, float]:
        """The drift of every conserved quantity: the energy where it is conserved.

        Where it is not (:attr:`energy_not_conserved`: forced, dissipative or
        time-dependent systems) its change is physics, not error:
        :meth:`summary` gives it under ``not_conserved`` with the reason.
        """
        energy = () if self.energy_not_conserved else ("energy",)
        return {name: self.drift(name) for name in (*energy, *self.invariants)}

    def summary(self) -> dict[str, object]:
        """The ``simulate --json`` document (DESIGN section 5) as a dict."""
        attrs = self._data.attrs
        document: dict[str, object] = {
            "final_state": self.final_state,
            "invariants": self.drifts(),
        }
        if self.energy_not_conserved:
            document["not_conserved"] = {
                "energy": {"change": self.drift("energy"), "reason": self.energy_not_conserved}
            }
        if self.conserved_here:  # in general not: say why it is in this run
            document["conserved_in_this_run"] = {
                name: {"reason_in_general": reason} for name, reason in self.conserved_here.items()
            }
        units = {
            name: str(self._data[name].attrs["units"])
            for name in dict.fromkeys(["t", *self.final_state, "energy", *self.drifts()])
            if "units" in self._data[name].attrs
        }
        if units:  # additive: a dimensioned model's units (issue 31)
            document["units"] = units
        if self.reactions:  # additive: a linkage's joint reactions (issue 34)
            document["reactions"] = {
                name: {"final": float(self[name][-1]), "max_abs": float(np.max(np.abs(self[name])))}
                for name in self.reactions
            }
        document["method"] = attrs.get("method")
        for key in ("backend", "choice"):  # which code ran and why (integrate.choice)
            if key in attrs:
                document[key] = str(attrs[key])
        for key in ("rtol", "atol", "dt"):
            if key in attrs:
                document[key] = float(attrs[key])
        document["steps"] = int(attrs.get("steps", 0))
        document["wall_time"] = float(attrs.get("wall_time", 0.0))
        # CPU seconds the run spent making (or loading) its compiled code, and what it made
        # (integrate.simulate): every run of simulate has them, a trajectory built by hand not
        if "compile_time" in attrs:
            document["compile_time"] = float(attrs["compile_time"])
        if "compiled" in attrs:
            document["compiled"] = str(attrs["compiled"])
        document["status"] = self.status
        document["events"] = {name: r.times.tolist() for name, r in self.events.items()}
        if self.contacts:  # additive: a model with contacts (issue 34)
            document["impacts"] = [
                {"t": r.t, "contact": r.contact, "energy_before": r.energy_before,
                 "energy_after": r.energy_after}
                for r in self.impacts
            ]  # fmt: skip
            holds = json.loads(str(attrs.get("holds", "[]")))
            document["held_contacts"] = [
                {"contact": name, "t_from": start, "t_to": end} for name, start, end in holds
            ]
        return document

    # -- pictures: plot, animate and _repr_html_ are added by lagrangian.facade, above
    # output/ (this layer is below the printers)

    # -- files --------------------------------------------------------------------
    def columns(self) -> list[str]:
        """The CSV columns after ``t``: q..., q_dot..., energy, invariants, multipliers,
        joint reactions."""
        return [
            *self.coordinates,
            *self.velocities,
            "energy",
            *self.invariants,
            *self.multipliers,
            *self.reactions,
        ]

    def to_csv(self, path: str | os.PathLike) -> Path:
        """Write the time series as CSV (full float precision), atomically; a column with
        a unit (a dimensioned model's) is headed ``name [unit]``: ``theta [rad]``."""
        names = self.columns()
        table = np.column_stack([self.t, *(self[name] for name in names)])
        headers = []
        for name in ["t", *names]:
            unit = self._data[name].attrs.get("units")
            headers.append(f"{name} [{unit}]" if unit else name)
        return write_csv(path, table, headers)

    def to_netcdf(self, path: str | os.PathLike) -> Path:
        """Write the dataset as netCDF-3 (``engine="scipy"``), atomically."""
        dataset = self.dataset
        return write_atomically(path, lambda target: dataset.to_netcdf(target, engine="scipy"))

    def save(self, path: str | os.PathLike) -> Path:
        """``to_csv`` or ``to_netcdf`` by the suffix of ``path`` (.csv, .nc)."""
        return _by_suffix(path, {".csv": self.to_csv, ".nc": self.to_netcdf})(path)

    @classmethod
    def load(cls, path: str | os.PathLike) -> Trajectory:
        """A trajectory read from a .csv or .nc file written by this class.

        A file that is not one (another program's, damaged, empty, too large, a
        folder) is a :class:`~lagrangian.errors.FileError` naming it and what is wrong.
        """
        return cls(_by_suffix(path, {".csv": read_csv, ".nc": read_netcdf})(path))


def _impact_variables(impacts: Sequence[ImpactRecord], contacts: str) -> dict[str, object]:
    """The data variables of the impacts along their dimension ``impact`` (none if empty:
    netCDF-3 has no empty dimensions, and the ``contacts`` attribute says there were some)."""
    if not impacts:
        return {}
    index = {name: i for i, name in enumerate(name_list(contacts))}
    return {
        "impact__t": ("impact", np.array([r.t for r in impacts], dtype=float)),
        "impact__contact": (
            "impact",
            np.array([index[r.contact] for r in impacts], dtype=np.int32),
        ),
        "impact__velocities_before": (
            ("velocity", "impact"),
            np.stack([r.velocities_before for r in impacts], axis=-1),
        ),
        "impact__velocities_after": (
            ("velocity", "impact"),
            np.stack([r.velocities_after for r in impacts], axis=-1),
        ),
        "impact__energy_before": ("impact", np.array([r.energy_before for r in impacts])),
        "impact__energy_after": ("impact", np.array([r.energy_after for r in impacts])),
    }


def _by_suffix(path: str | os.PathLike, table: Mapping[str, Callable]) -> Callable:
    suffix = Path(path).suffix.lower()
    if suffix not in table:
        known = ", ".join(table)
        raise ModelError(f"unknown trajectory file type '{suffix or path}' (use {known})")
    return table[suffix]


def _netcdf_attrs(attrs: Mapping[str, object]) -> dict[str, object]:
    """Attributes netCDF-3 can hold: numbers and text; mappings become JSON; None is left out."""
    result: dict[str, object] = {}
    for key, value in attrs.items():
        if value is None:
            continue
        if isinstance(value, Mapping):
            result[key] = json.dumps({k: float(v) for k, v in value.items()}, sort_keys=True)
        elif isinstance(value, bool | np.bool_ | int | np.integer):
            result[key] = int(value)
        elif isinstance(value, float | np.floating):
            result[key] = float(value)
        else:
            result[key] = str(value)
    return result

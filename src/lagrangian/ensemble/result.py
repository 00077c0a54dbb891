"""`EnsembleTrajectory`: the outcome of many runs, an xarray Dataset.

Dimensions: ``member`` (a list of members) or the grid's dimensions
(``theta1`` x ``theta2``), plus ``t`` for the optional subsampled paths.
Variables: the observables (``flip_time``, ``energy_drift``, ``final_theta1``,
...) and ``path_<name>`` when paths were saved; coordinates: the initial
values and parameters that vary.  Attributes: model, method, dt, t_end,
backend, members, steps, wall_time (s, JIT compilation and cluster start-up
included), trajectory_steps_per_second (members x steps / wall_time: steps
that members stopped early skipped count too), observables (comma-separated).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import FileError
from ..files import check_input_file, write_atomically

#: Largest ensemble file read (bytes): the whole dataset is held in memory.
MAX_ENSEMBLE_BYTES = 4 << 30


@dataclass(frozen=True, eq=False)
class EnsembleTrajectory:
    """Final states, observables and optional paths of every member (see the module)."""

    dataset: xr.Dataset

    @property
    def dims(self) -> tuple[str, ...]:
        """The member dimensions (``("member",)`` or the grid's)."""
        for variable in self.dataset.data_vars.values():
            return tuple(str(d) for d in variable.dims if d != "t")
        return tuple(str(d) for d in self.dataset.sizes if d != "t")

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(self.dataset.sizes[d] for d in self.dims)

    @property
    def observables(self) -> tuple[str, ...]:
        text = str(self.dataset.attrs.get("observables", ""))
        return tuple(name for name in text.split(",") if name)

    @property
    def attrs(self) -> dict[str, object]:
        return dict(self.dataset.attrs)

    @property
    def final_state(self) -> dict[str, np.ndarray]:
        """``{name: values}`` of the state at t_end (when ``final_state`` was asked for)."""
        return {
            str(name)[len("final_") :]: self.dataset[name].values
            for name in self.dataset.data_vars
            if str(name).startswith("final_")
        }

    def __getitem__(self, name: str) -> np.ndarray:
        return self.dataset[name].values

    def to_netcdf(self, path: str | os.PathLike) -> Path:
        """Write the dataset to ``path`` (.nc) atomically."""
        return write_atomically(path, lambda target: self.dataset.to_netcdf(target))

    @classmethod
    def load(cls, path: str | os.PathLike) -> EnsembleTrajectory:
        """An ensemble read from a .nc file written by :meth:`to_netcdf`; a file that is
        not one (missing, empty, damaged, another program's) is a FileError naming it."""
        check_input_file(path, what="an ensemble file", max_bytes=MAX_ENSEMBLE_BYTES)
        try:
            with xr.open_dataset(path) as dataset:
                dataset = dataset.load()
        except Exception as error:  # the engines' many kinds of "damaged"
            first = (str(error).strip().splitlines() or [type(error).__name__])[0][:100]
            raise FileError(path, f"is not a readable netCDF file ({first})") from None
        if "observables" not in dataset.attrs or "members" not in dataset.attrs:
            raise FileError(path, "holds no ensemble of lagrangian (another program's data?)")
        return cls(dataset)

    def __repr__(self) -> str:
        attrs = self.dataset.attrs
        shape = " x ".join(f"{d}={s}" for d, s in zip(self.dims, self.shape, strict=True))
        return (
            f"EnsembleTrajectory({attrs.get('model', '')}: {shape}, {attrs.get('method')} "
            f"dt={attrs.get('dt')}, backend={attrs.get('backend')}, "
            f"observables={', '.join(self.observables)})"
        )

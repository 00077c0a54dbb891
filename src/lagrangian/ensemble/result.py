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

from ..files import write_atomically


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
        with xr.open_dataset(path) as dataset:
            return cls(dataset.load())

    def __repr__(self) -> str:
        attrs = self.dataset.attrs
        shape = " x ".join(f"{d}={s}" for d, s in zip(self.dims, self.shape, strict=True))
        return (
            f"EnsembleTrajectory({attrs.get('model', '')}: {shape}, {attrs.get('method')} "
            f"dt={attrs.get('dt')}, backend={attrs.get('backend')}, "
            f"observables={', '.join(self.observables)})"
        )

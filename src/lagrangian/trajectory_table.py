"""The arrays of a :class:`~lagrangian.trajectory.Trajectory` before they become a Dataset.

``Trajectory.build`` keeps its arrays in a :class:`Table` and makes the
:class:`xarray.Dataset` only when ``Trajectory.dataset`` is first read.  The first Dataset
of a process costs about 1 s of CPU: xarray imports pandas, and its duck-array checks import
dask.array and pint.  ``simulate --json`` reads only a few arrays and attributes, which the
table answers with the names a Dataset has (``attrs``, ``name in``, ``[name].values``,
``[name].attrs``, ``.transpose``), so the trajectory reads either the same way.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import xarray


class Column:
    """One variable of a :class:`Table`: ``values`` along ``dims``, its own ``attrs``."""

    def __init__(self, dims: tuple[str, ...], values: np.ndarray, attrs: dict) -> None:
        self.dims = dims
        self.values = values
        self.attrs = attrs

    @property
    def shape(self) -> tuple[int, ...]:
        return self.values.shape

    def transpose(self, *dims: str) -> Column:
        order = [self.dims.index(d) for d in dims]
        return Column(tuple(dims), np.transpose(self.values, order), self.attrs)


class Table:
    """What ``xarray.Dataset(data_vars, coords=coords, attrs=attrs)`` would hold, and the
    per-variable ``units`` (name -> unit), until :meth:`to_dataset` makes that Dataset."""

    def __init__(
        self,
        data_vars: Mapping[str, tuple],
        coords: Mapping[str, object],
        attrs: dict[str, object],
        units: Mapping[str, str] | None = None,
    ) -> None:
        self._data_vars = dict(data_vars)
        self._coords = dict(coords)
        self._units = dict(units or {})
        self.attrs = attrs  # read and added to (integrate.simulate) before the Dataset exists
        self._columns: dict[str, Column] = {}
        for name, values in self._coords.items():
            self._add(name, (name,), values)
        for name, (dims, values) in self._data_vars.items():
            self._add(name, (dims,) if isinstance(dims, str) else tuple(dims), values)
        self._check_sizes()

    def _add(self, name: str, dims: tuple[str, ...], values: object) -> None:
        attrs = {"units": self._units[name]} if name in self._units else {}
        self._columns[name] = Column(dims, np.asarray(values), attrs)

    def _check_sizes(self) -> None:
        """The ValueError xarray raises: a dimension with two lengths, or a variable whose
        number of axes is not its number of dimensions."""
        sizes: dict[str, int] = {}
        for name, column in self._columns.items():
            if column.values.ndim != len(column.dims):
                raise ValueError(
                    f"'{name}' has {column.values.ndim} axes but dimensions {column.dims}"
                )
            for dim, size in zip(column.dims, column.values.shape, strict=True):
                if sizes.setdefault(dim, size) != size:
                    raise ValueError(
                        f"conflicting sizes for dimension '{dim}': {sizes[dim]} and {size} "
                        f"('{name}')"
                    )

    def __contains__(self, name: object) -> bool:
        return name in self._columns

    def __getitem__(self, name: str) -> Column:
        return self._columns[name]

    def to_dataset(self) -> xarray.Dataset:
        import xarray as xr

        dataset = xr.Dataset(self._data_vars, coords=self._coords, attrs=self.attrs)
        for name, unit in self._units.items():  # CF conventions: units on each variable
            dataset[name].attrs["units"] = unit
        return dataset

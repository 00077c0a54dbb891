"""Reading trajectory files (.csv, .nc) back, refusing what is not one with one line.

A file given to ``plot`` may be anything: empty, damaged, another program's
netCDF, a spreadsheet with a column missing or a cell that is not a number.
Each of these is a :class:`~lagrangian.errors.FileError` naming the file and
what is wrong, checked before anything draws, so that no plot is made from a
file that was not read completely, and no library error leaks out.

The checks follow the layout of :mod:`lagrangian.trajectory`: a time ``t``
(finite, at least one value); every coordinate ``q`` with ``q_dot`` and the
``energy``, as numbers along ``t``; in netCDF also every invariant, multiplier
and event the attributes list.
"""

from __future__ import annotations

import csv
import os
import warnings
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import xarray

from .errors import FileError
from .files import check_input_file

#: Largest trajectory file read (bytes): the whole file is held in memory,
#: a CSV file several times over while it is parsed.
MAX_TRAJECTORY_BYTES = 1 << 30

_NETCDF3_MAGIC = (b"CDF\x01", b"CDF\x02", b"CDF\x05")
_HDF5_MAGIC = b"\x89HDF\r\n\x1a\n"


def name_list(text: str) -> tuple[str, ...]:
    """The names of a comma-separated list attribute (``coordinate_names``, ...)."""
    return tuple(name for name in str(text).split(",") if name)


def read_netcdf(path: str | os.PathLike) -> xarray.Dataset:
    """The dataset of a netCDF-3 file written by :meth:`Trajectory.to_netcdf`, checked."""
    import xarray as xr

    check_input_file(path, what="a trajectory file", max_bytes=MAX_TRAJECTORY_BYTES)
    with open(path, "rb") as stream:
        magic = stream.read(8)
    if magic == _HDF5_MAGIC:
        raise FileError(path, "is netCDF-4 (HDF5); lagrangian writes trajectories as netCDF-3")
    if magic[:4] not in _NETCDF3_MAGIC:
        raise FileError(path, "is not a netCDF file")
    try:
        with xr.open_dataset(path, engine="scipy", mmap=False) as dataset:
            dataset = dataset.load()
    except Exception as error:  # scipy's and xarray's many kinds of "damaged"
        raise FileError(path, f"is a damaged netCDF file ({_first_line(error)})") from None
    _check_netcdf(path, dataset)
    return dataset


def read_csv(path: str | os.PathLike) -> xarray.Dataset:
    """The dataset of a CSV file written by :meth:`Trajectory.to_csv`, checked."""
    import xarray as xr

    check_input_file(path, what="a trajectory file", max_bytes=MAX_TRAJECTORY_BYTES)
    try:
        with open(path, newline="", encoding="utf-8") as stream:
            header, units = _names_and_units(next(csv.reader(stream), []))
            _check_header(path, header)
            table = _table(path, stream, len(header))
    except UnicodeDecodeError:
        raise FileError(path, "is not a text file (not UTF-8)") from None
    except (OSError, csv.Error) as error:
        raise FileError(path, f"cannot read: {_first_line(error)}") from None
    names = header[1:]
    _check_time(path, table[:, 0])
    coordinates = [name for name in names if f"{name}_dot" in names]
    known = {*coordinates, *(f"{q}_dot" for q in coordinates), "energy"}
    extra = [name for name in names if name not in known]
    data_vars = {name: ("t", table[:, i + 1]) for i, name in enumerate(names)}
    attrs = {"coordinate_names": ",".join(coordinates), "invariants": ",".join(extra), "events": ""}
    dataset = xr.Dataset(data_vars, coords={"t": table[:, 0]}, attrs=attrs)
    for name, unit in units.items():
        dataset[name].attrs["units"] = unit
    return dataset


def _names_and_units(cells: list[str]) -> tuple[list[str], dict[str, str]]:
    """The column names of a header and the units some carry (``theta [rad]``)."""
    names, units = [], {}
    for cell in cells:
        name, bracket, unit = cell.strip().partition(" [")
        names.append(name.strip())
        if bracket and unit.endswith("]") and unit[:-1].strip():
            units[name.strip()] = unit[:-1].strip()
    return names, units


# -- CSV -------------------------------------------------------------------------------
def _check_header(path, header: list[str]) -> None:
    if not header or header[0] != "t":
        raise FileError(path, "is not a trajectory CSV file (first column must be t)")
    names = header[1:]
    twice = sorted({name for name in names if names.count(name) > 1})
    if twice or "t" in names:
        raise FileError(path, f"has the column '{(twice or ['t'])[0]}' twice")
    if "energy" not in names:
        raise FileError(path, "has no column 'energy' (columns: t, q..., q_dot..., energy)")
    if not any(f"{name}_dot" in names for name in names):
        raise FileError(path, "has no coordinate columns (a q with its q_dot)")


def _table(path, stream, width: int) -> np.ndarray:
    """The rows after the header as floats; a short row or a word names its place."""
    try:
        with warnings.catch_warnings():  # "input contained no data": said below, once
            warnings.simplefilter("ignore", UserWarning)
            table = np.loadtxt(stream, delimiter=",", ndmin=2, dtype=float)
    except ValueError:
        _locate_bad_cell(path, width)
        raise FileError(path, "has rows that are not numbers") from None  # pragma: no cover
    if table.shape[0] == 0:
        raise FileError(path, "has a header but no rows")
    if table.shape[1] != width:
        raise FileError(path, f"has {table.shape[1]} values per row but {width} column names")
    return table


def _locate_bad_cell(path, width: int) -> None:
    """Raise the FileError of the first row that has the wrong length or a non-number."""
    with open(path, newline="", encoding="utf-8") as stream:
        for number, row in enumerate(csv.reader(stream), start=1):
            if number == 1 or not row:
                continue
            if len(row) != width:
                raise FileError(path, f"line {number} has {len(row)} values, the header {width}")
            for column, cell in enumerate(row, start=1):
                try:
                    float(cell)
                except ValueError:
                    shown = cell if len(cell) <= 20 else cell[:17] + "..."
                    raise FileError(
                        path, f"line {number}, column {column}: '{shown}' is not a number"
                    ) from None


def _check_time(path, t: np.ndarray) -> None:
    if t.size == 0:
        raise FileError(path, "has no times")
    if not np.all(np.isfinite(t)):
        first = int(np.argmin(np.isfinite(t)))
        raise FileError(path, f"has a time t that is not finite ({t[first]} in row {first + 1})")


# -- netCDF ----------------------------------------------------------------------------
def _check_netcdf(path, dataset) -> None:
    """Everything the attributes promise is there, as numbers along t."""
    if "coordinate_names" not in dataset.attrs or "t" not in dataset.variables:
        raise FileError(path, "holds no trajectory of lagrangian (another program's data?)")
    t = dataset["t"]
    if t.dims != ("t",) or not np.issubdtype(t.dtype, np.number):
        raise FileError(path, "has a time t that is not a list of numbers")
    _check_time(path, np.asarray(t.values, dtype=float))
    coordinates = name_list(dataset.attrs.get("coordinate_names", ""))
    if not coordinates:
        raise FileError(path, "lists no coordinates (attribute coordinate_names)")
    attrs = dataset.attrs
    expected = [
        *coordinates,
        *(f"{q}_dot" for q in coordinates),
        "energy",
        *name_list(attrs.get("invariants", "")),
        *name_list(attrs.get("multipliers", "")),
        *name_list(attrs.get("reactions", "")),
    ]
    for name in expected:
        if name not in dataset.data_vars:
            raise FileError(path, f"has no variable '{name}'")
        variable = dataset[name]
        if variable.dims != ("t",) or not np.issubdtype(variable.dtype, np.number):
            raise FileError(path, f"has a variable '{name}' that is not numbers along t")
    for event in name_list(attrs.get("events", "")):
        dim = f"event__{event}"
        if f"{dim}__t" in dataset.data_vars and f"{dim}__y" not in dataset.data_vars:
            raise FileError(path, f"has the times of event '{event}' but not its states")


def _first_line(error: BaseException) -> str:
    text = str(error).strip().splitlines()
    line = text[0] if text else type(error).__name__
    return line if len(line) <= 100 else line[:97] + "..."

"""Measured time series for a fit: read from CSV or NetCDF, checked, converted to SI.

A table has a time column ``t`` and columns named for what was measured: a coordinate or
velocity of the model (``theta``, ``x_dot``) or an observed expression's name
(``x_tip`` of ``observe={"x_tip": "l*sin(theta)"}``).  A CSV file names them in its
header, each optionally with a unit in brackets (``t [ms]``, ``x [cm]``); a NetCDF file
is an xarray Dataset with the time as its coordinate (``t`` or ``time``) and the columns
as variables along it, a unit in a variable's ``units`` attribute.

This is an edge of the package, as the model file is: a column with a unit is converted
here to the SI units the model computes in (a model with ``[units]``; a unit is refused
where it has a different dimension, or where the model has no units, since its numbers'
units are then unknown), and nothing below sees a unit.  A column without a unit is in
the unit the model declares for the name (``[units] theta = "deg"``), as a bare number
given on the command line is; an observed expression's, in SI.

Problems are :class:`~lagrangian.errors.FileError` lines naming the file and the row (a
CSV row counts the header as row 1, as a spreadsheet shows it) or the column: an empty
file, a missing or unexpected column, a cell that is not a number, times that do not
increase or are before 0 (the model's initial values are at t = 0).  A row with an empty
or NaN cell is dropped, and :attr:`Measurements.dropped` lists it so that the fit can
say how many (a measurement that failed is common; refusing the file would make the user
edit it by hand).
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .errors import FileError, ModelError, setting
from .symbols import TIME_NAME

if TYPE_CHECKING:
    import sympy

    from .model import System

_HEADER = re.compile(r"\s*([^\[\]]*?)\s*(?:\[([^\[\]]*)\])?\s*")
_MISSING = {"", "nan", "NaN", "NAN"}
_NETCDF = (".nc", ".nc4", ".netcdf")


@dataclass(frozen=True)
class Measurements:
    """A checked time series: ``times`` (m,) increasing from 0 on, ``columns`` name ->
    values (m,) in the model's SI units, ``units`` name -> the unit the source gave (None:
    the model's own), ``dropped`` the rows left out for a missing value (CSV rows: the
    header is row 1; other data: their 0-based ``index``, as ``place`` says), ``source``
    the file (or ``<data>``)."""

    source: str
    times: np.ndarray
    columns: Mapping[str, np.ndarray]
    units: Mapping[str, str | None]
    dropped: tuple[int, ...] = ()
    place: str = "row"


def read_measurements(
    data: object,
    system: System,
    observed: Mapping[str, sympy.Expr] | None = None,
) -> Measurements:
    """``data`` (a CSV or NetCDF path, an xarray Dataset, a pandas DataFrame or a mapping
    of column name -> values) checked against ``system`` and the names of ``observed``
    (name -> its expression, for the dimension of a column with a unit)."""
    observed = dict(observed or {})
    if isinstance(data, str | Path):
        path = Path(data)
        source = str(data)
        if not path.is_file():
            raise FileError(source, "no such file")
        if path.suffix.lower() in _NETCDF:
            names, rows, numbers = _netcdf_table(path)
        else:
            names, rows, numbers = _csv_table(path)
    else:
        source = "<data>"
        names, rows, numbers = _mapping_table(data)
    csv_file = isinstance(data, str | Path) and Path(data).suffix.lower() not in _NETCDF
    place = "row" if csv_file else "index"
    return _checked(source, names, rows, numbers, system, observed, place)


def _csv_table(path: Path) -> tuple[list[str], list[int], np.ndarray]:
    source = str(path)
    try:
        with path.open(newline="", encoding="utf-8-sig") as handle:
            lines = list(csv.reader(handle))
    except (OSError, UnicodeDecodeError, csv.Error) as error:
        raise FileError(source, f"cannot be read as CSV: {error}") from None
    numbered = [(i, line) for i, line in enumerate(lines, 1) if any(c.strip() for c in line)]
    if not numbered:
        raise FileError(source, "the file is empty (expected a header such as 't,x')")
    (_, header), body = numbered[0], numbered[1:]
    if not body:
        raise FileError(source, "no data rows after the header")
    numbers = np.empty((len(body), len(header)))
    for k, (row, line) in enumerate(body):
        if len(line) != len(header):
            raise FileError(source, f"row {row} has {len(line)} cells, the header {len(header)}")
        for j, cell in enumerate(line):
            numbers[k, j] = _number(cell, source, row, header[j])
    return header, [row for row, _ in body], numbers


def _number(cell: str, source: str, row: int, column: str) -> float:
    text = cell.strip()
    if text in _MISSING:
        return math.nan
    try:
        value = float(text)
    except ValueError:
        shown = text if len(text) <= 30 else text[:27] + "..."
        raise FileError(
            source, f"row {row}, column '{column.strip()}': {shown!r} is not a number"
        ) from None
    if math.isinf(value):
        raise FileError(source, f"row {row}, column '{column.strip()}': {text} is not finite")
    return value


def _netcdf_table(path: Path) -> tuple[list[str], list[int], np.ndarray]:
    import xarray as xr

    try:
        with xr.open_dataset(path) as dataset:
            return _dataset_table(dataset.load(), str(path))
    except FileError:
        raise
    except Exception as error:  # netCDF4/h5netcdf/scipy each fail their own way
        raise FileError(str(path), f"cannot be read as NetCDF: {error}") from None


def _dataset_table(dataset, source: str) -> tuple[list[str], list[int], np.ndarray]:
    """An xarray Dataset's time coordinate and the variables along it."""
    time = next((name for name in (TIME_NAME, "time") if name in dataset.coords), None)
    if time is None:
        known = ", ".join(map(str, dataset.coords)) or "none"
        raise FileError(source, f"no time coordinate 't' or 'time' (coordinates: {known})")
    names, columns = [_with_unit(TIME_NAME, dataset[time])], [dataset[time].values]
    for name, variable in dataset.data_vars.items():
        if variable.dims != (time,):
            raise FileError(
                source, f"variable '{name}' is along {variable.dims}, not the time '{time}'"
            )
        names.append(_with_unit(str(name), variable))
        columns.append(variable.values)
    try:
        numbers = np.column_stack([np.asarray(c, dtype=float) for c in columns])
    except (TypeError, ValueError):
        raise FileError(source, "a variable is not numeric") from None
    return names, list(range(len(numbers))), numbers


def _with_unit(name: str, variable) -> str:
    unit = variable.attrs.get("units")
    return f"{name} [{unit}]" if isinstance(unit, str) and unit.strip() else name


def _mapping_table(data: object) -> tuple[list[str], list[int], np.ndarray]:
    if hasattr(data, "data_vars"):  # an xarray Dataset
        return _dataset_table(data, "<data>")
    items = list(data.items()) if hasattr(data, "items") else None
    if items is None:
        raise ModelError(
            "the data is a CSV or NetCDF path, an xarray Dataset, a pandas DataFrame or "
            f"a mapping of column name -> values, not {type(data).__name__}"
        )
    names = [str(name) for name, _ in items]
    try:
        columns = [np.asarray(values, dtype=float).ravel() for _, values in items]
    except (TypeError, ValueError):
        raise FileError("<data>", "a column is not numeric") from None
    if len({c.size for c in columns}) > 1:
        sizes = ", ".join(f"{n}: {c.size}" for n, c in zip(names, columns, strict=True))
        raise FileError("<data>", f"the columns differ in length ({sizes})")
    numbers = np.column_stack(columns) if columns else np.empty((0, 0))
    return names, list(range(len(numbers))), numbers


def _checked(
    source: str,
    header: Sequence[str],
    rows: Sequence[int],
    numbers: np.ndarray,
    system: System,
    observed: Mapping[str, sympy.Expr],
    place: str,
) -> Measurements:
    names, units = _header(source, header)
    coordinates = system.coordinate_names
    states = (*coordinates, *(f"{q}_dot" for q in coordinates))
    if TIME_NAME not in names:
        raise FileError(source, f"no column 't' (the columns there: {', '.join(names)})")
    for name in observed:
        if name not in names:
            there = ", ".join(names)
            raise FileError(
                source, f"no column '{name}' to compare with (the columns there: {there})"
            )
    for name in names:
        if name != TIME_NAME and name not in states and name not in observed:
            raise FileError(
                source,
                f"column '{name}' is neither a coordinate or velocity of the model "
                f"({', '.join(states)}) nor an observed expression "
                f"(name it with {setting('observe=')}, or leave the column out)",
            )
    if len(names) < 2:
        raise FileError(source, "no measured column besides 't'")
    if numbers.shape[0] == 0:
        raise FileError(source, "no data rows")
    missing = ~np.all(np.isfinite(numbers), axis=1)
    dropped = tuple(row for row, gone in zip(rows, missing, strict=True) if gone)
    numbers, rows = (
        numbers[~missing],
        [row for row, gone in zip(rows, missing, strict=True) if not gone],
    )
    if numbers.shape[0] == 0:
        raise FileError(source, "every row has a missing value (empty or NaN)")
    factors = _factors(source, names, units, system, observed)
    numbers = numbers * np.array([factors[name] for name in names])
    times = numbers[:, names.index(TIME_NAME)]
    _check_times(source, times, rows, place)
    columns = {n: numbers[:, j].copy() for j, n in enumerate(names) if n != TIME_NAME}
    return Measurements(source, times.copy(), columns, dict(units), dropped, place)


def _header(source: str, header: Sequence[str]) -> tuple[list[str], dict[str, str | None]]:
    names, units = [], {}
    for position, cell in enumerate(header, 1):
        match = _HEADER.fullmatch(cell)
        name = match[1] if match else ""
        if not name or not match:
            raise FileError(
                source,
                f"column {position} of the header, {cell.strip()!r}, is not 'NAME' or "
                "'NAME [unit]'",
            )
        if name in units:
            raise FileError(source, f"column '{name}' appears twice in the header")
        names.append(name)
        unit = match[2].strip() if match[2] is not None else None
        units[name] = unit or None
    return names, units


def _factors(
    source: str,
    names: Iterable[str],
    units: Mapping[str, str | None],
    system: System,
    observed: Mapping[str, sympy.Expr],
) -> dict[str, float]:
    """name -> the factor that takes the column to the model's SI units."""
    factors = {}
    for name in names:
        try:
            factors[name] = _factor(name, units.get(name), system, observed)
        except ModelError as error:
            raise FileError(source, str(error)) from None
    return factors


def _factor(
    name: str, text: str | None, system: System, observed: Mapping[str, sympy.Expr]
) -> float:
    """The factor to SI of a column ``name`` given in the unit ``text``: None is the unit the
    model declares for the name (SI for an observed expression, or without units)."""
    from .model.dimensions import describe, dimension_of
    from .model.quantities import read_unit

    units = system.units
    if text is None:
        return 1.0 if units is None or name in observed else units.bare(name, 1.0)
    if units is None:
        raise ModelError(
            f"column '{name} [{text}]' has a unit but the model has none, so its numbers' "
            f"units are unknown: give the model a [units] table, or drop the unit"
        )
    unit = read_unit(text, f"column '{name}'")
    if name in observed:
        expected = dimension_of(observed[name], units.symbols(system))
        what = "" if expected is None else describe(expected)
    else:
        expected, what = units.dimension(name), units.describe(name)
    if expected is not None and unit.dimension != expected:
        raise ModelError(
            f"column '{name} [{text}]': {name} is {what}, but {text} is {describe(unit.dimension)}"
        )
    return unit.factor


def noise_levels(
    noise: object,
    columns: Sequence[str],
    system: System,
    observed: Mapping[str, sympy.Expr] | None = None,
) -> np.ndarray | None:
    """Each column's noise sigma in SI (None without ``noise``): one value for every column
    or a mapping column -> value; a value is a positive number (in the unit the model
    declares for the column, as a bare data column is) or text with a unit (``"0.3 deg"``,
    checked against the column's dimension).  With no ``columns``, only the values are
    checked (before the data are read)."""
    from .model.quantities import has_unit, read_quantity

    if noise is None:
        return None
    field = setting("noise")
    given = dict(noise) if isinstance(noise, Mapping) else dict.fromkeys(columns or ["*"], noise)
    texts = {}
    for name, value in given.items():
        text = value.strip() if isinstance(value, str) else None
        try:
            number = (
                read_quantity(text, f"{field} {name}").number
                if text is not None and has_unit(text)
                else float(value)
            )
        except ModelError:  # a unit that is not one: its own message
            raise
        except (TypeError, ValueError):
            number = math.nan
        if not (math.isfinite(number) and number > 0):
            raise ModelError(
                f"the noise level must be a positive number, not {value!r}", field=field
            )
        texts[name] = text if text is not None and has_unit(text) else None
    if not columns:
        return None
    unknown = [name for name in given if name not in columns]
    if unknown and isinstance(noise, Mapping):
        known = ", ".join(columns)
        raise ModelError(f"'{unknown[0]}' is not a measured column ({known})", field=field)
    observed = observed or {}
    sigma = []
    for name in columns:
        if name not in given:
            raise ModelError(f"no noise level for the column '{name}'", field=field)
        text = texts[name]
        try:
            if text is None:
                sigma.append(float(given[name]) * _factor(name, None, system, observed))
            else:
                quantity = read_quantity(text, f"{field} {name}")
                factor = _factor(name, quantity.unit.text, system, observed)
                sigma.append(float(quantity.number) * factor)
        except ModelError as error:
            raise ModelError(f"the noise of {error}", field=field) from None
    return np.array(sigma)


def _check_times(source: str, times: np.ndarray, rows: Sequence[int], place: str) -> None:
    if times[0] < 0:
        raise FileError(
            source,
            f"{place} {rows[0]}: t = {times[0]:g} is before 0, where the model's initial "
            "values are",
        )
    steps = np.diff(times)
    if steps.size and not np.all(steps > 0):
        k = int(np.argmax(~(steps > 0))) + 1
        raise FileError(
            source,
            f"{place} {rows[k]}: t = {times[k]:g} is not after t = {times[k - 1]:g} of {place} "
            f"{rows[k - 1]} (times must increase)",
        )

"""Sensitivities shown and written: a summary (text, JSON), a picture, CSV and NetCDF.

The values are d state(t) / d w (see :mod:`lagrangian.integrate.sensitivity`): for a
parameter w in the state's units per unit of w, for an initial value (a coordinate
or velocity named in ``wrt``) a pure ratio that starts at 1 on its own state.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..files import write_atomically, write_csv
from ..integrate.sensitivity import Sensitivities
from ..model.dimensions import over, unit_text
from .plots import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: The files :func:`write_sensitivities` writes, by suffix.
SENSITIVITY_FORMATS = (".nc", ".csv")


def shown(result: Sensitivities, wrt: str) -> str:
    """``wrt`` as shown: a parameter ``k`` as itself, an initial value as ``x(0)``."""
    return f"{wrt}(0)" if wrt in result.state_names else wrt


def column_name(result: Sensitivities, state: str, wrt: str) -> str:
    """The CSV column of d state / d wrt: ``d(x)/d(k)``, ``d(x)/d(x(0))``."""
    return f"d({state})/d({shown(result, wrt)})"


def state_unit(system, state: str) -> str | None:
    """The SI unit of a state (``m``, ``rad/s``) of a dimensioned ``system``, else None."""
    units = getattr(system, "units", None)
    return None if units is None else units.column_unit(state)


def sensitivity_unit(system, state: str, wrt: str) -> str | None:
    """The SI unit of d state / d wrt for a dimensioned ``system``: the quotient's, in base
    units (d(x)/d(k), m per N/m: ``s^2/kg``; a ratio of like things: ``1``), else None."""
    units = getattr(system, "units", None)
    if units is None:
        return None
    top, bottom = units.dimension(state), units.dimension(wrt)
    return None if top is None or bottom is None else unit_text(over(top, bottom))


def _units_section(result: Sensitivities, system) -> dict[str, object]:
    """JSON's ``units`` of a dimensioned model's sensitivities; empty without units."""
    if getattr(system, "units", None) is None:
        return {}
    states = {state: state_unit(system, state) for state in result.state_names}
    per = {s: {w: sensitivity_unit(system, s, w) for w in result.wrt} for s in result.state_names}
    return {"units": {"t": "s", "states": states, "sensitivities": per}}


def sensitivity_summary(result: Sensitivities, system=None) -> dict[str, object]:
    """The JSON form: the names, the settings, the state and each sensitivity at t_end and
    its largest size over the run ({state: {wrt: value}}), and for a dimensioned
    ``system`` their SI ``units``."""
    final, largest = {}, {}
    for j, state in enumerate(result.state_names):
        final[state] = {w: float(result.values[-1, j, k]) for k, w in enumerate(result.wrt)}
        sizes = np.max(np.abs(result.values[:, j, :]), axis=0)
        largest[state] = {w: float(sizes[k]) for k, w in enumerate(result.wrt)}
    return {
        "model": result.name,
        "wrt": list(result.wrt),
        "states": list(result.state_names),
        **result.settings(),
        "points": len(result.times),
        "final": final,
        "largest": largest,
        "initial": dict(result.initial),
        "parameters": dict(result.parameters),
    } | _units_section(result, system)


def sensitivity_text(result: Sensitivities, system=None) -> str:
    """Lines for a terminal: d state(t_end) / d w, one state a row, one w a column (the
    time in s for a dimensioned ``system``: JSON and the files give each one's unit)."""
    t_end = float(result.times[-1])
    width = max(12, *(len(shown(result, w)) + 2 for w in result.wrt))
    seconds = " s" if getattr(system, "units", None) is not None else ""
    lines = [f"{result.name}: d state(t) / d w at t = {t_end:g}{seconds}"]
    lines.append(" " * 12 + "".join(f"{shown(result, w):>{width}}" for w in result.wrt))
    for j, state in enumerate(result.state_names):
        row = "".join(f"{value:>{width}.6g}" for value in result.values[-1, j])
        lines.append(f"{state:>12}{row}")
    lines.append(
        f"dop853 rtol={result.rtol:g} atol={result.atol:g}, {len(result.times)} output times"
    )
    return "\n".join(lines)


def plot_sensitivities(result: Sensitivities, system=None) -> Figure:
    """d q(t) / d w against t (in s for a dimensioned ``system``): one panel per
    coordinate q, one line per w."""
    coordinates = result.state_names[: len(result.state_names) // 2]
    figure, axes = new_figure(len(coordinates), sharex=True)
    for row, state in enumerate(coordinates):
        axis = axes[row, 0]
        for w in result.wrt:
            axis.plot(result.times, result.of(state, w), label=f"d{state}/d{shown(result, w)}")
        axis.axhline(0.0, color="0.5", lw=0.8)
        axis.set_ylabel(f"d{state} / d w")
        axis.grid(True, alpha=0.3)
        axis.legend(loc="upper left", fontsize=8, ncols=min(4, len(result.wrt)))
    axes[-1, 0].set_xlabel("$t$" + (" [s]" if getattr(system, "units", None) is not None else ""))
    axes[0, 0].set_title(
        f"{result.name}: sensitivities to {', '.join(shown(result, w) for w in result.wrt)}"
    )
    return figure


def write_sensitivities(result: Sensitivities, path: str | os.PathLike, system=None) -> Path:
    """``path`` (.nc: :meth:`~Sensitivities.to_dataset`; .csv: columns t, the states, then
    ``d(state)/d(w)`` for each state and w), written atomically.  For a dimensioned
    ``system`` a CSV column says its SI unit (``t [s]``, ``d(x)/d(k) [s^2/kg]``); netCDF's
    ``time`` has ``units``, ``y`` its ``state_units`` (one per state) and ``sensitivity``
    its ``units_by_state_and_wrt`` (state by state, w by w): one variable holds several."""
    suffix = Path(path).suffix.lower()
    dimensioned = getattr(system, "units", None) is not None
    if suffix == ".nc":
        dataset = result.to_dataset()
        if dimensioned:
            dataset["time"].attrs["units"] = "s"
            states = [state_unit(system, s) or "" for s in result.state_names]
            dataset["y"].attrs["state_units"] = ",".join(states)
            quotients = [
                sensitivity_unit(system, s, w) or "" for s in result.state_names for w in result.wrt
            ]
            dataset["sensitivity"].attrs["units_by_state_and_wrt"] = ",".join(quotients)
        return write_atomically(path, lambda target: dataset.to_netcdf(target, engine="scipy"))
    if suffix == ".csv":
        columns = ["t", *result.state_names]
        columns += [column_name(result, s, w) for s in result.state_names for w in result.wrt]
        if dimensioned:
            units = ["s", *(state_unit(system, s) for s in result.state_names)]
            units += [
                sensitivity_unit(system, s, w) for s in result.state_names for w in result.wrt
            ]
            columns = [f"{c} [{u}]" if u else c for c, u in zip(columns, units, strict=True)]
        table = np.column_stack(
            (result.times, result.states, result.values.reshape(len(result.times), -1))
        )
        return write_csv(path, table, columns)
    raise ModelError(f"cannot write sensitivities to '{suffix or path}' files (use .nc or .csv)")

"""A fit shown: its table (text), its JSON summary, and the picture of data, fit and
residuals (see :mod:`lagrangian.integrate.fit` for what the numbers are).

For a dimensioned model the values, standard errors, times and columns are in SI units
(the data were converted when read), and the text and plots say which.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..integrate.fit_result import FitResult
from .plots import new_figure
from .units import bracketed, name_unit

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def _number(value: float) -> float | None:
    """A JSON number, or null for what is not one (an undetermined standard error)."""
    return float(value) if math.isfinite(value) else None


def shown(result: FitResult, name: str) -> str:
    """A fitted name as shown: an initial value as ``theta(0)``."""
    return f"{name}(0)" if name in result.state_names else name


def fit_summary(result: FitResult, system=None) -> dict[str, object]:
    """The JSON form: ``parameters`` {name: {value, stderr}} (stderr null where the data do
    not determine it), ``correlation`` {name: {name: value}}, ``rms``, ``chi2_per_dof``
    (null without a noise level), ``dof``, ``warnings``, ``starts``, ``converged``,
    ``iterations``, ``evaluations``, the ``columns`` fitted and the ``samples``; for a
    dimensioned ``system`` the SI ``units`` of the fitted names."""
    parameters = {
        name: {"value": float(value), "stderr": _number(error)}
        for name, value, error in zip(result.names, result.values, result.stderr, strict=True)
    }
    correlation = {
        a: {b: _number(result.correlation[i, j]) for j, b in enumerate(result.names)}
        for i, a in enumerate(result.names)
    }
    document = {
        "model": result.name,
        "data": result.source,
        "parameters": parameters,
        "correlation": correlation,
        "rms": float(result.rms),
        "chi2_per_dof": None if result.chi2_per_dof is None else float(result.chi2_per_dof),
        "dof": result.dof,
        "warnings": list(result.warnings),
        "starts": result.starts,
        "converged": result.converged,
        "iterations": result.iterations,
        "evaluations": result.evaluations,
        "columns": list(result.observed),
        "samples": int(result.times.shape[0]),
    }
    if getattr(system, "units", None) is not None:
        document["units"] = {name: name_unit(system, name) for name in result.names}
    return document


def fit_text(result: FitResult, system=None) -> str:
    """Lines for a terminal: value ± standard error and relative error per fitted name,
    the correlation matrix, rms, chi^2 per degree of freedom, the starts, the warnings."""
    width = max(8, *(len(shown(result, n)) for n in result.names))
    lines = [f"{result.name or 'model'} fitted to {result.source or 'the data'} "
             f"({result.times.shape[0]} times, columns {', '.join(result.observed)})"]  # fmt: skip
    lines.append(f"{'':<{width}}  {'value':>14}  {'stderr':>12}  {'relative':>9}")
    for name, value, error in zip(result.names, result.values, result.stderr, strict=True):
        unit = name_unit(system, name) if getattr(system, "units", None) is not None else None
        relative = f"{abs(error / value):9.2%}" if value != 0 and math.isfinite(error) else " " * 9
        error_text = f"{error:12.4g}" if math.isfinite(error) else f"{'undetermined':>12}"
        lines.append(
            f"{shown(result, name):<{width}}  {value:14.8g}  {error_text}  {relative}"
            + bracketed(unit)
        )
    if len(result.names) > 1:
        lines.append("correlation:")
        lines.append(
            f"{'':<{width}}" + "".join(f"  {shown(result, n):>{width}}" for n in result.names)
        )
        for i, name in enumerate(result.names):
            row = "".join(f"  {value:>{width}.4f}" for value in result.correlation[i])
            lines.append(f"{shown(result, name):<{width}}{row}")
    units = {name_unit(system, c) for c in result.observed} if system is not None else {None}
    shared = bracketed(units.pop()) if len(units) == 1 else ""  # one unit for every column
    lines.append(f"rms of the residuals: {result.rms:.6g}{shared}")
    if result.chi2_per_dof is not None:
        lines.append(f"chi^2 per degree of freedom: {result.chi2_per_dof:.4g} ({result.dof} dof)")
    lines.append(
        f"{result.converged} of {result.starts} start(s) reached this optimum; "
        f"{result.iterations} iterations, {result.evaluations} evaluations"
    )
    lines += [f"warning: {warning}" for warning in result.warnings]
    return "\n".join(lines)


def plot_fit(result: FitResult, system=None, *, residuals: bool = False) -> Figure:
    """Data (points) and fit (line) against t, one panel per measured column; with
    ``residuals`` a panel of data - fit below each."""
    columns = list(result.observed)
    rows = len(columns) * (2 if residuals else 1)
    figure, axes = new_figure(rows, sharex=True)
    dimensioned = getattr(system, "units", None) is not None
    for k, column in enumerate(columns):
        unit = bracketed(name_unit(system, column)) if dimensioned else ""
        axis = axes[k * (2 if residuals else 1), 0]
        axis.plot(result.times, result.observed[column], ".", ms=3, color="0.35", label="data")
        axis.plot(result.times, result.fitted[column], "-", lw=1.4, color="C3", label="fit")
        axis.set_ylabel(f"{column}{unit}")
        axis.grid(True, alpha=0.3)
        axis.legend(loc="upper right", fontsize=8)
        if residuals:
            below = axes[k * 2 + 1, 0]
            below.plot(result.times, result.residuals[column], ".", ms=3, color="C0")
            below.axhline(0.0, color="0.5", lw=0.8)
            below.set_ylabel(f"data - fit{unit}")
            below.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel("$t$" + (" [s]" if dimensioned else ""))
    fitted = ", ".join(
        f"{shown(result, n)} = {v:.5g} ± {e:.1g}"
        for n, v, e in zip(result.names, result.values, result.stderr, strict=True)
    )
    axes[0, 0].set_title(f"{result.name} fitted: {fitted}", fontsize=9, wrap=True)
    return figure

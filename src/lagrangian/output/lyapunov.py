"""Lyapunov exponents shown: a summary (text, JSON) and the convergence of the estimates.

The estimates after time t are the sums of log |R_ii| over the re-orthonormalisations
so far divided by t (see :mod:`lagrangian.integrate.lyapunov`); the plot shows them
against t on a logarithmic time axis, where a converged exponent is a flat line and a
zero one falls like log(t) / t.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..integrate.lyapunov import LyapunovSpectrum
from .plots import new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def _rate_unit(spectrum: LyapunovSpectrum, system) -> str | None:
    """``1/s`` for a dimensioned model (``system``, else the spectrum's own: its times are
    in s), else None."""
    model = system if system is not None else spectrum.system
    return None if getattr(model, "units", None) is None else "1/s"


def lyapunov_summary(spectrum: LyapunovSpectrum, system=None) -> dict[str, object]:
    """The JSON form: exponents (largest first), their sum, the settings and the state;
    ``units`` (``{"exponents": "1/s", "t": "s"}``) for a dimensioned ``system``."""
    unit = _rate_unit(spectrum, system)
    return ({"units": {"exponents": unit, "t": "s"}} if unit else {}) | {
        "model": spectrum.name,
        "exponents": [float(x) for x in spectrum.exponents],
        "sum": float(np.sum(spectrum.exponents)),
        **spectrum.settings(),
        "reorthonormalisations": len(spectrum.times),
        "initial": dict(spectrum.initial),
        "parameters": dict(spectrum.parameters),
    }


def lyapunov_text(spectrum: LyapunovSpectrum, system=None) -> str:
    """Lines for a terminal: one exponent a line, then the sum and the settings (in 1/s
    and s for a dimensioned ``system``)."""
    unit = _rate_unit(spectrum, system)
    seconds = " s" if unit else ""
    count = spectrum.count
    what = "largest Lyapunov exponent" if count == 1 else f"{count} Lyapunov exponents"
    lines = [
        f"{spectrum.name}: {what} over t = {spectrum.t_end:g}{seconds} "
        f"(after a transient of {spectrum.transient:g}{seconds}), {unit or '1 / time unit'}:"
    ]
    lines += [f"  lambda{i} = {value: .6g}" for i, value in enumerate(spectrum.exponents, 1)]
    if count > 1:
        lines.append(f"  sum = {float(np.sum(spectrum.exponents)):.6g}")
    lines.append(
        f"dop853 rtol={spectrum.rtol:g} atol={spectrum.atol:g}, re-orthonormalised every "
        f"{spectrum.interval:g} ({len(spectrum.times)} times)"
    )
    return "\n".join(lines)


def plot_lyapunov(spectrum: LyapunovSpectrum, system=None) -> Figure:
    """The running estimate of each exponent against the averaging time (log scale), in
    1/s against s for a dimensioned ``system``."""
    unit = _rate_unit(spectrum, system)
    figure, axes = new_figure(height=4.4)
    axis = axes[0, 0]
    elapsed = spectrum.times - spectrum.transient
    for i in range(spectrum.count):
        axis.plot(elapsed, spectrum.history[:, i], label=rf"$\lambda_{{{i + 1}}}$")
    axis.axhline(0.0, color="0.5", lw=0.8)
    axis.set_xscale("log")
    axis.set_xlabel("averaging time $t$" + (" [s]" if unit else ""))
    axis.set_ylabel(f"estimate [{unit}]" if unit else "estimate (1 / time unit)")
    axis.grid(True, alpha=0.3)
    axis.legend(loc="upper right", fontsize=8, ncols=2 if spectrum.count > 4 else 1)
    final = ", ".join(f"{x:.3g}" for x in spectrum.exponents)
    axis.set_title(f"{spectrum.name}: Lyapunov exponents ({final})")
    return figure

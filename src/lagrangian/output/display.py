"""Jupyter display of a trajectory: a small HTML summary table (``_repr_html_``).

The animation's display is :class:`lagrangian.output.animation.Animation`.
"""

from __future__ import annotations

import html

from ..trajectory import Trajectory
from .notation import latex_name


def trajectory_html(trajectory: Trajectory) -> str:
    """An HTML table: model, method, status, time span, final state and drifts.

    >>> import numpy as np
    >>> run = Trajectory.build(t=np.array([0.0, 1.0]), coordinates=["x"],
    ...                        y=np.array([[0.0, 1.0], [1.0, 1.0]]), energy=np.ones(2))
    >>> "<table" in trajectory_html(run) and "\\\\dot{x}" in trajectory_html(run)
    True
    """
    attrs = trajectory.dataset.attrs
    t = trajectory.t
    rows: list[tuple[str, str]] = [("model", str(attrs.get("model") or "trajectory"))]
    method = str(attrs.get("method", ""))
    for key in ("dt", "rtol", "atol"):
        if key in attrs:
            method += f", {key} = {float(attrs[key]):g}"
    if method:
        rows.append(("method", method))
    if "status" in attrs:
        rows.append(("status", f"{attrs['status']} ({attrs.get('message', '')})"))
    if t.size:
        rows.append(("time", f"{t[0]:g} to {t[-1]:g}, {t.size} samples"))
    if "steps" in attrs:
        rows.append(("steps", f"{int(attrs['steps'])} in {float(attrs.get('wall_time', 0)):.3g} s"))
    if t.size:
        for name, value in trajectory.final_state.items():
            rows.append((f"${latex_name(name)}(t_{{end}})$", f"{value:.10g}"))
        for name, value in trajectory.drifts().items():
            shown = "energy $h$" if name == "energy" else f"${latex_name(name)}$"
            rows.append((f"drift of {shown}", f"{value:.3e}"))
    body = "\n".join(
        f'<tr><th style="text-align:left">{html.escape(key)}</th>'
        f'<td style="text-align:left">{html.escape(value)}</td></tr>'
        for key, value in rows
    )
    return f'<table class="lagrangian-trajectory">\n{body}\n</table>'

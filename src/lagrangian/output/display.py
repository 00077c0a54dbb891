"""Jupyter display: a trajectory's HTML summary table, and a model's page in a frame.

The animation's display is :class:`lagrangian.output.animation.Animation`.
"""

from __future__ import annotations

import html
import os
from dataclasses import dataclass, field

from ..files import check_output_path, write_atomically
from ..trajectory import Trajectory
from .notation import latex_name

#: Height in CSS pixels of a model's page shown inline (its width is the notebook's).
PAGE_FRAME_HEIGHT = 720


@dataclass(frozen=True)
class ModelPage:
    """A model's page (:func:`lagrangian.output.page.page_html`), shown inline in Jupyter
    in a sandboxed frame: its scripts run, but in an origin of their own, so they can
    reach neither the notebook nor its kernel."""

    html: str = field(repr=False)  # a whole document: megabytes in a terminal otherwise
    height: int = PAGE_FRAME_HEIGHT

    def _repr_html_(self) -> str:
        return sandboxed_frame(self.html, height=self.height)

    def save(self, path: str | os.PathLike) -> None:
        """Write the page to ``path`` (an .html file that works offline), atomically."""
        write_atomically(
            check_output_path(path),
            lambda temporary: temporary.write_text(self.html, encoding="utf-8"),
        )


def sandboxed_frame(document: str, *, height: int = PAGE_FRAME_HEIGHT) -> str:
    """An ``<iframe>`` showing the HTML ``document`` from its ``srcdoc`` attribute, escaped
    (so that no text of the document can end the attribute), sandboxed to run scripts only.

    >>> sandboxed_frame('<p title="a">x</p>', height=100)[:62]
    '<iframe sandbox="allow-scripts" srcdoc="&lt;p title=&quot;a&quot;'
    """
    return (
        f'<iframe sandbox="allow-scripts" srcdoc="{html.escape(document, quote=True)}" '
        f'style="width: 100%; height: {int(height)}px; border: 1px solid #ddd" '
        'title="the page of the model"></iframe>'
    )


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
        if trajectory.energy_not_conserved:  # its change is physics, not drift
            change = f"{trajectory.drift('energy'):.3e} ({trajectory.energy_not_conserved})"
            rows.append(("change of energy $h$, not conserved", change))
        for name, reason in trajectory.conserved_here.items():
            shown = "energy $h$" if name == "energy" else f"${latex_name(name)}$"
            why = f"not in general ({reason}): not at these values"
            rows.append((f"{shown} conserved in this run", why))
    body = "\n".join(
        f'<tr><th style="text-align:left">{html.escape(key)}</th>'
        f'<td style="text-align:left">{html.escape(value)}</td></tr>'
        for key, value in rows
    )
    return f'<table class="lagrangian-trajectory">\n{body}\n</table>'

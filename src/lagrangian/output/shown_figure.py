"""A matplotlib figure that shows itself in Jupyter, with no ``%matplotlib inline``.

The toolkit's figures are built on the Agg canvas without pyplot
(:func:`lagrangian.output.plots.new_figure`), so no backend ever registered them with
IPython: a cell that returned one printed ``<Figure size 750x380 with 1 Axes>`` until
the user typed ``%matplotlib inline``.  IPython shows an object through its
``_repr_png_`` when no formatter of its type is registered (and the inline backend's,
where it is active, draws the same PNG): so each figure carries its own.

Imported only by :func:`~lagrangian.output.plots.new_figure` (matplotlib is heavy).
"""

from __future__ import annotations

from io import BytesIO

from matplotlib.figure import Figure

#: Resolution of the picture a notebook shows (matplotlib_inline's default is 72 at
#: its figure size; 100 reads better on today's screens and stays small).
NOTEBOOK_DPI = 100


class ShownFigure(Figure):
    """A :class:`matplotlib.figure.Figure` with ``_repr_png_``: in Jupyter a cell that
    returns it shows the picture."""

    def _repr_png_(self) -> bytes:
        buffer = BytesIO()
        self.savefig(buffer, format="png", dpi=NOTEBOOK_DPI)
        return buffer.getvalue()

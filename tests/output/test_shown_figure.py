"""A figure the toolkit returns shows itself in Jupyter with no ``%matplotlib inline``:
IPython calls ``_repr_png_`` of an object no formatter is registered for, and the PNG
it gets back is the figure (its size in pixels is the figure's at the notebook's dpi)."""

from __future__ import annotations

import struct

import pytest

import lagrangian as lg
from lagrangian.output.shown_figure import NOTEBOOK_DPI

pytestmark = pytest.mark.slow  # a simulation and matplotlib

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("kind", ["timeseries", "phase"])
def test_a_returned_figure_shows_itself_as_png(kind):
    trajectory = lg.load("simple_pendulum").simulate(t_end=1.0)
    figure = trajectory.plot(kind)
    png = figure._repr_png_()
    assert png.startswith(PNG_SIGNATURE)
    width, height = struct.unpack(">II", png[16:24])  # the IHDR chunk
    expected = figure.get_size_inches() * NOTEBOOK_DPI
    assert (width, height) == pytest.approx(tuple(expected), abs=1)

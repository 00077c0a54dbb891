"""Shared test data and pixel helpers: read a rendered figure (rows from the top) where
the data point."""

from __future__ import annotations

import numpy as np

PENDULUM_WITH_BOB = """
name = "Pendulum with a bob"
coordinates = ["theta"]

[parameters]
m = 1.0
l = 1.0
g = 9.81

[[particles]]
name = "bob"
mass = "m"
position = ["l*sin(theta)", "-l*cos(theta)"]

[gravity]
g = "g"

[initial]
theta = 1.0
"""


def pixels(figure) -> np.ndarray:
    """The RGBA pixels of a figure, drawn in full (rows from the top)."""
    figure.canvas.draw()
    return np.asarray(figure.canvas.buffer_rgba())[..., :3].astype(int)


def pixel_of(ax, x: float, y: float, height: int) -> tuple[float, float]:
    """(row, column) of the data point (x, y): display coordinates have y upwards."""
    column, up = ax.transData.transform((x, y))
    return height - up, column


def color_mask(image: np.ndarray, color, tolerance: int = 12) -> np.ndarray:
    from matplotlib.colors import to_rgb

    target = np.array(to_rgb(color)) * 255
    return np.all(np.abs(image - target) <= tolerance, axis=-1)


def near(image: np.ndarray, row: float, column: float, radius: int = 2) -> np.ndarray:
    """The pixels within ``radius`` of (row, column), as (k, 3)."""
    r, c = round(row), round(column)
    return image[r - radius : r + radius + 1, c - radius : c + radius + 1].reshape(-1, 3)

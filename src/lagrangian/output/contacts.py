"""The walls and floors of a model's contacts (``[[impacts]]``), as lines to draw.

A contact's gap that is affine in one particle's position r (each coordinate it uses is a
component of that particle's position, and g = a . r + c with a and c numbers at the
parameter values) closes on the line (2-D) a . r + c = 0: the floor of the bouncing ball
(g = y), the wall of the impact oscillator (g = d - x).  Other gaps (a block's corners,
two balls' distance) have no fixed set in the plane and are not drawn.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy

from ..algebra import as_expression

#: How contact lines are drawn.
WALL_COLOR, WALL_WIDTH = "#5b5b5b", 2.5


def contact_lines(system, parameters: Mapping[str, float]) -> list[tuple[np.ndarray, float]]:
    """(a (D,), c) of each contact whose gap is a . r + c in one particle's position r."""
    coordinates = {c.q for c in system.coordinates}
    values = {p.symbol: parameters[p.name] for p in system.parameters if p.name in parameters}
    lines = []
    for impact in system.impacts:
        used = impact.gap.free_symbols & coordinates
        for particle in system.particles:
            components = [as_expression(x) for x in particle.position]
            slots = {x: k for k, x in enumerate(components) if x in coordinates}
            if not used <= set(slots):
                continue
            r = sympy.symbols(f"_r0:{len(components)}", real=True)
            gap = impact.gap.xreplace({x: r[k] for x, k in slots.items()}).xreplace(values)
            slopes = [sympy.diff(gap, rk) for rk in r]
            if any(s.free_symbols for s in slopes) or gap.has(system.time):
                continue
            offset = gap.xreplace(dict.fromkeys(r, 0))
            try:
                a = np.array([float(s) for s in slopes])
                c = float(offset)
            except TypeError:
                continue
            if np.any(a) and np.all(np.isfinite(a)) and np.isfinite(c):
                lines.append((a, c))
                break
    return lines


def draw_contact_lines(ax, lines, axes: tuple[int, int]) -> None:
    """Each line a . r + c = 0 across the panel of the position components ``axes``."""
    i, j = axes
    for a, c in lines:
        if len(a) != 2 or (i, j) != (0, 1):
            continue
        base = -c * a / float(a @ a)
        ax.axline(base, base + np.array([-a[1], a[0]]), color=WALL_COLOR, lw=WALL_WIDTH, zorder=1)

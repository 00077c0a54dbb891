"""`MechanismView`: one figure of the mechanism whose moving parts show any frame.

The view is built from a :class:`~lagrangian.output.geometry.Geometry` and the
motion resampled at the frame times (see :mod:`lagrangian.output.animation`):
particles are dots whose area grows like mass^(2/3) (balls of one density),
rods join the points a rigid link holds at constant distance, springs are
zigzags, planar rigid bodies are thick rods through their centre, 3-D bodies are
boxes or discs turned by their rotation (with a stem from the origin when they
turn about a fixed point there), the last particle
leaves a fading trail, and the time is printed in a corner.  The axes have
aspect 1:1 and limits that hold the largest extent of the whole run plus a
margin, so nothing is clipped at the largest swing.

Figures are built with the Agg canvas directly (no pyplot, no global backend
state), so everything works without a display.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING

import numpy as np

from .geometry import ORIGIN, Geometry, Positions, axis_label, solid_pivots, zigzag

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .linkage_drawing import LinkageFrames

#: Largest side of the drawing area, inches; pixels per inch of the frames.
DEFAULT_SIZE = 5.0
DEFAULT_DPI = 80
#: Margin around the largest extent, as a fraction of the largest span.
MARGIN = 0.12
#: Marker diameter (points) of the heaviest particle and of a particle of mass -> 0.
LARGEST_MARKER, SMALLEST_MARKER = 15.0, 5.0
#: The colours of the parts, as hex (the page uses them as they are: no matplotlib to read
#: them); the greys are matplotlib's "0.25" and "0.45" rounded to 8 bits, as it draws them.
ROD_COLOR, SPRING_COLOR, BODY_COLOR, PIVOT_COLOR = "#404040", "#737373", "#8c564b", "#000000"
#: The hoop or rail a particle is held to (:mod:`lagrangian.output.tracks`).
TRACK_COLOR = "#9aa4ae"
SOLID_COLOR = "#1f4e79"
#: Opacity of the newest piece of the trail (the oldest is transparent).
TRAIL_ALPHA = 0.85
_LEFT, _RIGHT, _BOTTOM, _TOP, _GAP = 0.65, 0.2, 0.5, 0.5, 0.55  # figure margins, inches


class MechanismView:
    """The mechanism at the frames of a motion: ``update(k)`` moves every part to frame k.

    ``positions`` hold the geometry at ``oversample`` times per frame (the trail
    uses the points between frames); ``extent`` (D, 2) is the box to show.
    """

    def __init__(
        self,
        geometry: Geometry,
        positions: Positions,
        rods: Sequence[tuple[int, int]],
        extent: np.ndarray,
        *,
        oversample: int,
        trail_points: int,
        title: str,
        caption: str = "",
        size: float = DEFAULT_SIZE,
        dpi: int = DEFAULT_DPI,
        tracks: Sequence[np.ndarray] = (),
        linkage: LinkageFrames | None = None,
    ):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.geometry = geometry
        self.tracks = tuple(tracks)  # (D, S, frames): the hoops and rails (.tracks)
        self.linkage = linkage  # links, joints, pins and reactions (.linkage_drawing)
        self.positions = positions
        self.rods = tuple(rods)
        self.oversample = int(oversample)
        self.trail_points = int(trail_points)
        self.caption = caption
        self.frame_count = (positions.t.shape[0] - 1) // self.oversample + 1
        self.outlines = geometry.solid_outlines(positions)  # (K, 3, T) per 3-D body
        self.stems = solid_pivots(positions)
        spans = max(float(np.max(extent[:, 1] - extent[:, 0])), 1e-9)
        self.spring_width = 0.025 * spans
        limits = _limits(extent, geometry.views, size)
        width, height, boxes = _layout(limits, size, dpi)
        self.figure: Figure = Figure(figsize=(width, height), dpi=dpi)
        FigureCanvasAgg(self.figure)
        self.figure.suptitle(title, fontsize=11)
        self.axes = []
        self._moving: list = []
        self._panels = []
        for (horizontal, vertical), box, (xlim, ylim) in zip(
            geometry.views, boxes, limits, strict=True
        ):
            ax = self.figure.add_axes(box)
            ax.set_xlim(*xlim)
            ax.set_ylim(*ylim)
            ax.set_aspect("equal", adjustable="box")
            ax.set_xlabel(axis_label(horizontal))
            ax.set_ylabel(axis_label(vertical))
            ax.tick_params(labelsize=8)
            ax.grid(True, color="0.92", linewidth=0.6)
            ax.set_axisbelow(True)
            if geometry.dimension == 3:
                view = "top view" if vertical != geometry.vertical else "side view"
                ax.set_title(
                    f"{view} ({axis_label(horizontal)}-{axis_label(vertical)})", fontsize=9
                )
            self.axes.append(ax)
            self._panels.append(self._panel(ax, (horizontal, vertical)))
        self.time_text = self.axes[0].text(
            0.03,
            0.96,
            "",
            transform=self.axes[0].transAxes,
            va="top",
            ha="left",
            fontsize=9,
            family="monospace",
            bbox={"facecolor": "white", "edgecolor": "0.8", "alpha": 0.85, "pad": 2},
        )
        self._moving.append(self.time_text)

    # -- building -------------------------------------------------------------------
    def _panel(self, ax, axes: tuple[int, int]) -> dict:
        from matplotlib.collections import LineCollection

        geometry = self.geometry
        panel: dict = {"axes": axes}
        support = self.positions.support
        panel["pivot"] = []
        if support is not None and any(ORIGIN in rod for rod in self.rods):
            # a moving support: its path dotted, the pivot moving along it
            a, b = axes
            ax.plot(support[a], support[b], ":", color=PIVOT_COLOR, lw=1.0, zorder=1)
            panel["pivot"] = [
                ax.plot([], [], "o", ms=6, mfc="white", mec=PIVOT_COLOR, mew=1.5, zorder=4)[0]
            ]
        elif any(ORIGIN in rod for rod in self.rods) or self.stems:
            ax.plot([0], [0], "o", ms=6, mfc="white", mec=PIVOT_COLOR, mew=1.5, zorder=4)
        if geometry.system.impacts:  # the walls and floors of the contacts
            from .contacts import contact_lines, draw_contact_lines

            draw_contact_lines(ax, contact_lines(geometry.system, geometry.parameters), axes)
        panel["tracks"] = [
            ax.plot([], [], "-", color=TRACK_COLOR, lw=1.2, zorder=1)[0] for _ in self.tracks
        ]
        panel["springs"] = [
            ax.plot([], [], "-", color=SPRING_COLOR, lw=1.2, zorder=2)[0]
            for _ in geometry.system.springs
        ]
        panel["rods"] = [
            ax.plot([], [], "-", color=ROD_COLOR, lw=2.2, solid_capstyle="round", zorder=3)[0]
            for _ in self.rods
        ]
        for s in range(self.positions.springs.shape[0]):
            for end in self.positions.springs[s]:  # (D, T): a fixed end gets an anchor
                if np.ptp(end, axis=1).max() == 0:
                    ax.plot(
                        [end[axes[0], 0]], [end[axes[1], 0]], "s", ms=6, color=PIVOT_COLOR, zorder=4
                    )
        panel["bodies"] = [
            ax.plot([], [], "-", color=BODY_COLOR, lw=7, alpha=0.85, zorder=3)[0]
            for _ in geometry.planar_bodies
        ]
        panel["centers"] = [
            ax.plot([], [], "o", ms=4, color="white", mec="black", mew=0.8, zorder=4)[0]
            for _ in [*geometry.planar_bodies, *geometry.solids]
        ]
        panel["stems"] = [
            ax.plot([], [], "-", color=ROD_COLOR, lw=2.2, solid_capstyle="round", zorder=3)[0]
            for _ in self.stems
        ]
        panel["solids"] = [
            [
                ax.plot([], [], "-", color=SOLID_COLOR, lw=1.6, zorder=3)[0]
                for _ in geometry.solid_shapes[i].paths
            ]
            for i in range(len(geometry.solid_shapes))
        ]
        trail = LineCollection([], linewidths=1.8, zorder=1, capstyle="butt")
        ax.add_collection(trail)
        panel["trail"] = trail
        panel["particles"] = [
            ax.plot([], [], "o", ms=size, color=color, mec=_darker(color), mew=1.0, zorder=5)[0]
            for size, color in zip(self.marker_sizes, self.particle_colors, strict=True)
        ]
        kinds = ("tracks", "springs", "rods", "bodies", "centers", "stems", "particles", "pivot")
        for kind in kinds:
            self._moving.extend(panel[kind])
        if self.linkage is not None:
            from .linkage_drawing import linkage_panel, moving_artists

            panel["linkage"] = linkage_panel(ax, self.linkage, self.spring_width / 0.025)
            self._moving.extend(moving_artists(panel["linkage"]))
        for lines in panel["solids"]:
            self._moving.extend(lines)
        self._moving.append(trail)
        return panel

    @property
    def marker_sizes(self) -> list[float]:
        masses = np.clip(np.nan_to_num(self.geometry.masses), 0, None)
        if masses.size == 0 or masses.max() <= 0:
            return [LARGEST_MARKER * 0.8] * masses.size
        relative = (masses / masses.max()) ** (1 / 3)
        return list(SMALLEST_MARKER + (LARGEST_MARKER - SMALLEST_MARKER) * relative)

    @property
    def particle_colors(self) -> list[str]:
        return [f"C{i % 10}" for i in range(self.geometry.masses.size)]

    @property
    def colors(self) -> list:
        """Every colour the moving parts are drawn in (a GIF palette keeps them exact)."""
        colors = [ROD_COLOR, SPRING_COLOR, BODY_COLOR, PIVOT_COLOR, SOLID_COLOR]
        colors += self.particle_colors
        return colors + [_darker(color) for color in self.particle_colors]

    @property
    def trail_color(self) -> str:
        return self.particle_colors[-1] if self.particle_colors else BODY_COLOR

    @property
    def frame_times(self) -> np.ndarray:
        return self.positions.t[:: self.oversample]

    # -- frames -----------------------------------------------------------------------
    def point(self, k: int) -> np.ndarray:
        """(D,) position at frame k of the point that leaves the trail (last particle/body)."""
        return self._tracked()[:, k * self.oversample]

    def _tracked(self) -> np.ndarray:
        if self.positions.particles.shape[0]:
            return self.positions.particles[-1]
        if not self.positions.centers.shape[0]:  # 3-D bodies only
            return self.positions.solid_centers[-1]
        center = self.positions.centers[-1]
        return np.concatenate([center, np.zeros((self.geometry.dimension - 2, center.shape[1]))])

    def update(self, k: int) -> list:
        """Move every part to frame ``k``; returns the artists that changed."""
        j = k * self.oversample
        p = self.positions
        ends = self.geometry.body_ends(p) if self.geometry.planar_bodies else None
        tracked = self._tracked()
        for panel in self._panels:
            a, b = panel["axes"]
            for line, i in zip(panel["particles"], range(p.particles.shape[0]), strict=True):
                line.set_data([p.particles[i, a, j]], [p.particles[i, b, j]])
            for line in panel["pivot"]:
                line.set_data([p.support[a, j]], [p.support[b, j]])
            for line, curve in zip(panel["tracks"], self.tracks, strict=True):
                line.set_data(curve[a, :, k], curve[b, :, k])
            for line, (i, n) in zip(panel["rods"], self.rods, strict=True):
                first, second = p.point(i)[:, j], p.point(n)[:, j]
                line.set_data([first[a], second[a]], [first[b], second[b]])
            for line, s in zip(panel["springs"], range(p.springs.shape[0]), strict=True):
                start, end = p.springs[s, 0, :, j], p.springs[s, 1, :, j]
                points = zigzag(start[[a, b]], end[[a, b]], width=self.spring_width)
                line.set_data(points[0], points[1])
            if ends is not None:
                for line, n in zip(panel["bodies"], range(ends.shape[0]), strict=True):
                    line.set_data(ends[n, :, 0, j], ends[n, :, 1, j])
                dots = panel["centers"][: ends.shape[0]]
                for dot, n in zip(dots, range(ends.shape[0]), strict=True):
                    dot.set_data([p.centers[n, 0, j]], [p.centers[n, 1, j]])
            self._update_solids(panel, j)
            if self.linkage is not None:
                from .linkage_drawing import update_linkage

                update_linkage(panel["linkage"], self.linkage, j)
            start = max(0, j - self.trail_points)
            xy = np.column_stack([tracked[a, start : j + 1], tracked[b, start : j + 1]])
            segments = np.stack([xy[:-1], xy[1:]], axis=1) if len(xy) > 1 else np.empty((0, 2, 2))
            panel["trail"].set_segments(segments)
            panel["trail"].set_color(_fading(self.trail_color, len(segments)))
        shown = f"t = {p.t[j]:.2f}"
        self.time_text.set_text(f"{shown}\n{self.caption}" if self.caption else shown)
        return self._moving

    def _update_solids(self, panel: dict, j: int) -> None:
        """Move the outlines, centres and stems of the 3-D bodies to sample ``j``."""
        a, b = panel["axes"]
        centers = self.positions.solid_centers
        dots = panel["centers"][len(self.geometry.planar_bodies) :]
        for i, (lines, outline) in enumerate(zip(panel["solids"], self.outlines, strict=True)):
            paths = self.geometry.solid_shapes[i].paths
            for line, path in zip(lines, paths, strict=True):
                line.set_data(outline[list(path), a, j], outline[list(path), b, j])
            dots[i].set_data([centers[i, a, j]], [centers[i, b, j]])
        for line, i in zip(panel["stems"], self.stems, strict=True):
            line.set_data([0, centers[i, a, j]], [0, centers[i, b, j]])

    def render(self, k: int) -> np.ndarray:
        """The RGBA pixels (rows from the top) of frame ``k``, drawn in full."""
        self._set_animated(False)
        self.update(k)
        self.figure.canvas.draw()
        return np.asarray(self.figure.canvas.buffer_rgba()).copy()

    def frames(self) -> Iterator[np.ndarray]:
        """The RGBA pixels of every frame, fast: the still parts are drawn once (blitting)."""
        canvas = self.figure.canvas
        self._set_animated(True)
        try:
            canvas.draw()
            background = canvas.copy_from_bbox(self.figure.bbox)
            for k in range(self.frame_count):
                canvas.restore_region(background)
                for artist in sorted(self.update(k), key=lambda a: a.get_zorder()):
                    artist.axes.draw_artist(artist)
                yield np.asarray(canvas.buffer_rgba()).copy()
        finally:
            self._set_animated(False)

    def _set_animated(self, value: bool) -> None:
        for artist in self._moving:
            artist.set_animated(value)


def _fading(color: str, count: int) -> np.ndarray:
    from matplotlib.colors import to_rgba

    rgba = np.tile(to_rgba(color), (count, 1))
    rgba[:, 3] = TRAIL_ALPHA * np.linspace(0.0, 1.0, count + 1)[1:] if count else []
    return rgba


def _darker(color: str) -> tuple[float, float, float]:
    from matplotlib.colors import to_rgb

    return tuple(0.6 * c for c in to_rgb(color))


def _limits(extent: np.ndarray, views, size: float) -> list[tuple[tuple, tuple]]:
    """(xlim, ylim) of every view: the extent plus a margin; a flat box gets some height."""
    spans = extent[:, 1] - extent[:, 0]
    largest = float(spans.max()) if spans.size and spans.max() > 0 else 1.0
    margin = MARGIN * largest
    limits = []
    for a, b in views:
        box = []
        for axis in (a, b):
            low, high = extent[axis]
            middle, half = (low + high) / 2, (high - low) / 2 + margin
            half = max(half, 0.2 * largest)  # at most 1:2.5 within a panel
            box.append((middle - half, middle + half))
        limits.append(tuple(box))
    # every panel gets the height of the tallest: one scale for all views
    tallest = max(y[1] - y[0] for _, y in limits)
    return [(x, ((y[0] + y[1] - tallest) / 2, (y[0] + y[1] + tallest) / 2)) for x, y in limits]


def _layout(limits, size: float, dpi: int) -> tuple[float, float, list[list[float]]]:
    """Figure (width, height) in inches and the axes boxes, one scale (inches per unit)."""
    largest = max(max(x[1] - x[0], y[1] - y[0]) for x, y in limits)
    scale = size / len(limits) ** 0.5 / largest
    widths = [(x[1] - x[0]) * scale for x, _ in limits]
    height = (limits[0][1][1] - limits[0][1][0]) * scale
    figure_width = _LEFT + sum(widths) + _GAP * (len(widths) - 1) + _RIGHT
    figure_height = _BOTTOM + height + _TOP
    # whole, even pixel counts (video encoders need even sizes)
    figure_width = 2 * np.ceil(figure_width * dpi / 2) / dpi
    figure_height = 2 * np.ceil(figure_height * dpi / 2) / dpi
    boxes, left = [], _LEFT
    for width in widths:
        boxes.append(
            [
                left / figure_width,
                _BOTTOM / figure_height,
                width / figure_width,
                height / figure_height,
            ]
        )
        left += width + _GAP
    return figure_width, figure_height, boxes

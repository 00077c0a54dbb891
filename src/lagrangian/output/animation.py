"""Animations of the mechanism: GIF, MP4 (with ffmpeg) or a standalone HTML page.

The frames play in real time: at ``fps`` frames per second a run of T seconds
has round(T fps) frames (10 s at 25 fps: 250 frames of 40 ms), the motion
resampled at the frame times t_k = t_0 + k / fps by cubic Hermite
interpolation of q with its velocities q' (so the resampling error is O(h^4)
in the output step h, and no extra integration is needed).  Longer runs are
capped at ``max_frames`` frames and then play faster than real time; the plan
says so (:attr:`FramePlan.description`).

Formats, by the suffix of the path:

- ``.gif``: Pillow, one shared palette, a frame duration of 1000 / fps ms;
- ``.html``: one page with the frames embedded (base64 PNG) and matplotlib's
  JavaScript player (``Animation.to_jshtml``); it plays in a browser from the
  file, with no server;
- ``.mp4``: matplotlib's ffmpeg writer, only where ffmpeg is installed.

Every file is written atomically (a temporary file, then a rename).  The
picture itself is described in :mod:`lagrangian.output.mechanism`.

>>> plan = frame_plan(0.0, 10.0, fps=25)
>>> plan.frames, plan.frame_duration_ms, plan.speed
(250, 40.0, 1.0)
"""

from __future__ import annotations

import base64
import html
import os
import re
import shutil
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from ..errors import ModelError
from ..files import write_atomically
from ..model import System
from ..trajectory import Trajectory
from .geometry import geometry, rods
from .linkage_drawing import linkage_frames
from .mechanism import DEFAULT_DPI, DEFAULT_SIZE, MechanismView
from .tracks import held, track_curves, tracks

DEFAULT_FPS = 25
#: At most this many frames (20 s of real time at 25 fps); longer runs play faster.
DEFAULT_MAX_FRAMES = 500
#: Seconds of motion the trail of the last particle remembers.
DEFAULT_TRAIL = 1.0
#: Geometry samples per frame (the trail is drawn through them).
OVERSAMPLE = 4
#: Colours of a GIF (fewer colours, smaller files; the drawing uses few).
GIF_COLORS = 64
FORMATS = (".gif", ".html", ".mp4")
MP4_NEEDS_FFMPEG = "MP4 needs ffmpeg; write .gif or .html"


@dataclass(frozen=True)
class FramePlan:
    """The frame times of an animation, its frame rate and its speed (simulated s per s)."""

    times: np.ndarray = field(repr=False)
    fps: float
    speed: float
    capped: bool = False

    @property
    def frames(self) -> int:
        return int(self.times.shape[0])

    @property
    def frame_duration_ms(self) -> float:
        return 1000.0 / self.fps

    @property
    def description(self) -> str:
        """'250 frames at 25 fps, real time' or what the cap changed."""
        text = f"{self.frames} frames at {self.fps:g} fps"
        if abs(self.speed - 1.0) < 1e-9:
            return text + ", real time"
        pace = f"{self.speed:.3g}x real time"
        if self.capped:
            return f"{text}, {pace} (at most {self.frames} frames; pass max_frames for more)"
        return f"{text}, {pace}"


def frame_plan(
    t_start: float,
    t_end: float,
    *,
    fps: float = DEFAULT_FPS,
    max_frames: int = DEFAULT_MAX_FRAMES,
) -> FramePlan:
    """Frames t_k = t_start + k / fps, k < round((t_end - t_start) fps), at most ``max_frames``.

    Beyond ``max_frames`` the frames are spread evenly over the run and the
    animation plays ``speed`` times faster than real time.
    """
    if not fps > 0:
        raise ModelError(f"fps must be positive, not {fps!r}")
    if int(max_frames) < 2:
        raise ModelError(f"max_frames must be at least 2, not {max_frames!r}")
    span = float(t_end - t_start)
    if not np.isfinite(span) or span <= 0:
        raise ModelError("the trajectory has no time span to animate")
    wanted = max(2, round(span * fps))
    capped = wanted > max_frames
    frames = int(max_frames) if capped else wanted
    step = span / frames if (capped or (frames - 1) / fps > span) else 1.0 / fps
    times = t_start + step * np.arange(frames)
    return FramePlan(times=times, fps=float(fps), speed=step * fps, capped=capped)


def resample(trajectory: Trajectory, times: np.ndarray) -> np.ndarray:
    """q (n, len(times)) at ``times``: cubic Hermite interpolation through q and q'."""
    from scipy.interpolate import CubicHermiteSpline

    t = trajectory.t
    keep = np.concatenate([[True], np.diff(t) > 0])  # repeated times (an event) add nothing
    t = t[keep]
    rows = []
    for name, rate in zip(trajectory.coordinates, trajectory.velocities, strict=True):
        q, v = trajectory[name][keep], trajectory[rate][keep]
        if t.shape[0] < 2:
            rows.append(np.full(np.shape(times), q[0] if q.size else np.nan))
            continue
        rows.append(CubicHermiteSpline(t, q, v, extrapolate=True)(np.clip(times, t[0], t[-1])))
    return np.array(rows, dtype=float).reshape(len(rows), np.size(times))


def mechanism_view(
    trajectory: Trajectory,
    system: System,
    *,
    fps: float = DEFAULT_FPS,
    max_frames: int = DEFAULT_MAX_FRAMES,
    trail: float = DEFAULT_TRAIL,
    size: float = DEFAULT_SIZE,
    dpi: int = DEFAULT_DPI,
    reactions: bool = False,
) -> tuple[MechanismView, FramePlan]:
    """The :class:`MechanismView` of ``trajectory`` and its :class:`FramePlan`; with
    ``reactions``, a linkage's joint reactions drawn as arrows."""
    scene = geometry(system, trajectory.parameters)
    missing = [q for q in system.coordinate_names if q not in trajectory.coordinates]
    if missing:
        raise ModelError(f"the trajectory has no coordinate(s) {', '.join(missing)} of the model")
    t = trajectory.t
    if t.shape[0] == 0:
        raise ModelError("the trajectory is empty")
    plan = frame_plan(float(t[0]), float(t[-1]), fps=fps, max_frames=max_frames)
    step = (plan.times[1] - plan.times[0]) / OVERSAMPLE
    fine = plan.times[0] + step * np.arange((plan.frames - 1) * OVERSAMPLE + 1)
    samples = np.stack([trajectory[q] for q in system.coordinate_names])
    along_run = scene.at(t, samples)
    positions = scene.at(fine, resample(trajectory, fine))
    linkage = linkage_frames(
        system, trajectory, fine, resample(trajectory, fine), scene.parameters, reactions=reactions
    )
    links = () if scene.coordinates_only else rods(along_run)
    drawn, links = ([], links) if scene.coordinates_only else held(tracks(system), links)
    extent = _union(scene.extent(along_run, links), scene.extent(positions, links))
    if linkage is not None:
        extent = _union(extent, linkage.extent())
    span = max(float(np.max(extent[:, 1] - extent[:, 0])), 1e-9)
    curves = track_curves(scene, drawn, plan.times, resample(trajectory, plan.times), span)
    for track, curve in zip(drawn, curves, strict=True):
        if track.closed:  # a hoop whole in view (a rail is longer than any view)
            points = curve.reshape(curve.shape[0], -1)
            extent = _union(extent, np.column_stack([points.min(axis=1), points.max(axis=1)]))
    caption = "" if abs(plan.speed - 1) < 1e-9 else f"({plan.speed:.3g}x speed)"
    view = MechanismView(
        scene,
        positions,
        links,
        extent,
        oversample=OVERSAMPLE,
        trail_points=max(1, round(trail / step)),
        title=trajectory.dataset.attrs.get("model") or system.name,
        caption=caption,
        size=size,
        dpi=dpi,
        tracks=curves,
        linkage=linkage,
    )
    return view, plan


def _union(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The box (D, 2) that holds the boxes ``a`` and ``b``."""
    return np.column_stack([np.minimum(a[:, 0], b[:, 0]), np.maximum(a[:, 1], b[:, 1])])


@dataclass(frozen=True, eq=False)
class Animation:
    """A rendered animation: the file written (or None) and its :class:`FramePlan`.

    Displays itself in Jupyter (``_repr_html_``): the embedded player when no
    file was written, else the file (GIF as an image, MP4 as a video, HTML as is).
    """

    path: Path | None
    plan: FramePlan
    html: str | None = field(default=None, repr=False)

    @cached_property
    def _page(self) -> str:
        if self.html is not None:
            return self.html
        assert self.path is not None
        data = self.path.read_bytes()
        if self.path.suffix == ".html":
            return data.decode("utf-8")
        encoded = base64.b64encode(data).decode("ascii")
        if self.path.suffix == ".gif":
            return (
                f'<img src="data:image/gif;base64,{encoded}" alt="{html.escape(self.path.name)}"/>'
            )
        return f'<video controls loop src="data:video/mp4;base64,{encoded}"></video>'

    def _repr_html_(self) -> str:
        return self._page


def check_animation_path(path: str | os.PathLike) -> str:
    """The suffix of ``path`` if it can be written here, else a :class:`ModelError`."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ModelError(f"cannot write '{suffix or path}' animations (use .gif, .html or .mp4)")
    if suffix == ".mp4" and not ffmpeg_available():
        raise ModelError(MP4_NEEDS_FFMPEG)
    return suffix


def ffmpeg_available() -> bool:
    import matplotlib

    return shutil.which(str(matplotlib.rcParams["animation.ffmpeg_path"])) is not None


def animate(
    trajectory: Trajectory,
    system: System,
    path: str | os.PathLike | None = None,
    *,
    fps: float = DEFAULT_FPS,
    max_frames: int = DEFAULT_MAX_FRAMES,
    trail: float = DEFAULT_TRAIL,
    size: float = DEFAULT_SIZE,
    dpi: int = DEFAULT_DPI,
    reactions: bool = False,
) -> Animation:
    """Animate ``trajectory`` of ``system``; write ``path`` (.gif, .html, .mp4) when given.

    Without a path the result holds the HTML player and shows in Jupyter.  ``reactions``:
    a linkage's joint reactions as arrows (:mod:`.linkage_drawing`).
    A model without particles or bodies is drawn as its coordinates (one dot per
    coordinate moving along its own line).  Errors: an unknown suffix, MP4
    without ffmpeg.
    """
    suffix = check_animation_path(path) if path is not None else None
    view, plan = mechanism_view(
        trajectory,
        system,
        fps=fps,
        max_frames=max_frames,
        trail=trail,
        size=size,
        dpi=dpi,
        reactions=reactions,
    )
    if suffix is None:
        return Animation(None, plan, html=_player(view, plan))
    writer = {".gif": _write_gif, ".html": _write_html, ".mp4": _write_mp4}[suffix]
    target = write_atomically(path, lambda temporary: writer(view, plan, temporary))
    return Animation(target, plan)


def _write_gif(view: MechanismView, plan: FramePlan, target: Path) -> None:
    from PIL import Image

    palette = _gif_palette(view, plan)
    nearest = _NearestColor(np.array(palette.getpalette()[: 3 * GIF_COLORS]).reshape(-1, 3))
    frames = []
    for rgba in view.frames():
        frame = Image.frombytes("P", rgba.shape[1::-1], nearest(rgba[..., :3]).tobytes())
        frame.putpalette(palette.getpalette())
        frames.append(frame)
    frames[0].save(
        target,
        format="GIF",
        save_all=True,
        append_images=frames[1:],
        duration=plan.frame_duration_ms,
        loop=0,
        optimize=False,
    )


class _NearestColor:
    """Pixels -> index of the nearest palette colour, exactly (Pillow's own mapping is
    approximate: white would come out as (253, 252, 251)); a table over the 2^24
    colours is filled as colours appear, so each frame costs one lookup."""

    def __init__(self, palette: np.ndarray):
        self.palette = palette.astype(np.int64)
        self.table = np.full(1 << 24, -1, dtype=np.int16)

    def __call__(self, rgb: np.ndarray) -> np.ndarray:
        rgb = rgb.astype(np.int64)
        packed = (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]
        index = self.table[packed]
        missing = index < 0
        if missing.any():
            new = np.unique(packed[missing])
            colors = np.stack([new >> 16, (new >> 8) & 255, new & 255], axis=1)
            distance = ((colors[:, None, :] - self.palette[None, :, :]) ** 2).sum(axis=-1)
            self.table[new] = distance.argmin(axis=1)
            index = self.table[packed]
        return index.astype(np.uint8)


def _gif_palette(view: MechanismView, plan: FramePlan):
    """:data:`GIF_COLORS` colours: the drawing's own colours exactly (white paper, the
    particles, rods, springs), the rest by median cut of a few frames (edges, text)."""
    from matplotlib.colors import to_rgb
    from PIL import Image

    exact = {(255, 255, 255), (0, 0, 0)}
    exact |= {tuple(round(255 * c) for c in to_rgb(color)) for color in view.colors}
    samples = np.linspace(0, plan.frames - 1, 4).round().astype(int)
    stills = [Image.fromarray(view.render(int(k))[..., :3]) for k in samples]
    montage = Image.new("RGB", (stills[0].width, stills[0].height * len(stills)))
    for i, still in enumerate(stills):
        montage.paste(still, (0, i * still.height))
    rest = montage.quantize(colors=GIF_COLORS - len(exact), method=Image.Quantize.MEDIANCUT)
    entries = rest.getpalette()[: 3 * (GIF_COLORS - len(exact))]
    for color in sorted(exact):
        entries.extend(color)
    palette = Image.new("P", (1, 1))
    palette.putpalette(entries)
    return palette


def _func_animation(view: MechanismView, plan: FramePlan):
    from matplotlib.animation import FuncAnimation

    return FuncAnimation(
        view.figure,
        view.update,
        frames=plan.frames,
        interval=plan.frame_duration_ms,
        blit=False,
        repeat=True,
    )


def _player(view: MechanismView, plan: FramePlan) -> str:
    """matplotlib's JavaScript player with every frame embedded (no frame dropped)."""
    import matplotlib

    view._set_animated(False)
    with matplotlib.rc_context({"animation.embed_limit": 2048.0}):  # MB; the cap bounds it
        return _func_animation(view, plan).to_jshtml(
            fps=plan.fps, embed_frames=True, default_mode="loop"
        )


#: Button labels that need no web font (the player links one from a CDN; offline it is
#: missing, so the page drops the link and labels the buttons with these characters).
_OFFLINE_BUTTONS = """<style>
.anim-buttons .fa { font-style: normal; }
.fa-minus:before { content: "\\2212"; }
.fa-plus:before { content: "+"; }
.fa-fast-backward:before { content: "\\23EE"; }
.fa-step-backward:before { content: "\\23EA"; }
.fa-play:before { content: "\\25B6"; }
.fa-flip-horizontal:before { content: "\\25C0"; }
.fa-pause:before { content: "\\23F8"; }
.fa-step-forward:before { content: "\\23E9"; }
.fa-fast-forward:before { content: "\\23ED"; }
</style>"""


def _write_html(view: MechanismView, plan: FramePlan, target: Path) -> None:
    """A page that plays at once, from the file, offline: frames and script inline."""
    title = html.escape(str(view.figure.get_suptitle()))
    player = re.sub(r'<link rel="stylesheet"\s+href="https?://[^"]*"\s*>', "", _player(view, plan))
    names = re.findall(r"(anim[0-9a-f]+)\.play_animation", player)
    start = (
        f"<script>window.addEventListener('load', function() {{ setTimeout(function() {{"
        f" {names[0]}.play_animation(); }}, 100); }});</script>\n"
        if names
        else ""
    )
    page = (
        '<!DOCTYPE html>\n<html>\n<head>\n<meta charset="utf-8">\n'
        f"<title>{title}</title>\n{_OFFLINE_BUTTONS}\n</head>\n<body>\n"
        f"<p>{title}: {html.escape(plan.description)}</p>\n"
        f"{player}\n{start}</body>\n</html>\n"
    )
    target.write_text(page, encoding="utf-8")


def _write_mp4(view: MechanismView, plan: FramePlan, target: Path) -> None:
    from matplotlib.animation import FFMpegWriter

    view._set_animated(False)
    writer = FFMpegWriter(fps=plan.fps, extra_args=["-f", "mp4"])  # the temporary has no .mp4
    _func_animation(view, plan).save(str(target), writer=writer, dpi=view.figure.dpi)

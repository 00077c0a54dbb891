"""The animation: where the bob is drawn, the trail, the limits, the files and their timing."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image, ImageSequence

import lagrangian as lg
from helpers import spring_bar_and_bob
from lagrangian.model import Gravity, Particle
from lagrangian.output.animation import (
    Animation,
    animate,
    frame_plan,
    mechanism_view,
    resample,
)
from lagrangian.output.geometry import ORIGIN, geometry, rods, zigzag
from visual.pictures import color_mask, near, pixel_of

FRAME = 37  # t = 1.48 s: the bob on its way back, well inside the picture


def bob_at(run, t: float) -> tuple[float, float]:
    """The bob's position from the densely sampled run (linear interpolation), l = 1."""
    theta = np.interp(t, run.t, run["theta"])
    return np.sin(theta), -np.cos(theta)


@pytest.fixture(scope="module")
def view(bob_pendulum, bob_run):
    view, plan = mechanism_view(bob_run, bob_pendulum)
    return view, plan, view.render(FRAME)[..., :3].astype(int)


def test_bob_is_drawn_where_the_motion_puts_it(view, bob_run):
    view, plan, image = view
    t = plan.times[FRAME]
    assert t == pytest.approx(FRAME / 25)
    row, column = pixel_of(view.axes[0], *bob_at(bob_run, t), image.shape[0])
    bob = np.argwhere(color_mask(image, view.particle_colors[0]))
    assert len(bob) > 50  # a dot, not a speck
    centre = bob.mean(axis=0)
    assert abs(centre[0] - row) < 1.0 and abs(centre[1] - column) < 1.0


def test_trail_follows_the_previous_positions(view, bob_run):
    view, plan, image = view
    t = plan.times[FRAME]
    for back in (0.3, 0.5, 0.7):  # inside the 1 s trail, clear of the bob's marker
        row, column = pixel_of(view.axes[0], *bob_at(bob_run, t - back), image.shape[0])
        patch = near(image, row, column)
        assert np.any(np.abs(patch - 255).sum(axis=1) > 30), f"no trail {back} s back"
        tinted = patch[np.abs(patch - 255).sum(axis=1) > 30]
        assert np.all(tinted[:, 2] >= tinted[:, 0])  # the bob's blue, faded
    # and nothing where the pendulum never goes (beyond its amplitude of 1 rad)
    row, column = pixel_of(view.axes[0], np.sin(1.4), -np.cos(1.4), image.shape[0])
    assert np.all(near(image, row, column) == 255)


def test_rod_from_the_pivot_to_the_bob(view, bob_run):
    view, plan, image = view
    x, y = bob_at(bob_run, plan.times[FRAME])
    row, column = pixel_of(view.axes[0], x / 2, y / 2, image.shape[0])  # the rod's middle
    assert near(image, row, column, 1).max(axis=1).min() < 100  # dark grey
    assert rods(geometry(view.geometry.system).at(bob_run.t, bob_run["theta"][None])) == (
        (ORIGIN, 0),
    )


def test_square_axes_hold_the_largest_swing(view, bob_run):
    view, _, _ = view
    ax = view.axes[0]
    (x0, y0), (x1, y1) = ax.transData.transform([(0, 0), (1, 1)])
    assert x1 - x0 == pytest.approx(y1 - y0, rel=1e-3)  # 1:1
    amplitude = np.abs(bob_run["theta"]).max()
    xlim, ylim = ax.get_xlim(), ax.get_ylim()
    radius = view.marker_sizes[0] / 72 * view.figure.dpi / (x1 - x0)  # marker, in data units
    assert xlim[0] < -np.sin(amplitude) - radius and xlim[1] > np.sin(amplitude) + radius
    assert ylim[0] < -1 - radius and ylim[1] > radius


def test_time_is_shown(view):
    view, plan, _ = view
    assert view.time_text.get_text() == f"t = {plan.times[FRAME]:.2f}"


def test_gif_plays_in_real_time(bob_pendulum, bob_run, tmp_path):
    result = animate(bob_run, bob_pendulum, tmp_path / "pendulum.gif")
    assert isinstance(result, Animation) and result.plan.description.endswith("real time")
    with Image.open(tmp_path / "pendulum.gif") as gif:
        durations = [frame.info["duration"] for frame in ImageSequence.Iterator(gif)]
        gif.seek(FRAME)
        frame = np.asarray(gif.convert("RGB")).astype(int)
    assert len(durations) == 50  # 2 s at 25 fps
    assert set(durations) == {40}
    assert sum(durations) == 2000
    assert color_mask(frame, "C0", tolerance=40).sum() > 50  # the bob survives the palette
    assert [p.name for p in tmp_path.iterdir()] == ["pendulum.gif"]  # no temporary left


def test_frame_plan_caps_long_runs_and_says_so():
    plan = frame_plan(0.0, 100.0, fps=25, max_frames=500)
    assert plan.frames == 500 and plan.speed == pytest.approx(5.0)
    assert "5x real time" in plan.description and "at most 500 frames" in plan.description
    plan = frame_plan(0.0, 10.0, fps=25)
    assert plan.frames == 250 and plan.times[1] == pytest.approx(0.04) and plan.speed == 1.0


def test_html_page_embeds_every_frame(bob_pendulum, bob_run, tmp_path):
    short = bob_pendulum.simulate(t_end=0.4, n_out=50)
    result = animate(short, bob_pendulum, tmp_path / "pendulum.html")
    page = (tmp_path / "pendulum.html").read_text()
    assert page.startswith("<!DOCTYPE html>") and result.plan.frames == 10
    assert page.count("data:image/png;base64,") == 10
    assert "https://" not in page  # plays offline, from the file
    assert ".play_animation(); }, 100)" in page  # starts by itself


def test_without_a_path_the_animation_displays_in_jupyter(bob_pendulum):
    short = bob_pendulum.simulate(t_end=0.2, n_out=20)
    html = animate(short, bob_pendulum)._repr_html_()
    assert "<script" in html and html.count("data:image/png;base64,") == 5


def test_mp4_needs_ffmpeg(bob_pendulum, bob_run, tmp_path, monkeypatch):
    import matplotlib

    monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path", "no-such-ffmpeg-here")
    with pytest.raises(lg.ModelError, match=r"^MP4 needs ffmpeg; write \.gif or \.html$"):
        animate(bob_run, bob_pendulum, tmp_path / "pendulum.mp4")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_a_model_without_geometry_is_drawn_as_its_coordinates():
    # one dot per coordinate at (q_i, -i), following the run; no rods between them
    system = lg.load("harmonic_oscillator")
    run = system.simulate(t_end=1.0)
    scene = geometry(system)
    positions = scene.at(run.t, np.stack([run["x"]]))
    assert np.allclose(positions.particles[0, 0], run["x"])
    assert np.allclose(positions.particles[0, 1], 0.0)
    assert scene.coordinates_only
    assert animate(run, system).html


def test_double_pendulum_chain_of_rods():
    system = lg.load("double_pendulum")
    scene = geometry(system)
    t = np.linspace(0, 1, 50)
    q = np.stack([np.sin(3 * t) * 2, np.cos(5 * t)])
    assert rods(scene.at(t, q)) == ((ORIGIN, 0), (0, 1))


def test_no_rod_where_the_distance_changes():
    system = lg.load("free_particle_spherical")
    run = system.simulate(t_end=1.0)
    positions = geometry(system).at(run.t, np.stack([run[q] for q in run.coordinates]))
    assert rods(positions) == ()


def test_spherical_pendulum_is_shown_from_the_side_and_from_above():
    system = lg.load("spherical_pendulum")
    run = system.simulate(t_end=1.0, n_out=2001)
    view, plan = mechanism_view(run, system)
    image = view.render(10)[..., :3].astype(int)
    assert [ax.get_title() for ax in view.axes] == [
        "side view ($x$-$z$)",
        "top view ($x$-$y$)",
    ]
    theta = np.interp(plan.times[10], run.t, run["theta"])
    phi = np.interp(plan.times[10], run.t, run["phi"])
    bob = np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), -np.cos(theta)])
    found = np.argwhere(color_mask(image, "C0"))
    for ax, (a, b) in zip(view.axes, ((0, 2), (0, 1)), strict=True):
        row, column = pixel_of(ax, bob[a], bob[b], image.shape[0])
        here = found[np.hypot(found[:, 0] - row, found[:, 1] - column) < 12]
        assert len(here) > 30
        assert np.allclose(here.mean(axis=0), (row, column), atol=1.0)


def test_springs_zigzag_and_bodies_are_bars():
    system = spring_bar_and_bob()
    run = system.simulate(t_end=1.0, n_out=2001)
    view, plan = mechanism_view(run, system)
    view.update(5)
    panel = view._panels[0]
    (spring,) = panel["springs"]
    x, y = spring.get_data()
    bob_y = -np.interp(plan.times[5], run.t, run["y"])
    assert len(x) == 2 * 8 + 3 and (x[-1], y[-1]) == (0, 0)  # from the bob to the fixed end
    assert y[0] == pytest.approx(bob_y, abs=1e-3) and np.ptp(x) > 0  # zigzag across the axis
    (bar,) = panel["bodies"]
    x, y = bar.get_data()
    assert np.hypot(x[1] - x[0], y[1] - y[0]) == pytest.approx(0.6)  # L = sqrt(12 I / m)
    angle = np.interp(plan.times[5], run.t, run["phi"])
    assert np.arctan2(y[1] - y[0], x[1] - x[0]) == pytest.approx(np.angle(np.exp(1j * angle)))


def test_zigzag_runs_from_end_to_end():
    points = zigzag(np.array([0.0, 0.0]), np.array([2.0, 0.0]), coils=4, width=0.1)
    assert points.shape == (2, 4 * 2 + 3)
    assert tuple(points[:, 0]) == (0, 0) and tuple(points[:, -1]) == (2, 0)
    assert np.abs(points[1]).max() == pytest.approx(0.1)


def test_mp4_goes_through_ffmpeg(bob_pendulum, tmp_path, monkeypatch):
    """A stand-in ffmpeg that writes its arguments: the frames are piped, the file renamed."""
    import matplotlib

    fake = tmp_path / "bin" / "ffmpeg"
    fake.parent.mkdir()
    fake.write_text('#!/bin/sh\nfor last; do :; done\necho "$@" > "$last"\ncat > /dev/null\n')
    fake.chmod(0o755)
    monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path", str(fake))
    short = bob_pendulum.simulate(t_end=0.2, n_out=20)
    animate(short, bob_pendulum, tmp_path / "pendulum.mp4")
    arguments = (tmp_path / "pendulum.mp4").read_text()
    assert "-framerate 25" in arguments and "-f mp4" in arguments
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bin", "pendulum.mp4"]


SHAKEN = lg.System.from_particles(
    ["theta"],
    particles=[Particle("bob", "m", ("a*cos(w*t) + l*sin(theta)", "-l*cos(theta)"))],
    gravity=Gravity("g"),
    parameters={"m": 1.0, "l": 1.0, "g": 9.81, "a": 0.3, "w": 6.0},
)


def test_a_moving_support_is_the_pivot_of_the_rod():
    # the part of the position that depends on t alone is the support: drawn, with the rod
    scene = geometry(SHAKEN)
    t = np.linspace(0, 2, 80)
    positions = scene.at(t, np.stack([0.5 * np.sin(4 * t)]))
    np.testing.assert_allclose(positions.point(ORIGIN), [0.3 * np.cos(6 * t), 0 * t])
    assert rods(positions) == ((ORIGIN, 0),)
    assert geometry(lg.load("double_pendulum")).at(t, np.zeros((2, 80))).support is None


def test_the_moving_pivot_is_drawn_where_the_support_is():
    run = SHAKEN.simulate(t_end=1.0, initial={"theta": 0.5})
    view, plan = mechanism_view(run, SHAKEN)
    image = view.render(10)[..., :3].astype(int)
    t = plan.times[10]
    (panel,) = view._panels
    (pivot,) = panel["pivot"]
    assert pivot.get_xdata()[0] == pytest.approx(0.3 * np.cos(6 * t), abs=1e-2)
    row, column = pixel_of(view.axes[0], 0.3 * np.cos(6 * t), 0.0, image.shape[0])
    assert near(image, row, column, 2).min() < 200  # the pivot's ring is drawn there


def test_a_bead_is_drawn_on_its_hoop_or_wire_and_a_cart_on_its_rail():
    # a bead on a hoop of radius R = 1.5 turning at omega about the vertical: its distance
    # from the centre is constant, and it was drawn as a pendulum's rod from the origin
    hoop = lg.System.from_particles(
        ["theta"],
        [
            Particle(
                "bead", "m", ("R*sin(theta)*cos(w*t)", "R*sin(theta)*sin(w*t)", "-R*cos(theta)")
            )
        ],
        gravity=Gravity(g="g", direction=(0, 0, -1)),
        parameters={"m": 1.0, "R": 1.5, "g": 9.81, "w": 5.0},
        initial={"theta": 0.5},
    )
    view, plan = mechanism_view(hoop.simulate(t_end=1.0), hoop)
    (curve,) = view.tracks  # (3, points, frames): the whole hoop at every frame
    assert curve.shape[2] == plan.frames
    assert np.allclose(np.linalg.norm(curve, axis=0), 1.5)
    assert view.rods == ()
    # the wire turning at omega = 1 through the origin, the bead on it at every frame
    wire = lg.load("rotating_wire_bead")
    run = wire.simulate(t_end=2.0)
    view, plan = mechanism_view(run, wire)
    (curve,) = view.tracks
    angle = plan.times  # omega t
    across = curve[0] * np.sin(angle) - curve[1] * np.cos(angle)
    assert np.abs(across).max() < 1e-9
    middle = curve[:, curve.shape[1] // 2, :]
    (r,) = resample(run, plan.times)  # the frames' r, as the bead is drawn at them
    assert np.allclose(middle, [r * np.cos(angle), r * np.sin(angle)], atol=1e-12)
    # a pendulum keeps its rod and has no hoop; the cart-pole's cart runs on y = 0
    assert (
        mechanism_view(lg.load("simple_pendulum").simulate(t_end=1.0), lg.load("simple_pendulum"))[
            0
        ].tracks
        == ()
    )
    cart_pole = lg.load("cart_pole")
    view, _ = mechanism_view(cart_pole.simulate(t_end=1.0), cart_pole)
    (rail,) = view.tracks
    assert np.all(rail[1] == 0) and view.rods == ((0, 1),)

"""The linkage drawing: links from start to end, joints, ground pins, reaction arrows."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.cli import ExitStatus, main
from lagrangian.output.animation import mechanism_view
from lagrangian.output.linkage_drawing import ARROW_COLOR, linkage_frames, links_as_bars
from lagrangian.trajectory import Trajectory


@pytest.fixture(scope="module")
def four_bar():
    """The four-bar example with a made-up motion (no derivation: the drawing reads the
    coordinates and the reaction columns as they are)."""
    system = lg.load("four_bar")
    t = np.linspace(0.0, 1.0, 21)
    q = np.stack([1.0 + t, 0.6 + 0.1 * t, 1.5 - 0.2 * t])
    reactions = {f"R_{j}_{x}": (k + 1) * np.cos(t + k) for k, (j, x) in
                 enumerate((j, x) for j in "ABDC" for x in "xy")}  # fmt: skip
    run = Trajectory.build(
        t=t,
        coordinates=system.coordinate_names,
        y=np.concatenate([q, np.zeros_like(q)]),
        energy=np.zeros_like(t),
        reactions=reactions,
        system=system,
    )
    return system, run, q


def test_links_are_drawn_from_start_to_end_with_their_joints_and_pins(four_bar):
    system, run, q = four_bar
    values = {p.name: p.default for p in system.parameters}
    frames = linkage_frames(system, run, run.t, q, values, reactions=True)
    a, b, c, d = (values[k] for k in "abcd")
    crank, coupler, rocker = q
    assert np.allclose(frames.ends[0, 0], 0.0)
    assert np.allclose(frames.ends[0, 1], [a * np.cos(crank), a * np.sin(crank)])
    assert np.allclose(
        frames.ends[1, 1] - frames.ends[1, 0], [b * np.cos(coupler), b * np.sin(coupler)]
    )
    assert np.allclose(frames.ends[2, 0], [[d], [0.0]])
    assert np.allclose(frames.ends[2, 1], [d + c * np.cos(rocker), c * np.sin(rocker)])
    assert np.allclose(frames.ground, [[0.0, 0.0], [d, 0.0]])
    assert frames.joints.shape == (4, 2, 21)
    assert np.allclose(frames.joints[1], frames.ends[1, 0])  # B: the coupler's start
    names = [j.name for j in system.linkage.joints]
    for k, joint in enumerate(names):
        assert np.allclose(frames.forces[k, 0], run[f"R_{joint}_x"])
        assert np.allclose(frames.forces[k, 1], run[f"R_{joint}_y"])


def test_reaction_arrows_are_drawn_on_request(four_bar):
    system, run, _ = four_bar
    red = tuple(int(ARROW_COLOR[i : i + 2], 16) for i in (1, 3, 5))

    def reddish(image):
        pixels = image[..., :3].astype(int)
        return int(np.sum(np.all(np.abs(pixels - red) < 40, axis=-1)))

    plain, _ = mechanism_view(run, system, max_frames=5, size=3.0, dpi=60)
    arrows, _ = mechanism_view(run, system, max_frames=5, size=3.0, dpi=60, reactions=True)
    assert reddish(plain.render(2)) == 0
    assert reddish(arrows.render(2)) > 20


def test_animate_reactions_on_a_model_without_linkage_is_refused(capsys, tmp_path):
    status = main(["animate", "simple_pendulum", "--t-end", "0.1", "--reactions",
                   "--out", str(tmp_path / "p.gif")])  # fmt: skip
    err = capsys.readouterr().err.strip()
    assert status == ExitStatus.BAD_INPUT
    assert err == (
        "lagrangian: error: --reactions: the model has no joint reactions to draw (no "
        "[[links]] and [[joints]], or other masses move with them)"
    )
    assert not (tmp_path / "p.gif").exists()


def test_the_page_draws_each_link_as_the_bar_from_its_start_to_its_end():
    """The page's planar bodies are bars of length sqrt(12 I / m) through their centres:
    the slider-crank's flywheel crank (centre at the pivot, I = 0.05) is drawn as the bar
    from the pivot to the crank pin instead."""
    system = lg.load("slider_crank")
    drawn = links_as_bars(system)
    values = {p.symbol: p.default for p in system.parameters}
    crank = next(b for b in drawn.bodies if b.name == "crank")
    theta = next(c.q for c in system.coordinates if c.name == "theta")
    r, m = values[next(p.symbol for p in system.parameters if p.name == "r")], 2.0
    assert float(crank.inertia.xreplace(values)) == pytest.approx(m * r**2 / 12)
    centre = [float(x.xreplace(values | {theta: 0.7})) for x in crank.center]
    assert centre == pytest.approx([r / 2 * np.cos(0.7), r / 2 * np.sin(0.7)])
    original = next(b for b in system.bodies if b.name == "crank")
    assert float(original.inertia.xreplace(values)) == pytest.approx(0.05)  # the model's own
    assert links_as_bars(lg.load("double_pendulum")).bodies == ()


@pytest.mark.slow  # derives and analyzes the slider-crank (seconds)
def test_the_page_starts_a_linkage_on_its_loop():
    """The page's own integrator starts from document["initial"]: the slider-crank's held
    crank angle with x and phi solved onto the loop (from the file's guesses, which are
    off it), as simulate starts it."""
    from lagrangian.output.page_content import page_content

    state = page_content(lg.load("slider_crank")).document["initial"]
    r, rod, theta = 0.1, 0.4, 0.5
    assert state["theta"] == theta and state["theta_dot"] == 20.0
    assert state["x"] == pytest.approx(
        r * np.cos(theta) + np.sqrt(rod**2 - r**2 * np.sin(theta) ** 2), abs=1e-12
    )
    assert state["phi"] == pytest.approx(np.arcsin(-r * np.sin(theta) / rod), abs=1e-12)

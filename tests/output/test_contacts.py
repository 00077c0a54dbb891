"""The contacts drawn: the wall or floor of an affine gap, and impacts marked on plots."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.model.impacts import Impact
from lagrangian.output.contacts import contact_lines


@pytest.mark.parametrize(
    "name, normal, offset",
    [("bouncing_ball", [0.0, 1.0], 0.0), ("impact_oscillator", [-1.0, 0.0], 0.5)],
)
def test_an_affine_gap_in_a_particles_position_is_a_line(name, normal, offset):
    system = lg.load(name)
    ((a, c),) = contact_lines(system, system.parameter_values)
    np.testing.assert_allclose(a, normal)
    assert c == pytest.approx(offset)


def test_a_gap_between_two_particles_has_no_fixed_line():
    system = lg.System.from_particles(
        coordinates=["x1", "x2"],
        particles=(lg.Particle("a", "m", ("x1", "0")), lg.Particle("b", "m", ("x2", "0"))),
        parameters={"m": 1.0, "r": 0.1},
        impacts=(Impact(gap="x2 - x1 - 2*r", restitution="1"),),
        initial={"x2": 1.0},
    )
    assert contact_lines(system, system.parameter_values) == []


def test_the_timeseries_marks_every_impact():
    from lagrangian.output.plots import plot_timeseries

    trajectory = lg.load("bouncing_ball").simulate(t_end=3.0)
    figure = plot_timeseries(trajectory)
    times = [r.t for r in trajectory.impacts]
    assert len(times) == 4
    for ax in figure.axes:
        marks = [line.get_xdata()[0] for line in ax.lines if line.get_linestyle() == ":"]
        np.testing.assert_allclose(marks, times)


def test_the_animation_draws_the_floor_where_the_gap_closes():
    from lagrangian.output.animation import mechanism_view
    from lagrangian.output.contacts import WALL_COLOR

    system = lg.load("bouncing_ball")
    view, _ = mechanism_view(system.simulate(t_end=1.0), system)
    image = view.render(10)[..., :3].astype(int)
    wall = np.array([int(WALL_COLOR[k : k + 2], 16) for k in (1, 3, 5)])
    ax = view.axes[0]
    for x in (0.0, 0.2):  # on the line y = 0, across the picture
        column, up = ax.transData.transform((x, 0.0))
        row = image.shape[0] - up
        patch = image[int(row) - 2 : int(row) + 3, int(column)]
        assert np.abs(patch - wall).sum(axis=1).min() < 40
    column, up = ax.transData.transform((0.2, 0.5))  # nothing drawn above the floor there
    assert np.all(image[image.shape[0] - int(up), int(column)] > 200)


@pytest.mark.slow
def test_the_page_says_that_its_motion_passes_through_the_contacts():
    from lagrangian.output.page import page_html

    html = page_html(lg.load("bouncing_ball"))
    assert "The contacts (floor) are not simulated in this page" in html
    assert "are not simulated in this page" not in page_html(lg.load("harmonic_oscillator"))

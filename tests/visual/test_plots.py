"""Plots checked for content: the curves are where the physics puts them, labels, scales."""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.output.display import trajectory_html
from lagrangian.output.mode_shapes import plot_normal_modes
from lagrangian.output.phase import (
    SEPARATRIX_COLOR,
    angle_coordinates,
    phase_family,
    plot_phase_portrait,
)
from lagrangian.output.plots import plot_energy_error, plot_timeseries, save_figure
from lagrangian.output.poincare import plot_poincare, poincare_points, section_event
from visual.pictures import color_mask, near, pixel_of, pixels

G = 9.81


@pytest.fixture(scope="module")
def pendulum():
    return lg.load("simple_pendulum")


@pytest.fixture(scope="module")
def pendulum_run(pendulum):
    return pendulum.simulate(t_end=5.0, n_out=1001)


@pytest.fixture(scope="module")
def portrait(pendulum):
    family = phase_family(pendulum, t_end=3.0, n_out=600)
    figure = plot_phase_portrait(family, pendulum)
    return family, figure, pixels(figure)


def not_blank(image: np.ndarray) -> None:
    assert image.std() > 20
    assert (np.abs(image - 255).sum(axis=-1) > 60).mean() > 0.01  # more than a frame of ink


def test_time_series_shows_each_coordinate_and_velocity(pendulum, pendulum_run):
    figure = plot_timeseries(pendulum_run, pendulum)
    image = pixels(figure)
    not_blank(image)
    assert color_mask(image, "C0").sum() > 300 and color_mask(image, "C1").sum() > 300
    left, right = figure.axes
    assert left.get_ylabel() == r"$\theta$" and right.get_ylabel() == r"$\dot{\theta}$"
    assert figure.get_suptitle() == "Simple pendulum: time series"
    # the curve passes through its data: the first sample, theta(0) = 1
    row, column = pixel_of(left, 0.0, 1.0, image.shape[0])
    assert color_mask(near(image, row, column, 2)[None], "C0").any()


def test_energy_error_is_relative_and_on_a_log_axis(pendulum, pendulum_run):
    figure = plot_energy_error(pendulum_run, pendulum)
    ax = figure.axes[0]
    assert ax.get_yscale() == "log"
    assert ax.get_ylabel() == r"$|X(t) - X(0)|\,/\,|X(0)|$"
    energy = pendulum_run["energy"]
    expected = np.abs(energy - energy[0]) / abs(energy[0])
    curve = ax.get_lines()[0].get_ydata()
    shown = np.isfinite(curve)
    assert np.allclose(curve[shown], expected[shown]) and np.all(expected[~shown] == 0)
    assert "energy $h$, dop853, rtol = 1e-10" in [t.get_text() for t in ax.get_legend().texts]
    not_blank(pixels(figure))


def test_phase_portrait_of_the_pendulum_has_its_separatrix(portrait):
    _, figure, image = portrait
    ax = figure.axes[0]
    (separatrix,) = [c for c in ax.collections if c.get_gid() == "separatrix"]
    assert separatrix.levels == pytest.approx([2 * 1.0 * G * 1.0])  # h = 2 m g l
    red = color_mask(image, SEPARATRIX_COLOR, tolerance=20)
    # on the separatrix h = 2 m g l: theta_dot = sqrt(2 g (1 + cos theta)) (m = l = 1)
    for theta in (0.0, np.pi / 2, -2.0):
        speed = np.sqrt(2 * G * (1 + np.cos(theta)))
        for sign in (1, -1):
            row, column = pixel_of(ax, theta, sign * speed, image.shape[0])
            assert red[round(row) - 3 : round(row) + 4, round(column) - 3 : round(column) + 4].any()
    assert any("separatrix" in t.get_text() for t in ax.get_legend().texts)


def test_phase_family_lies_below_and_above_the_separatrix(portrait):
    family, figure, _ = portrait
    energies = sorted({round(run["energy"][0], 6) for run in family})
    assert sum(e < 2 * G for e in energies) >= 3 and sum(e > 2 * G for e in energies) >= 2
    for run in family:  # each run keeps its energy, so each curve is one level set
        assert np.ptp(run["energy"]) < 1e-6 * max(1.0, abs(run["energy"][0]))
    ax = figure.axes[0]
    labels = [line.get_label() for line in ax.get_lines() if line.get_label().startswith("$h$")]
    assert len(labels) == len(energies)
    assert ax.get_xlabel() == r"$\theta$" and ax.get_ylabel() == r"$\dot{\theta}$"
    assert ax.get_xlim() == pytest.approx((-np.pi, np.pi))  # the angle is wrapped


def test_angles_are_found_by_periodicity():
    assert angle_coordinates(lg.load("double_pendulum")) == {"theta1", "theta2"}
    assert angle_coordinates(lg.load("spherical_pendulum")) == {"theta", "phi"}
    assert angle_coordinates(lg.load("central_force")) == {"theta"}
    assert angle_coordinates(lg.load("harmonic_oscillator")) == set()


TWO_OSCILLATORS = """
name = "Two oscillators"
coordinates = ["x", "y"]
lagrangian = "(x_dot^2 + y_dot^2)/2 - (x^2 + w^2*y^2)/2"

[parameters]
w = 1.4142135623730951

[initial]
x_dot = 1.0
y = 1.0
"""


def test_poincare_section_of_two_oscillators_is_exact():
    """x = sin t crosses 0 upwards at t = 2 pi k, where y = cos(w t), y' = -w sin(w t)."""
    system = lg.loads(TWO_OSCILLATORS)
    w = np.sqrt(2)
    k = np.arange(1, 7)
    expected = np.stack([np.cos(w * 2 * np.pi * k), -w * np.sin(w * 2 * np.pi * k)])
    run = system.simulate(t_end=40.0, events=[section_event(system)])
    points = poincare_points(run)
    assert points.shape == (4, 6)
    assert np.allclose(points[0], 0, atol=1e-9) and np.all(points[2] > 0)
    assert np.allclose(points[[1, 3]], expected, atol=1e-7)
    sampled = poincare_points(system.simulate(t_end=40.0, n_out=8001))  # no events: samples
    assert np.allclose(sampled[[1, 3]], expected, atol=2e-3)
    figure = plot_poincare(run, system)
    ax = figure.axes[0]
    assert np.allclose(ax.get_lines()[0].get_xydata().T, expected, atol=1e-7)
    assert ax.get_xlabel() == "$y$" and ax.get_ylabel() == r"$\dot{y}$"
    assert "Poincaré section $x = 0$, $\\dot{x} > 0$ (6 points)" in figure.get_suptitle()
    image = pixels(figure)
    for y, y_dot in expected.T:
        row, column = pixel_of(ax, y, y_dot, image.shape[0])
        assert color_mask(near(image, row, column, 1)[None], "C0").any()


@pytest.mark.slow
def test_normal_modes_of_the_double_pendulum():
    """Unit masses and lengths: omega^2 = g (2 -+ sqrt 2), shapes (1, +-sqrt 2)."""
    figure = plot_normal_modes(lg.load("double_pendulum"), {"theta1": 0, "theta2": 0})
    titles = [ax.get_title() for ax in figure.axes]
    for title, sign in zip(titles, (-1, 1), strict=True):
        omega = np.sqrt(G * (2 + sign * np.sqrt(2)))
        assert f"$\\omega$ = {omega:.4g}" in title
        assert f"shape (1, {-sign * np.sqrt(2):.3g})" in title
    not_blank(pixels(figure))


@pytest.mark.slow
def test_normal_modes_about_an_equilibrium_stable_apart_from_a_free_translation(tmp_path):
    """The hanging cart-pole: no equilibrium is stable (the cart's translation is free),
    and plot --kind modes refused ('no stable equilibrium'); drawn about theta = pi, the
    translation named, the pendulum's mode at omega^2 = g (M + m) / (M l)."""
    from lagrangian.cli import ExitStatus, main

    system = lg.load("cart_pole")
    figure = plot_normal_modes(system)
    assert "$\\theta$ = 3.14 (stable apart from its free motion)" in figure.get_suptitle()
    free, swing = (ax.get_title() for ax in figure.axes)
    assert free == (
        "mode 1: $\\omega^2$ = 0, free motion:\n"
        "translation of all particles along x (L is invariant)"
    )
    values = system.parameter_values
    omega = np.sqrt(G * (values["M"] + values["m"]) / (values["M"] * values["l"]))
    assert f"$\\omega$ = {omega:.4g}" in swing
    out = tmp_path / "modes.png"
    assert main(["plot", "cart_pole", "--kind", "modes", "--out", str(out)]) == ExitStatus.SUCCESS
    assert out.read_bytes().startswith(b"\x89PNG")


def test_a_constrained_pendulums_mode_is_drawn_on_its_circle():
    # the mode shape (1, 0) is tangent to x^2 + y^2 = l^2 at the bottom: each drawn phase is
    # brought back onto the circle (q0 + A s cos(phi) alone stretched the rod by 3%)
    figure = plot_normal_modes(lg.load("cartesian_pendulum"))  # l = 1, g = 9.81
    (ax,) = figure.axes
    assert f"$\\omega$ = {np.sqrt(G):.4g}" in ax.get_title()
    bobs = [
        (x, y)
        for line in ax.lines
        if line.get_marker() == "o"
        for x, y in zip(line.get_xdata(), line.get_ydata(), strict=True)
        if (x, y) != (0, 0)  # the pivot
    ]
    radii = np.hypot(*np.array(bobs, dtype=float).T)
    assert len(bobs) >= 5 and np.allclose(radii, 1.0, atol=1e-12)
    assert np.ptp([x for x, _ in bobs]) > 0.3  # and it swings


def test_the_title_of_a_single_mode_fits_its_figure():
    # one panel, "Spherical pendulum: normal modes about θ = 0, φ = 0": its ends were cut
    figure = plot_normal_modes(lg.load("spherical_pendulum"))
    figure.canvas.draw()
    box = figure._suptitle.get_window_extent()
    assert box.x0 >= 0 and box.x1 <= figure.bbox.width, (box, figure.bbox)


def test_normal_modes_without_geometry_are_bars():
    figure = plot_normal_modes(lg.load("harmonic_oscillator"), {"x": 0})
    (ax,) = figure.axes
    assert "$\\omega$ = 1," in ax.get_title() and len(ax.patches) == 1


def test_save_figure_is_atomic(pendulum_run, tmp_path, monkeypatch):
    figure = plot_timeseries(pendulum_run)
    path = save_figure(figure, tmp_path / "series.png")
    assert path.read_bytes().startswith(b"\x89PNG")

    def broken(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(figure, "savefig", broken)
    with pytest.raises(RuntimeError):
        save_figure(figure, tmp_path / "other.png")
    assert [p.name for p in tmp_path.iterdir()] == ["series.png"]
    with pytest.raises(lg.ModelError, match=r"use \.png, \.pdf or \.svg"):
        save_figure(figure, tmp_path / "series.jpg2")


def test_trajectory_html_summary(pendulum_run):
    page = trajectory_html(pendulum_run)
    assert page.startswith('<table class="lagrangian-trajectory">')
    for text in (
        "Simple pendulum",
        "dop853, rtol = 1e-10",
        r"$\dot{\theta}(t_{end})$",
        "drift of energy $h$",
        "1001 samples",
    ):
        assert text in page


def test_trajectory_html_says_the_energy_is_not_conserved_and_why(pendulum_run):
    pendulum_run.dataset.attrs["energy_not_conserved"] = "dissipation"
    try:
        page = trajectory_html(pendulum_run)
    finally:
        del pendulum_run.dataset.attrs["energy_not_conserved"]
    assert "drift of energy" not in page
    assert "change of energy $h$, not conserved" in page and "(dissipation)" in page

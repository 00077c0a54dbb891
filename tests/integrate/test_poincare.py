"""Poincaré sections (integrate/section.py, integrate/poincare.py) against analytic facts."""

from __future__ import annotations

import math

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import LagrangianWarning, ModelError
from lagrangian.integrate.section import parse_section
from lagrangian.numeric import compile_equations


def test_henon_heiles_points_lie_on_the_section_and_the_energy_surface():
    points = lg.load("henon_heiles").poincare(
        section="x = 0", axes=("y", "p_y"), energy=1 / 8, orbits=3, t_end=60
    )
    assert points.orbit_count == 3 and points.count > 20
    assert set(points.orbits) == {0, 1, 2}
    np.testing.assert_allclose(points["x"], 0.0, atol=1e-10)  # located on the section
    assert np.all(points["x_dot"] > 0)  # crossing upwards
    # h = (x'^2 + y'^2)/2 + (x^2 + y^2)/2 + x^2 y - y^3/3, written out here
    x, y, vx, vy = (points[name] for name in ("x", "y", "x_dot", "y_dot"))
    energy = (vx**2 + vy**2) / 2 + (x**2 + y**2) / 2 + x**2 * y - y**3 / 3
    np.testing.assert_allclose(energy, 1 / 8, rtol=0, atol=1e-8)
    np.testing.assert_array_equal(points["p_y"], points["y_dot"])  # p_y = y' here
    start = points.starts[:, 0]  # the starts are on the section and the shell too
    assert start[0] == 0.0 and start[3] == 0.0
    assert start[2] ** 2 / 2 + start[1] ** 2 / 2 - start[1] ** 3 / 3 == pytest.approx(1 / 8)


def test_separable_oscillator_points_lie_on_the_analytic_invariant_curves():
    # L = (x'^2 + y'^2)/2 - (x^2 + w^2 y^2)/2: E_y = (y'^2 + w^2 y^2)/2 is conserved
    # on its own, so each orbit's points on x = 0 lie on the ellipse of its start's E_y
    w = math.sqrt(2.0)
    system = lg.System.from_lagrangian(
        "(x_dot**2 + y_dot**2)/2 - (x**2 + w**2*y**2)/2",
        coordinates=["x", "y"],
        parameters={"w": w},
    )
    points = system.poincare(
        section="x = 0", axes=("y", "y_dot"), energy=1.0, orbits=4, t_end=60, rtol=1e-11
    )
    assert points.count > 4 * 8
    for k in range(4):
        start = points.starts[:, k]
        ellipse = (start[3] ** 2 + w**2 * start[1] ** 2) / 2
        mine = points.orbits == k
        on_curve = (points["y_dot"][mine] ** 2 + w**2 * points["y"][mine] ** 2) / 2
        np.testing.assert_allclose(on_curve, ellipse, rtol=1e-8, atol=1e-10)
        np.testing.assert_allclose(points["x_dot"][mine], math.sqrt(2 * (1.0 - ellipse)), rtol=1e-7)


def test_strobe_of_a_driven_damped_oscillator_is_its_steady_state():
    # x'' + b x' + x = A cos(omega t): after the transient x = R cos(omega t - phi)
    b, drive, omega = 0.5, 0.8, 1.3
    system = lg.System.from_lagrangian(
        "x_dot**2/2 - x**2/2", coordinates=["x"], forces={"x": "A*cos(omega*t) - b*x_dot"},
        parameters={"A": drive, "omega": omega, "b": b},
    )  # fmt: skip
    period = 2 * math.pi / omega
    points = system.poincare(strobe=period, transient=80.0, axes=("x", "x_dot"), t_end=120)
    np.testing.assert_allclose(np.diff(points.times), period, rtol=1e-12)
    # at whole periods from t = 0 (phase 0), the first one after the transient
    assert points.times[0] == pytest.approx(period * math.ceil(80.0 / period))
    assert points.settings["phase"] == 0.0
    amplitude = drive / math.hypot(1 - omega**2, b * omega)
    phase = math.atan2(b * omega, 1 - omega**2)
    angle = omega * points.times - phase
    np.testing.assert_allclose(points["x"], amplitude * np.cos(angle), atol=1e-8)
    np.testing.assert_allclose(points["x_dot"], -amplitude * omega * np.sin(angle), atol=1e-8)


def test_spread_starts_and_momentum_axes():
    points = lg.load("double_pendulum").poincare(
        section="theta1 = 0", axes=("theta2", "p_theta2"), spread={"theta2": (0.1, 0.3)},
        orbits=2, t_end=8,
    )  # fmt: skip
    np.testing.assert_allclose(points.starts[1], [0.1, 0.3])
    assert points.variables[-1] == "p_theta2"
    # p_theta2 = m2 l2 (l1 theta1' cos(theta1 - theta2) + l2 theta2'), unit masses and rods
    t1, t2, v1, v2 = (points[n] for n in ("theta1", "theta2", "theta1_dot", "theta2_dot"))
    np.testing.assert_allclose(points["p_theta2"], v1 * np.cos(t1 - t2) + v2, rtol=1e-12)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("x == 0", "a section is 'expression = expression' with one '='"),
        ("x", "a section is 'expression = expression' with one '='"),
        ("x = 2*zz", "unknown symbol 'zz' at position 7 in 'x = 2*zz'"),
        ("lam = 1", "depends on no coordinate or velocity"),
        ("__import__('os') = 0", "section"),
        ("x = (", "section"),
    ],
)
def test_section_text_errors_are_one_line(text, message):
    compiled = compile_equations(lg.load("henon_heiles").equations_of_motion())
    with pytest.raises(ModelError) as error:
        parse_section(compiled, text)
    assert message in str(error.value)
    assert "\n" not in str(error.value)


def test_energy_below_the_section_is_an_error():
    with pytest.raises(ModelError, match="below the energy of the section's start"):
        lg.load("henon_heiles").poincare(
            section="x = 0", axes=("y", "p_y"), energy=-1.0, t_end=1, initial={"y": 0.0}
        )


def test_files_hold_the_points(tmp_path):
    import xarray

    points = lg.load("henon_heiles").poincare(
        section="x = 0", axes=("y", "p_y"), energy=1 / 12, orbits=2, t_end=20
    )
    points.save(tmp_path / "points.csv")
    table = np.loadtxt(tmp_path / "points.csv", delimiter=",", skiprows=1)
    header = (tmp_path / "points.csv").read_text().splitlines()[0]
    assert header == "orbit,t,x,y,x_dot,y_dot,p_y,energy"
    np.testing.assert_array_equal(table, points.table())
    points.save(tmp_path / "points.nc")
    with xarray.open_dataset(tmp_path / "points.nc", engine="scipy") as dataset:
        np.testing.assert_array_equal(dataset["y"].values, points["y"])
        assert dataset.attrs["section"] == "x = 0"
    with pytest.raises(ModelError, match=r"\.csv or \.nc"):
        points.save(tmp_path / "points.txt")


def test_a_section_keeps_only_the_crossings_after_the_transient():
    # x = cos t crosses x = 0 upwards at t = 3 pi/2 + 2 pi k; a transient of 5 drops the first
    system = lg.load("harmonic_oscillator")
    every = system.poincare(section="x = 0", axes=("x", "x_dot"), t_end=20)
    later = system.poincare(section="x = 0", axes=("x", "x_dot"), t_end=20, transient=5.0)
    upward = 1.5 * math.pi + 2 * math.pi * np.arange(3)
    np.testing.assert_allclose(every.times, upward, rtol=1e-9)
    np.testing.assert_allclose(later.times, upward[1:], rtol=1e-9)
    assert later.settings["transient"] == 5.0


@pytest.mark.parametrize("transient", [-100.0, math.nan, math.inf])
@pytest.mark.parametrize("where", ["section", "strobe"])
def test_a_transient_that_is_no_time_ahead_is_refused(transient, where):
    # -100 integrated backwards first (meaningless points, exit 0), nan raised ValueError
    system = lg.load("harmonic_oscillator")
    place = {"section": "x = 0"} if where == "section" else {"strobe": 1.0}
    refused = r"^the transient must be a time >= 0, not (-100|nan|inf)$"
    with pytest.raises(ModelError, match=refused):
        system.poincare(axes=("x", "x_dot"), t_end=5, transient=transient, **place)


def test_a_transient_as_long_as_the_run_is_refused():
    with pytest.raises(ModelError, match=r"^the transient \(20\) leaves no time before t_end = 20"):
        lg.load("harmonic_oscillator").poincare(
            section="x = 0", axes=("x", "x_dot"), t_end=20, transient=20
        )


def test_a_section_never_crossed_is_said():
    # x = cos t never reaches 2: no points, and a warning rather than a silent empty result
    with pytest.warns(LagrangianWarning) as caught:
        points = lg.load("harmonic_oscillator").poincare(
            section="x = 2", direction="both", axes=("x", "x_dot"), t_end=20, transient=1
        )
    assert points.count == 0
    assert [str(w.message) for w in caught] == [
        "the orbit does not cross the section x = 2 (direction both) between t = 1 and 20: "
        "no points"
    ]

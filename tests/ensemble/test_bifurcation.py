"""Bifurcation diagrams (ensemble/bifurcation.py) against analytic and published results."""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.errors import ModelError


@pytest.mark.slow
def test_linear_oscillator_has_one_point_per_value_its_steady_state():
    # x'' + b x' + x = A cos(omega t): after the transient x(t_k) = R cos(omega t_k - phi),
    # R = A / sqrt((1 - omega^2)^2 + (b omega)^2): one point per drive, growing with it
    b, omega = 0.6, 1.3
    system = lg.System.from_lagrangian(
        "x_dot**2/2 - x**2/2", coordinates=["x"], forces={"x": "A*cos(omega*t) - b*x_dot"},
        parameters={"A": 1.0, "omega": omega, "b": b},
    )  # fmt: skip
    drives = np.linspace(0.2, 1.0, 5)
    period = 2 * math.pi / omega
    diagram = system.bifurcation(
        vary={"A": drives}, variable="x", period=period, transient=60.0, samples=4
    )
    assert diagram.points.shape == (5, 4)
    np.testing.assert_allclose(diagram.values, drives)
    assert diagram.settings["transient"] == 60.0 and diagram.settings["phase"] == 0.0
    # the first whole period after the transient, then every period
    assert diagram.times[0] == pytest.approx(period * math.ceil(60.0 / period))
    np.testing.assert_allclose(np.diff(diagram.times), period, rtol=1e-12)
    phase = math.atan2(b * omega, 1 - omega**2)
    amplitude = drives / math.hypot(1 - omega**2, b * omega)
    expected = amplitude[:, None] * np.cos(omega * diagram.times[None, :] - phase)
    np.testing.assert_allclose(diagram.points, expected, atol=1e-7)
    table = diagram.table()
    assert table.shape == (20, 3) and table[4, 0] == drives[1]


# J. R. Taylor, Classical Mechanics (University Science Books, 2005), section 12.5:
# phi'' + 2 beta phi' + w0^2 sin(phi) = gamma w0^2 cos(w t) with w = 2 pi, w0 = 1.5 w,
# beta = w0 / 4, from phi(0) = -pi/2 at rest
TAYLOR_W0 = 3 * math.pi
TAYLOR = {
    "variable": "theta", "period": 1.0, "steps_per_period": 150,
    "params": {"g": TAYLOR_W0**2, "b": TAYLOR_W0 / 2, "omega": 2 * math.pi},
    "initial": {"theta": -math.pi / 2},
}  # fmt: skip
#: The compiled loop where numba is installed: the same rk4 steps as the numpy backend's
#: (test_strobe_diagram_is_the_same_on_the_numba_backend), 38,000 of them in 0.1 s, not 24 s
#: of CPU; its one compile is the README's bifurcation line's too.
FAST = "numba" if importlib.util.find_spec("numba") else "numpy"


@pytest.mark.slow
def test_driven_pendulum_doubles_its_period_as_published():
    # period 1 at gamma = 1.060, period 2 at 1.078, period 4 at 1.081 (Taylor's
    # Figs. 12.8-12.10 and his table of thresholds)
    diagram = lg.load("driven_damped_pendulum").bifurcation(
        vary={"A": np.array([1.060, 1.078, 1.081]) * TAYLOR_W0**2}, transient=250, samples=8,
        backend=FAST, **TAYLOR,
    )  # fmt: skip
    assert diagram.settings["backend"] == FAST
    periods = [len(np.unique(np.round(row, 4))) for row in diagram.points]
    assert periods == [1, 2, 4]


@pytest.mark.slow
def test_strobe_diagram_is_the_same_on_the_numba_backend():
    pytest.importorskip("numba")
    settings = {
        "vary": {"A": np.array([1.060, 1.078, 1.081]) * TAYLOR_W0**2}, "transient": 3,
        "samples": 4, **TAYLOR,
    }  # fmt: skip
    pendulum = lg.load("driven_damped_pendulum")
    ours = pendulum.bifurcation(backend="numpy", **settings)
    theirs = pendulum.bifurcation(backend="numba", **settings)
    assert theirs.settings["backend"] == "numba"
    np.testing.assert_array_equal(theirs.times, ours.times)
    np.testing.assert_allclose(theirs.points, ours.points, rtol=1e-9, atol=1e-12)


def _driven_oscillator(b: float, omega: float):
    return lg.System.from_lagrangian(
        "x_dot**2/2 - x**2/2", coordinates=["x"], forces={"x": "A*cos(omega*t) - b*x_dot"},
        parameters={"A": 1.0, "omega": omega, "b": b},
    )  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize(("direction", "sign"), [("+", 1.0), ("-", -1.0)])
def test_section_of_a_linear_oscillator_holds_its_steady_velocity_where_x_is_zero(direction, sign):
    # x'' + b x' + x = A cos(omega t): after the transient x = R cos(omega t - phi), so x
    # crosses 0 upwards where omega t - phi = -pi/2 (mod 2 pi), with x' = R omega, and
    # downwards where it is +pi/2, with x' = -R omega; one point per drive, every period
    b, omega = 0.6, 1.3
    drives = np.linspace(0.2, 1.0, 5)
    period = 2 * math.pi / omega
    diagram = _driven_oscillator(b, omega).bifurcation(
        vary={"A": drives}, variable="x_dot", section="x = 0", direction=direction,
        transient=60.0, t_end=3.5 * period, samples=5, dt=period / 200,
    )  # fmt: skip
    amplitude = drives / math.hypot(1 - omega**2, b * omega)
    assert diagram.points.shape == diagram.times.shape == (5, 5)
    found = np.isfinite(diagram.points)
    assert found[:, :3].all() and not found[:, 4].any()  # 3 or 4 crossings in 3.5 periods
    assert np.all(diagram.times[found] > 60.0)
    expected = np.broadcast_to(sign * amplitude[:, None] * omega, diagram.points.shape)
    np.testing.assert_allclose(diagram.points[found], expected[found], rtol=1e-7)
    phase = math.atan2(b * omega, 1 - omega**2)
    angle = omega * diagram.times[found] - phase
    np.testing.assert_allclose(np.sin(angle), -sign, atol=1e-12)
    np.testing.assert_allclose(np.cos(angle), 0.0, atol=1e-7)
    np.testing.assert_allclose(np.diff(diagram.times[0, :3]), period, rtol=1e-7)
    assert diagram.settings["section"] == "x = 0" and diagram.settings["direction"] == direction
    assert diagram.table().shape == (int(found.sum()), 3)  # the missing crossings left out


@pytest.mark.slow
def test_section_diagram_is_the_same_on_the_numba_backend():
    pytest.importorskip("numba")
    b, omega = 0.3, 0.9
    settings = {
        "vary": {"A": np.linspace(0.5, 1.5, 4)}, "variable": "x_dot", "section": "x = 0.1",
        "direction": "both", "transient": 20.0, "t_end": 20.0, "samples": 6, "dt": 0.02,
    }  # fmt: skip
    ours = _driven_oscillator(b, omega).bifurcation(backend="numpy", **settings)
    theirs = _driven_oscillator(b, omega).bifurcation(backend="numba", **settings)
    assert theirs.settings["backend"] == "numba"
    np.testing.assert_allclose(theirs.times, ours.times, rtol=1e-12)
    np.testing.assert_allclose(theirs.points, ours.points, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"variable": "phi"}, "'phi' is not a coordinate or velocity"),
        ({"vary": {"q": [1.0]}}, "unknown parameter 'q'"),
        ({"vary": {"A": [1.0], "b": [1.0]}}, "vary one parameter, not 2"),
        ({"period": -1.0}, "period must be a finite number > 0"),
        ({"samples": 0}, "samples must be a whole number >= 1"),
        ({"section": "theta = 0"}, "give a strobe period or a section (one of them)"),
        ({"period": None, "section": "theta = "}, "section"),
        ({"period": None, "section": "theta = 0", "direction": "up"}, "the direction must be"),
    ],
)
def test_bad_settings_are_one_line_errors(options, message):
    settings = {"vary": {"A": [1.0]}, "variable": "theta", "period": 1.0, **options}
    with pytest.raises(ModelError) as error:
        lg.load("driven_damped_pendulum").bifurcation(**settings)
    assert message in str(error.value)

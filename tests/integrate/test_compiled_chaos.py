"""Sections and Lyapunov spectra in DOP853's compiled loop give SciPy's path's answers.

The compiled paths (integrate/compiled_sections.py, the tangent loop of
integrate/numba_dop853.py) take SciPy's steps and locate crossings as ``solve_ivp``
does, so over runs short enough that rounding has not grown (chaos multiplies it), the
points and the exponents agree with SciPy's path to near the tolerance.  Checked on
systems that are not built-in examples, with sections through parameters, time and
several coordinates, every crossing direction, and three coordinates (J W with n = 3).
"""

from __future__ import annotations

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.integrate import lyapunov, poincare
from lagrangian.integrate.lyapunov import lyapunov_spectrum
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")

# A quartic two-dimensional oscillator (not an example): chaotic at this energy.
QUARTIC = lg.System.from_lagrangian(
    "(x_dot**2 + y_dot**2)/2 - (x**2 + y**2)/2 - a*x**2*y**2 - (x**4 + y**4)/4",
    coordinates=["x", "y"],
    parameters={"a": 1.5},
    initial={"x": 0.3, "y": 0.8, "x_dot": 0.4},
)
# Three pendulums coupled by springs (not an example): J W with n = 3.
COUPLED = lg.System.from_lagrangian(
    "(a_dot**2 + b_dot**2 + c_dot**2)/2 + g*(cos(a) + cos(b) + cos(c))"
    " - k*((a - b)**2 + (b - c)**2)/2",
    coordinates=["a", "b", "c"],
    parameters={"g": 9.81, "k": 2.0},
    initial={"a": 1.2, "b": -0.4, "c": 0.1, "a_dot": 0.5},
)


def both_sections(monkeypatch, system, **options):
    """(compiled path, SciPy's path) of the same section."""
    ours = system.poincare(**options)
    with monkeypatch.context() as patch:
        patch.setattr(poincare, "section_loop", lambda compiled, section: None)
        theirs = system.poincare(**options)
    return ours, theirs


@pytest.mark.slow
@pytest.mark.parametrize(
    ("section", "direction"),
    [("x = y", "-"), ("x + a*y = 0.1*t", "both")],
)
def test_section_points_are_scipys(monkeypatch, section, direction):
    ours, theirs = both_sections(
        monkeypatch, QUARTIC, section=section, direction=direction, axes=("y", "y_dot"),
        spread={"y": (0.2, 0.9)}, orbits=3, t_end=30.0, rtol=1e-11, atol=1e-13,
    )  # fmt: skip
    assert ours.count == theirs.count > 10
    np.testing.assert_array_equal(ours.orbits, theirs.orbits)
    np.testing.assert_allclose(ours.times, theirs.times, rtol=0, atol=1e-8)
    np.testing.assert_allclose(ours.values, theirs.values, rtol=0, atol=1e-8)


@pytest.mark.slow
def test_energy_shell_starts_on_the_section_count_as_scipy_counts_them(monkeypatch):
    # every start lies on x = 0 (g = 0 at t = 0): not a crossing, as for solve_ivp
    ours, theirs = both_sections(
        monkeypatch, lg.load("henon_heiles"), section="x = 0", axes=("y", "p_y"),
        energy=1 / 12, orbits=4, t_end=40.0,
    )  # fmt: skip
    assert ours.count == theirs.count
    assert np.all(ours.times > 0)
    np.testing.assert_allclose(ours.values, theirs.values, rtol=0, atol=1e-8)


def test_a_section_crossed_many_times_keeps_every_point():
    # more crossings than one call of the loop keeps: its rows are collected and reused
    points = lg.System.from_lagrangian(
        "(x_dot**2 + y_dot**2)/2 - (x**2 + 2*y**2)/2", coordinates=["x", "y"]
    ).poincare(section="x = 0", axes=("y", "y_dot"), initial={"x": 1.0, "y": 0.5}, t_end=2000.0)
    assert points.count == 318  # x = cos t crosses 0 upwards at t = 3 pi / 2 + 2 pi k
    np.testing.assert_allclose(points.times, 1.5 * np.pi + 2 * np.pi * np.arange(318), atol=1e-7)


@pytest.mark.slow
@pytest.mark.parametrize(("system", "count"), [(QUARTIC, None), (COUPLED, None), (COUPLED, 2)])
def test_spectrum_is_scipys(monkeypatch, system, count):
    compiled = compile_equations(system.equations_of_motion(), backend="llvm")
    options = {"t_end": 6.0, "count": count, "transient": 1.5, "interval": 0.5}
    ours = lyapunov_spectrum(compiled, **options)
    with monkeypatch.context() as patch:
        patch.setattr(lyapunov, "tangent_loop", lambda compiled: None)
        theirs = lyapunov_spectrum(compiled, **options)
    np.testing.assert_allclose(ours.history, theirs.history, rtol=0, atol=1e-7)
    assert ours.count == (2 * compiled.n if count is None else count)

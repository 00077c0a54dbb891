"""Whole-pipeline checks on systems that are not built-in examples."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.analysis import Stability, analyze

CART = Path(__file__).with_name("cart_on_spring.toml")


def test_cart_with_rod_and_spring_with_rest_length():
    # a spring of rest length 1 from the anchor at x = -1: the cart rests at x = 0 (or x = -2,
    # through the anchor); the rod hangs stably and is unstable upside down
    system = lg.load(CART)
    analysis = analyze(system.equations_of_motion())
    points = {
        (round(float(e.point["x"]), 9), round(float(e.point["theta"]), 9)): e
        for e in analysis.equilibria
    }
    assert points[(0.0, 0.0)].modes.stability is Stability.STABLE
    assert points[(0.0, round(np.pi, 9))].modes.stability is Stability.UNSTABLE
    # small oscillations: M0 = [[M + m, m l/2], [m l/2, m l^2/3]], K0 = diag(k, m g l/2)
    M, m, l, k, g = 2.0, 1.0, 1.0, 5.0, 9.81
    mass = np.array([[M + m, m * l / 2], [m * l / 2, m * l**2 / 3]])
    stiffness = np.diag([k, m * g * l / 2])
    expected = np.sort(np.linalg.eigvals(np.linalg.solve(mass, stiffness)).real)
    found = np.sort([float(w2) for w2 in points[(0.0, 0.0)].modes.omega_squared])
    assert found == pytest.approx(expected, rel=1e-9)


def test_cart_simulates_and_conserves_energy():
    trajectory = lg.load(CART).simulate(t_end=3.0)
    assert trajectory.status == "success"
    assert trajectory.drift("energy") < 1e-8

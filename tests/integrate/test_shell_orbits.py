"""Periodic orbits on an energy shell through a section (integrate/shell_orbits.py), against
analytic orbits and SciPy's solve_ivp of Hénon–Heiles' equations written out here."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.integrate import floquet


@pytest.mark.slow
def test_the_normal_mode_of_an_anisotropic_oscillator():
    # L = (x'^2 + y'^2)/2 - (x^2 + w^2 y^2)/2: the x-mode through x = 0 upwards at E = 1/2
    # is x = sin t, y = 0, of time 2 pi; its multipliers are 1, 1 and exp(+-2 pi i w) (the
    # y-motion over one x-period), on the unit circle: elliptic
    w = math.sqrt(2.0)
    system = lg.System.from_lagrangian(
        "(x_dot**2 + y_dot**2)/2 - (x**2 + w**2*y**2)/2", coordinates=["x", "y"],
        parameters={"w": w},
    )  # fmt: skip
    search = system.orbits(section="x = 0", energy=0.5, period=1, attractor=5, t_end=30)
    (orbit,) = search.orbits
    assert orbit.time == pytest.approx(2 * math.pi, rel=1e-10)
    np.testing.assert_allclose(orbit.points[:, 0], [0.0, 0.0, 1.0, 0.0], atol=1e-9)
    pair = floquet.nontrivial(orbit.multipliers, 2)
    expected = np.exp(2j * math.pi * w)
    np.testing.assert_allclose(
        sorted(pair, key=lambda m: m.imag), [expected.conjugate(), expected], atol=1e-8
    )
    assert orbit.kind == "elliptic" and orbit.stable and orbit.period == 1
    assert search.settings["section"] == "x = 0" and search.settings["energy"] == 0.5


def _henon_heiles(t, z):
    x, y, vx, vy = z
    return [vx, vy, -x - 2 * x * y, -y - x**2 + y**2]


def test_henon_heiles_orbits_return_on_their_shell_with_reciprocal_multipliers():
    search = lg.load("henon_heiles").orbits(
        section="x = 0", energy=0.125, period=1, attractor=6, t_end=40
    )
    assert len(search.orbits) >= 2
    kinds = set()
    for orbit in search.orbits:
        x = orbit.points[:, 0]
        energy = (
            (x[2] ** 2 + x[3] ** 2) / 2
            + (x[0] ** 2 + x[1] ** 2) / 2
            + x[0] ** 2 * x[1]
            - x[1] ** 3 / 3
        )
        assert energy == pytest.approx(0.125, abs=1e-10) and abs(x[0]) < 1e-10 and x[2] > 0
        run = solve_ivp(_henon_heiles, (0, orbit.time), x, method="DOP853", rtol=1e-12, atol=1e-13)
        np.testing.assert_allclose(run.y[:, -1], x, atol=1e-8)
        # a Hamiltonian flow: det M = 1, and besides the two 1s a pair mu, 1/mu
        assert np.linalg.det(orbit.monodromy) == pytest.approx(1.0, abs=1e-8)
        pair = floquet.nontrivial(orbit.multipliers, 2)
        assert pair[0] * pair[1] == pytest.approx(1.0, abs=1e-8)
        kinds.add(orbit.kind)
    assert kinds == {"elliptic", "saddle"}


def test_a_driven_system_is_refused_a_section():
    with pytest.raises(ModelError, match="need equations that do not depend on t"):
        lg.load("driven_damped_pendulum").orbits(section="theta = 0", energy=1.0, period=1)

"""A model is built with Python's cycle collector paused, and the collector is given back
as it was found: after a build, after a refused model, and left off where it was off."""

from __future__ import annotations

import gc

import pytest
import sympy

import lagrangian as lg
from lagrangian.model import build
from lagrangian.model.toml_io import loads


@pytest.fixture
def collector():
    """The collector as the process had it, put back after the test whatever it did."""
    enabled = gc.isenabled()
    yield
    (gc.enable if enabled else gc.disable)()


def _recording(monkeypatch) -> list:
    """Whether the collector ran when T was assembled."""
    seen: list = []
    kinetic_energy = build.kinetic_energy

    def recorded(*args, **kwargs):
        seen.append(gc.isenabled())
        return kinetic_energy(*args, **kwargs)

    monkeypatch.setattr(build, "kinetic_energy", recorded)
    return seen


_PARTICLES = """
coordinates = ["a", "b"]
[parameters]
m = 1.0
l = 1.0
g = 9.8
[[particles]]
mass = "m"
position = ["l*sin(a)", "-l*cos(a)"]
[[particles]]
mass = "m"
position = ["l*sin(a) + l*sin(b)", "-l*cos(a) - l*cos(b)"]
[gravity]
g = "g"
"""


def test_paused_while_the_model_is_built_and_back_after(monkeypatch, collector):
    gc.enable()
    seen = _recording(monkeypatch)
    system = loads(_PARTICLES)
    assert seen == [False]
    assert gc.isenabled()
    # the build is the same: T of the double pendulum, checked by hand
    m, l, a, b = (system.symbol(name) for name in ("m", "l", "a", "b"))
    a_dot, b_dot = (c.q_dot for c in system.coordinates)
    expected = m * l**2 * (2 * a_dot**2 + b_dot**2 + 2 * a_dot * b_dot * sympy.cos(a - b)) / 2
    assert sympy.simplify(system.kinetic - expected) == 0


def test_back_after_a_refused_model(collector):
    gc.enable()
    with pytest.raises(lg.ModelError, match="not_a_coordinate"):
        loads(_PARTICLES + "[initial]\nnot_a_coordinate = 1.0\n")
    assert gc.isenabled()


def test_left_off_where_it_was_off(collector):
    gc.disable()
    loads(_PARTICLES)
    assert not gc.isenabled()

"""The large route pauses Python's cycle collector while it makes its tables, and gives it
back as it found it: after a derivation, after a refusal, after running out of time."""

from __future__ import annotations

import gc
import importlib

import pytest

import lagrangian as lg
from lagrangian.derive import euler_lagrange
from lagrangian.derive.term_tables import TermTables


def _chain(n: int) -> lg.System:
    """Coupled neighbours: M is one block, too large for q'' in closed form (kept quick)."""
    coordinates = [f"q{i}" for i in range(n)]
    kinetic = " + ".join(
        f"q{i}_dot^2 + q{i}_dot*q{(i + 1) % n}_dot*cos(q{i} - q{(i + 1) % n})/2" for i in range(n)
    )
    potential = " + ".join(f"cos(q{i})" for i in range(n))
    return lg.System.from_energies(kinetic, potential, coordinates=coordinates)


def _uncoupled_chain(n: int) -> lg.System:
    """test_budget_large's chain: its q'' in closed form take long enough to run out of time."""
    coordinates = [f"q{i}" for i in range(n)]
    kinetic = " + ".join(f"(1 + sin(q{i})^2)*q{i}_dot^2/2" for i in range(n))
    potential = " + ".join(f"cos(q{i} - q{(i + 1) % n})" for i in range(n))
    return lg.System.from_energies(kinetic, potential, coordinates=coordinates)


def _recording(monkeypatch) -> list:
    """Whether the collector ran, at each split of the tables."""
    seen: list = []
    split = TermTables.split

    def recorded(self, *args, **kwargs):
        seen.append(gc.isenabled())
        return split(self, *args, **kwargs)

    monkeypatch.setattr(TermTables, "split", recorded)
    return seen


@pytest.fixture
def collector():
    """The collector as the process had it, put back after the test whatever it did."""
    enabled = gc.isenabled()
    yield
    (gc.enable if enabled else gc.disable)()


def test_paused_while_the_tables_are_made_and_back_after(monkeypatch, collector):
    gc.enable()
    seen = _recording(monkeypatch)
    eom = _chain(7).equations_of_motion()
    assert eom.symengine is not None  # the large route (7 coordinates)
    assert seen and not any(seen)
    assert gc.isenabled()


def test_left_off_where_it_was_off(monkeypatch, collector):
    gc.disable()
    _chain(7).equations_of_motion()
    assert not gc.isenabled()


def test_back_after_a_derivation_out_of_time(monkeypatch, collector):
    gc.enable()
    monkeypatch.setattr(euler_lagrange, "LARGE_SECONDS", 1e-4)
    with pytest.raises(lg.ModelError, match="not derived within"):
        _uncoupled_chain(8).equations_of_motion()
    assert gc.isenabled()


def test_back_after_a_refused_expansion(monkeypatch, collector):
    gc.enable()
    monkeypatch.setattr(importlib.import_module("lagrangian.derive.fast"), "MAX_EXPANDED_TERMS", 3)
    with pytest.raises(lg.ModelError, match="too large to derive"):
        _chain(7).equations_of_motion()
    assert gc.isenabled()

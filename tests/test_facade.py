"""The facade's System: each stage derives the equations of motion once per System."""

from __future__ import annotations

import pytest

import lagrangian as lg
import lagrangian.facade
import lagrangian.simulation


def test_a_system_derives_once_for_all_its_analyses(monkeypatch):
    derived = []

    def counting(system):
        derived.append(system.input_names)
        return original(system)

    original = lagrangian.facade.derive
    monkeypatch.setattr(lagrangian.facade, "derive", counting)
    system = lg.load("cart_pole")  # an input, F: analyses hold it at 0, the equations keep it
    assert system.input_names
    first = system.equations_of_motion()
    system.conserved_quantities()
    system.equilibria()
    system.hamiltonian()
    system.linearize({"x": 0, "theta": 0})
    assert system.equations_of_motion() is first
    assert sorted(derived) == [(), system.input_names]  # once with the input, once held
    assert lg.load("cart_pole").equations_of_motion() is not first  # another System


def test_a_systems_runs_use_the_equations_it_keeps(monkeypatch):
    derived = []

    def counting(system):
        derived.append(system)
        return original(system)

    original = lagrangian.facade.derive
    monkeypatch.setattr(lagrangian.facade, "derive", counting)
    monkeypatch.setattr(lagrangian.simulation, "derive", counting)
    system = lg.load("simple_pendulum")
    first = system.simulate(t_end=1.0, n_out=11)
    again = system.simulate(t_end=1.0, n_out=11)
    system.equations_of_motion()
    assert derived == [system]  # the first run derived them, for the rest too
    assert first["theta"].tolist() == again["theta"].tolist()
    # the same run as the layer's own, which derives for itself
    alone = lagrangian.simulation.simulate_system(lg.load("simple_pendulum"), t_end=1.0, n_out=11)
    assert alone["theta"].tolist() == first["theta"].tolist()
    assert len(derived) == 2
    # a bad value is still refused before any derivation
    fresh = lg.load("simple_pendulum")
    with pytest.raises(lg.ModelError, match=r"^unknown parameter 'nope' \(parameters: m, l, g\)$"):
        fresh.simulate(t_end=1.0, params={"nope": 1.0})
    assert len(derived) == 2

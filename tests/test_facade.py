"""The facade's System: each stage derives the equations of motion once per System."""

from __future__ import annotations

import lagrangian as lg
import lagrangian.facade


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

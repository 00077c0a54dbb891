"""The large route keeps SymPy out of derive's documents: M and f are converted when read.

Above ``FAST_MIN_COORDINATES`` coordinates the equations are derived and printed in
SymEngine; their SymPy forms (``mass_matrix``, ``forcing``) are made on first read, and
the derivation starts from the Lagrangian the build assembled in SymEngine.  What is
read must still be the n-link pendulum's closed form, and a Lagrangian changed after
the build must be the one derived.
"""

from __future__ import annotations

import dataclasses
import math

import pytest
import sympy

import lagrangian as lg
from helpers import assert_close, counting, evaluate, random_point
from lagrangian.derive.equations import EquationsOfMotion
from lagrangian.lazy import Later
from lagrangian.output import derive_document
from model.test_large_assembly import _closed_form_energies

from .test_chain_pendulum import chain_pendulum, closed_form


def test_the_document_of_a_large_system_converts_nothing_to_sympy(monkeypatch, rng):
    converted = counting(monkeypatch, "lagrangian.derive.fast", "to_sympy")
    system = chain_pendulum(8)
    eom = system.equations_of_motion()
    document = derive_document(eom)
    assert len(document["mass_matrix"]) == 8
    assert converted == []  # printed from SymEngine: M and f never made in SymPy
    # read now, they are the closed form's
    n = 8
    point = random_point(system, rng)
    matrix, forcing = closed_form(n, point)
    for i in range(n):
        for j in range(n):
            assert_close(evaluate(eom.mass_matrix[i, j], point), matrix[i][j], scale=1.0)
        assert_close(evaluate(eom.forcing[i], point), forcing[i], scale=1.0)
    assert converted != []


def test_the_build_s_symengine_lagrangian_is_where_the_large_route_starts(monkeypatch):
    converted = counting(monkeypatch, "lagrangian.derive.fast", "to_symengine")
    system = chain_pendulum(8)
    assert system.built_lagrangian is system.symengine_lagrangian[1]
    system.equations_of_motion()
    assert all(args[0] is not system.lagrangian for args in converted)
    assert system.built_lagrangian is system.symengine_lagrangian[1]  # L read: still the build's


def test_a_large_model_s_sympy_forms_are_made_when_first_read(monkeypatch, rng):
    """Building the 8-link chain and deriving its document convert nothing to SymPy: L, T
    and V are made on first read, and are then the closed form's, the same object for
    every reader."""
    made = [
        counting(monkeypatch, module, "to_sympy")
        for module in ("lagrangian.model.energy_large", "lagrangian.derive.fast")
    ]
    system = chain_pendulum(8)
    document = derive_document(system.equations_of_motion())
    assert len(document["forcing"]) == 8
    assert made == [[], []]
    lagrangian = system.lagrangian
    assert made[0] != []  # converted now: T and V first, then L reusing their terms
    assert system.lagrangian is lagrangian
    assert system.built_lagrangian is system.symengine_lagrangian[1]  # read, still the build's
    point = random_point(system, rng)
    kinetic, potential = _closed_form_energies(8, point)
    assert_close(evaluate(lagrangian, point), kinetic - potential, scale=1.0)
    assert_close(evaluate(system.kinetic, point), kinetic, scale=1.0)
    assert_close(evaluate(system.potential, point), potential, scale=1.0)


def test_a_lagrangian_changed_after_the_build_is_the_one_derived(rng):
    """dataclasses.replace keeps the build's SymEngine L: it must not be used for the new L."""
    system = chain_pendulum(8)
    k, theta1 = sympy.Symbol("k", positive=True), system.coordinates[0].q
    changed = dataclasses.replace(system, lagrangian=system.lagrangian - k * theta1**2 / 2)
    eom = changed.equations_of_motion()
    point = random_point(system, rng) | {"k": 1.7}
    _, forcing = closed_form(8, point)
    assert_close(evaluate(eom.forcing[0], point), forcing[0] - 1.7 * point["theta1"], scale=1.0)
    for i in range(1, 8):
        assert_close(evaluate(eom.forcing[i], point), forcing[i], scale=1.0)


def test_accelerations_in_the_build_s_lagrangian_are_found_in_its_symengine_form(monkeypatch):
    """The check for q'' in L reads the SymEngine form the build made (SymPy's ``has`` is
    not run on L), and still refuses an L that holds one, as before; an L replaced after
    the build is checked by SymPy's ``has``."""
    from lagrangian.algebra import to_symengine

    system = chain_pendulum(8)
    acceleration = system.coordinates[2].q_ddot
    held = system.lagrangian + sympy.Symbol("m1", positive=True) * acceleration**2
    accelerated = dataclasses.replace(
        system, lagrangian=held, symengine_lagrangian=(held, to_symengine(held, {}))
    )
    looked_at: list = []
    has = sympy.Basic.has
    monkeypatch.setattr(
        sympy.Basic, "has", lambda self, *a: looked_at.append(self) or has(self, *a)
    )
    with pytest.raises(lg.ModelError, match=r"accelerations \(q_ddot\) are not allowed") as refused:
        accelerated.equations_of_motion()
    assert refused.value.field == "lagrangian"
    assert all(part is not held for part in looked_at)
    replaced = dataclasses.replace(system, lagrangian=held)  # the build's pair no longer is L
    with pytest.raises(lg.ModelError, match="not allowed"):
        replaced.equations_of_motion()
    assert any(part is held for part in looked_at)


def test_a_later_field_is_made_once_on_first_read_and_kept_by_replace():
    made = []

    def matrix():
        made.append(1)
        return sympy.ImmutableMatrix([[2]])

    eom = EquationsOfMotion(
        system=None,
        equations=(),
        mass_matrix=Later(matrix),
        forcing=sympy.ImmutableMatrix([[1]]),
        accelerations=None,
        steps=(),
    )
    assert made == []
    assert eom.mass_matrix == sympy.ImmutableMatrix([[2]])
    assert eom.mass_matrix is eom.mass_matrix
    assert made == [1]
    copy = dataclasses.replace(eom, accelerations={"x": sympy.Integer(1)})
    assert copy.mass_matrix is eom.mass_matrix
    with pytest.raises(dataclasses.FrozenInstanceError):
        eom.mass_matrix = sympy.ImmutableMatrix([[3]])
    assert math.isclose(float(copy.forcing[0, 0]), 1.0)

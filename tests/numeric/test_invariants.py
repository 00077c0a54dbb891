"""Energy, conserved quantities and the structural flags of the compiled systems."""

from __future__ import annotations

import pytest
import sympy

from helpers import evaluate
from lagrangian.analysis.conserved import conserved_quantities

from .cases import (
    EXAMPLES,
    ORACLE_FUNCTIONS,
    arguments,
    assert_arrays_close,
    compiled,
    equations,
    point,
)

RTOL = 1e-10


@pytest.mark.parametrize("name", EXAMPLES)
def test_energy_is_the_energy_function(name, rng):
    """h = sum q' dL/dq' - L, built here from L itself."""
    eom, system = equations(name), compiled(name)
    lagrangian = eom.system.lagrangian
    energy = sum(
        (c.q_dot * sympy.diff(lagrangian, c.q_dot) for c in eom.system.coordinates), -lagrangian
    )
    for _ in range(3):
        values = point(name, rng)
        t, y, params = arguments(system, values)
        expected = evaluate(energy, values, ORACLE_FUNCTIONS.get(name))
        assert_arrays_close(system.energy(t, y, params), expected, RTOL, name)


@pytest.mark.parametrize("name", EXAMPLES)
def test_invariants_are_the_conserved_quantities(name, rng):
    eom, system = equations(name), compiled(name)
    conserved = conserved_quantities(eom).conserved
    assert set(system.invariants) == {quantity.name for quantity in conserved}
    for _ in range(3):
        values = point(name, rng)
        t, y, params = arguments(system, values)
        for quantity in conserved:
            expected = evaluate(quantity.expression, values, ORACLE_FUNCTIONS.get(name))
            actual = system.invariants[quantity.name](t, y, params)
            assert_arrays_close(actual, expected, RTOL, f"{name}: {quantity.name}")


def test_invariants_of_the_examples():
    assert set(compiled("spherical_pendulum").invariants) == {"p_phi", "energy"}
    assert set(compiled("central_force").invariants) == {"p_theta", "energy"}
    assert set(compiled("planar_particle_forces").invariants) == set()


CONSTANT_MASS = {
    "bouncing_ball",
    "cartesian_pendulum",
    "driven_damped_pendulum",
    "harmonic_oscillator",
    "henon_heiles",
    "impact_oscillator",
    "planar_particle_forces",
    "rocking_block",
    "rolling_disc",
    "rotating_wire_bead",
    "simple_pendulum",
    "velocity_dependent_potential",
    "vertical_spring",
}
#: L = q'^T M q' / 2 - V(q), M constant, no forces: the bead's L = m (r'^2 + omega^2 r^2) / 2
#: has no t once sin^2 + cos^2 = 1; the charge has velocity-linear terms.
SEPARABLE = {
    "bouncing_ball",
    "harmonic_oscillator",
    "henon_heiles",
    "rocking_block",
    "rotating_wire_bead",
    "simple_pendulum",
    "vertical_spring",
}


@pytest.mark.parametrize("name", EXAMPLES)
def test_structural_flags(name):
    system = compiled(name)
    assert system.constant_mass_matrix == (name in CONSTANT_MASS)
    assert system.separable == (name in SEPARABLE)
    assert system.has_constraints == (equations(name).constraints is not None)

"""Noether charges found automatically, against charges written here by hand.

Each found charge must equal (up to a constant factor) the textbook one, be
reported with its reason, and never be reported when a force, dissipation or a
constraint breaks it.
"""

from __future__ import annotations

import sympy

import lagrangian as lg
from lagrangian.analysis import conserved_quantities
from lagrangian.analysis.motion import vanishes_along_motion
from lagrangian.model import Particle


def proportional(a: sympy.Expr, b: sympy.Expr) -> bool:
    ratio = sympy.simplify(a / b)
    return ratio != 0 and not ratio.free_symbols


def triatomic(**options):
    return lg.System.from_energies(
        "m*x1_dot**2/2 + M*x2_dot**2/2 + m*x3_dot**2/2",
        "k*(x2 - x1)**2/2 + k*(x3 - x2)**2/2",
        coordinates=["x1", "x2", "x3"],
        parameters={"m": 1.0, "M": 2.0, "k": 1.0} | options.pop("parameters", {}),
        **options,
    )


def kepler_pair():
    """Two particles in the plane, attracting as -k/r, in Cartesian coordinates."""
    return lg.System.from_particles(
        ["x1", "y1", "x2", "y2"],
        [Particle("a", "m1", ("x1", "y1")), Particle("b", "m2", ("x2", "y2"))],
        potential="-k/sqrt((x1 - x2)**2 + (y1 - y2)**2)",
        parameters={"m1": 1.0, "m2": 3.0, "k": 1.0},
    )


def charges(system):
    return {q.name: q for q in conserved_quantities(system.equations_of_motion()).conserved}


def test_triatomic_total_momentum_and_boost():
    system = triatomic()
    s = system.symbols
    found = charges(system)
    momentum = s["m"] * s["x1_dot"] + s["M"] * s["x2_dot"] + s["m"] * s["x3_dot"]
    (p,) = [q for name, q in found.items() if name.startswith("P")]
    assert proportional(p.expression, momentum)
    assert "translation of x1, x2, x3 together" in p.description
    # m X - P t with X the centre of mass (times the total mass)
    boost = s["m"] * s["x1"] + s["M"] * s["x2"] + s["m"] * s["x3"] - momentum * s["t"]
    (g,) = [q for name, q in found.items() if name.startswith("G")]
    assert proportional(g.expression, boost)
    assert "boost" in g.description


def test_kepler_pair_in_cartesian_coordinates_has_momentum_angular_momentum_and_boosts():
    system = kepler_pair()
    s = system.symbols
    found = charges(system)
    m1, m2 = s["m1"], s["m2"]
    assert proportional(found["P_x"].expression, m1 * s["x1_dot"] + m2 * s["x2_dot"])
    assert proportional(found["P_y"].expression, m1 * s["y1_dot"] + m2 * s["y2_dot"])
    angular = m1 * (s["x1"] * s["y1_dot"] - s["y1"] * s["x1_dot"]) + m2 * (
        s["x2"] * s["y2_dot"] - s["y2"] * s["x2_dot"]
    )
    assert proportional(found["L_z"].expression, angular)
    assert "rotation of all particles" in found["L_z"].description
    centre = m1 * s["x1"] + m2 * s["x2"] - (m1 * s["x1_dot"] + m2 * s["x2_dot"]) * s["t"]
    assert proportional(found["G_x"].expression, centre)
    # everything reported is conserved along the motion (an independent numerical check)
    eom = system.equations_of_motion()
    assert all(vanishes_along_motion(q.expression, eom) for q in found.values())


def test_particle_in_a_central_field_in_3d_has_the_three_angular_momenta():
    system = lg.System.from_particles(
        ["x", "y", "z"],
        [Particle("p", "m", ("x", "y", "z"))],
        potential="k*(x**2 + y**2 + z**2)**2",
        parameters={"m": 1.0, "k": 1.0},
    )
    s = system.symbols
    found = charges(system)
    r = [s["x"], s["y"], s["z"]]
    v = [s["x_dot"], s["y_dot"], s["z_dot"]]
    expected = {
        "L_x": r[1] * v[2] - r[2] * v[1],
        "L_y": r[2] * v[0] - r[0] * v[2],
        "L_z": r[0] * v[1] - r[1] * v[0],
    }
    for name, closed in expected.items():
        assert proportional(found[name].expression, s["m"] * closed)
    assert not any(name.startswith("P") for name in found)  # the field breaks translations


def test_charge_in_a_magnetic_field_keeps_its_canonical_angular_momentum():
    # symmetric gauge A = B (-y, x)/2: L = m v^2/2 + q B (x y' - y x')/2 is invariant under
    # rotations about z; translations change it by a total derivative only (not point symmetries)
    system = lg.System.from_lagrangian(
        "m*(x_dot**2 + y_dot**2)/2 + q*B*(x*y_dot - y*x_dot)/2",
        coordinates=["x", "y"],
        parameters={"m": 1.0, "q": 1.0, "B": 1.0},
    )
    s = system.symbols
    found = charges(system)
    canonical = (
        s["m"] * (s["x"] * s["y_dot"] - s["y"] * s["x_dot"])
        + s["q"] * s["B"] * (s["x"] ** 2 + s["y"] ** 2) / 2
    )
    (rotation,) = [q for name, q in found.items() if name != "energy"]
    assert proportional(rotation.expression, canonical)


def test_forces_dissipation_and_constraints_break_a_symmetry():
    # a force on one atom: total momentum is not conserved, and says why
    pushed = triatomic(forces={"x1": "F"}, parameters={"F": 1.0})
    result = conserved_quantities(pushed.equations_of_motion())
    assert not any(name.startswith("P") for name in result.names)
    broken = [q for q in result.not_conserved if q.name.startswith("P")]
    assert broken and "Q_x1" in broken[0].reason
    # friction on one atom breaks it too; friction between atoms does not
    dragged = triatomic(dissipation="b*x1_dot**2/2", parameters={"b": 0.1})
    names = conserved_quantities(dragged.equations_of_motion()).names
    assert not any(n.startswith("P") for n in names)
    internal = triatomic(dissipation="b*(x1_dot - x2_dot)**2/2", parameters={"b": 0.1})
    names = conserved_quantities(internal.equations_of_motion()).names
    assert any(n.startswith("P") for n in names)


def test_a_constraint_force_along_the_shift_breaks_it_one_across_does_not():
    free = "m*(x1_dot**2 + x2_dot**2)/2 - k*(x1 - x2)**2/2"
    options = {"coordinates": ["x1", "x2"], "parameters": {"m": 1.0, "k": 1.0, "d": 1.0}}
    pinned = lg.System.from_lagrangian(free, constraints=["x1 - d"], **options)
    names = conserved_quantities(pinned.equations_of_motion()).names
    assert not any(n.startswith("P") for n in names)
    rigid = lg.System.from_lagrangian(free, constraints=["x1 - x2 - d"], **options)
    names = conserved_quantities(rigid.equations_of_motion()).names
    assert any(n.startswith("P") for n in names)


def test_cyclic_coordinates_are_not_reported_twice():
    found = charges(lg.load("central_force"))
    assert set(found) == {"p_theta", "energy"}


def test_momenta_already_listed_are_not_repeated_and_single_angles_have_no_boost():
    # planar particle under constant forces: p_x, p_y are listed (not conserved) once
    result = conserved_quantities(lg.load("planar_particle_forces").equations_of_motion())
    names = [q.name for q in (*result.conserved, *result.not_conserved)]
    assert sorted(names) == ["energy", "p_x", "p_y"]
    # a rolling disc's cyclic angle turns uniformly, but that is no centre-of-mass charge
    rolling = conserved_quantities(lg.load("rolling_disc").equations_of_motion())
    assert not any(q.name.startswith("G") for q in rolling.conserved)

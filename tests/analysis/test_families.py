"""Continua of equilibria, configurations all at rest, and singular coordinates.

Closed forms: the linear triatomic molecule (omega^2 = 0, k/m, k (1/m + 2/M),
Goldstein 6.4), a chain with unequal masses and springs (against NumPy's
generalized eigenvalues of K and M written here by hand), an isotropic
oscillator in polar coordinates (k/m at r = 0, theta degenerate).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis import Stability, analyze, equilibria
from lagrangian.analysis import search as root_search
from lagrangian.cli import ExitStatus, main
from lagrangian.output.analysis import analysis_document, format_analysis


def triatomic():
    return lg.System.from_energies(
        "m*x1_dot**2/2 + M*x2_dot**2/2 + m*x3_dot**2/2",
        "k*(x2 - x1)**2/2 + k*(x3 - x2)**2/2",
        coordinates=["x1", "x2", "x3"],
        parameters={"m": 1.0, "M": 2.0, "k": 1.0},
        name="Linear triatomic molecule",
    )


def test_triatomic_molecule_rests_on_a_line_with_its_three_modes():
    system = triatomic()
    m, M, k = (system.symbol(n) for n in ("m", "M", "k"))
    (family,) = equilibria(system.equations_of_motion())
    assert len(family.free) == 1
    # every member of the reported family is at rest: dV/dq = 0 for any value of the free one
    potential = system.potential
    x = {c.name: c.q for c in system.coordinates}
    free = x[family.free[0]]
    for value in (-1.3, 0.0, 2.7):
        member = {x[name]: v.xreplace({free: value}) for name, v in family.point.items()}
        member[free] = value
        assert all(sympy.diff(potential, q).xreplace(member) == 0 for q in x.values())
    expected = [0, k / m, k * (1 / m + 2 / M)]
    assert len(family.omega_squared) == 3
    for found, closed in zip(family.omega_squared, expected, strict=True):
        assert sympy.simplify(found - closed) == 0
    assert family.modes.stability is Stability.MARGINAL
    (zero,) = family.zero_modes
    assert zero.startswith("translation of x1, x2, x3 together")


def test_a_four_atom_chain_with_unequal_masses_matches_numpy():
    # not the triatomic: four masses, three different springs; one zero mode, three others
    masses, springs = [1.0, 2.5, 0.7, 1.9], [1.0, 3.0, 0.5]
    kinetic = " + ".join(f"m{i}*x{i}_dot**2/2" for i in range(4))
    potential = " + ".join(f"k{i}*(x{i + 1} - x{i})**2/2" for i in range(3))
    parameters = {f"m{i}": v for i, v in enumerate(masses)} | {
        f"k{i}": v for i, v in enumerate(springs)
    }
    system = lg.System.from_energies(
        kinetic, potential, coordinates=[f"x{i}" for i in range(4)], parameters=parameters
    )
    (family,) = system.equilibria()
    assert family.free
    stiffness = np.zeros((4, 4))
    for i, k in enumerate(springs):
        stiffness[np.ix_([i, i + 1], [i, i + 1])] += k * np.array([[1, -1], [-1, 1]])
    expected = np.sort(np.linalg.eigvals(np.linalg.solve(np.diag(masses), stiffness)).real)
    values = {p.symbol: p.default for p in system.parameters}
    found = np.sort([complex(sympy.N(w.xreplace(values))).real for w in family.omega_squared])
    assert found == pytest.approx(expected, abs=1e-9)
    assert len(family.zero_modes) == 1 and "translation" in family.zero_modes[0]


def test_the_family_is_reported_in_text_and_json():
    analysis = analyze(triatomic().equations_of_motion(), timeout=None)
    text = format_analysis(analysis)
    assert "a family of equilibria, free:" in text
    assert "ω² = 0: translation of x1, x2, x3 together" in text
    (document,) = analysis_document(analysis)["equilibria"]
    assert document["stability"] == "marginal" and len(document["omega_squared"]) == 3
    assert document["free"] and document["zero_modes"][0].startswith("translation")
    json.dumps(document)


def test_torque_free_top_is_at_rest_everywhere_without_a_search(monkeypatch):
    # Euler angles of a symmetric top with no potential: every orientation is at rest
    def no_search(*args, **kwargs):
        raise AssertionError("V = 0 needs no root search")

    monkeypatch.setattr(root_search.RootSearch, "__init__", no_search)
    top = lg.System.from_energies(
        "A*(theta_dot**2 + phi_dot**2*sin(theta)**2)/2 + C*(psi_dot + phi_dot*cos(theta))**2/2",
        "0",
        coordinates=["phi", "theta", "psi"],
        parameters={"A": 1.0, "C": 2.0},
    )
    (everywhere,) = top.equilibria()
    assert everywhere.everywhere and dict(everywhere.point) == {}
    assert everywhere.omega_squared == (0, 0, 0)
    assert everywhere.modes.stability is Stability.MARGINAL


def test_a_force_at_rest_means_not_every_configuration_is_an_equilibrium():
    pushed = lg.System.from_lagrangian(
        "m*x_dot**2/2", coordinates=["x"], forces={"x": "F"}, parameters={"m": 1.0, "F": 1.0}
    )
    assert pushed.equilibria() == ()


def test_oscillator_in_polar_coordinates_has_theta_degenerate_at_the_centre():
    # V = k r^2/2 in the plane, in (r, theta): M = diag(m, m r^2) is singular at r = 0
    system = lg.System.from_energies(
        "m*(r_dot**2 + r**2*theta_dot**2)/2",
        "k*r**2/2",
        coordinates=["r", "theta"],
        parameters={"m": 1.0, "k": 4.0},
    )
    m, k = system.symbol("m"), system.symbol("k")
    (centre,) = system.equilibria()
    assert dict(centre.point) == {"r": 0}
    assert centre.degenerate == ("theta",)
    assert centre.omega_squared == (k / m,) and centre.stable


@pytest.mark.slow
def test_spherical_pendulum_modes_plot(tmp_path, capsys):
    out = tmp_path / "modes.png"
    status = main(["plot", "spherical_pendulum", "--kind", "modes", "--out", str(out)])
    assert status == ExitStatus.SUCCESS, capsys.readouterr().err
    assert out.stat().st_size > 0


def test_euler_angles_degenerate_along_a_combination_at_the_poles():
    # a heavy symmetric top in Euler angles: at theta = 0, pi only phi +- psi is defined, so
    # M0 is singular without a zero row; the regular directions keep the tilt, whose omega^2
    # is that of a physical pendulum, M g l/(I1 + M l^2) hanging and minus that upright
    top = lg.System.from_energies(
        "(I1 + M*l**2)*(theta_dot**2 + phi_dot**2*sin(theta)**2)/2"
        " + I3*(psi_dot + phi_dot*cos(theta))**2/2",
        "M*g*l*cos(theta)",
        coordinates=["phi", "theta", "psi"],
        parameters={"I1": 1.0, "I3": 2.0, "M": 1.0, "l": 1.0, "g": 9.81},
    )
    I1, M, g, l = (top.symbol(n) for n in ("I1", "M", "g", "l"))
    tilt = M * g * l / (I1 + M * l**2)
    found = {e.point["theta"]: e for e in top.equilibria()}
    up, down = found[0], found[sympy.pi]
    for e, sign in ((up, -1), (down, 1)):
        assert set(e.degenerate) == {"phi", "psi"}
        nonzero = [w for w in e.omega_squared if w != 0]
        assert len(nonzero) == 1 and sympy.simplify(nonzero[0] - sign * tilt) == 0
        assert len(e.zero_modes) == 1  # the spin about the figure axis
    assert up.modes.stability is Stability.UNSTABLE
    assert down.modes.stability is Stability.MARGINAL


def bent_molecule():
    """Three atoms in a plane, two springs of rest length d from the middle one, no bending
    stiffness: at rest wherever both springs have length d (a family of dimension 4)."""
    from lagrangian.model import Particle, Spring

    atoms = [
        Particle("H1", "m", ("x1", "y1")),
        Particle("O", "M", ("x2", "y2")),
        Particle("H2", "m", ("x3", "y3")),
    ]
    springs = [Spring("k", ("H1", "O"), "d"), Spring("k", ("O", "H2"), "d")]
    return lg.System.from_particles(
        ["x1", "y1", "x2", "y2", "x3", "y3"],
        atoms,
        springs=springs,
        parameters={"m": 1.0, "M": 16.0, "k": 1.0, "d": 1.0},
    )


@pytest.mark.slow
def test_a_bent_molecule_found_numerically_is_one_family_with_named_zero_modes():
    system = bent_molecule()
    found = equilibria(system.equations_of_motion(), timeout=1.0)
    (member,) = found  # the many numerical roots, grouped into one family
    assert member.numeric and member.family_dimension == 4
    x = np.array([float(member.point[n]) for n in system.coordinate_names]).reshape(3, 2)
    assert np.linalg.norm(x[0] - x[1]) == pytest.approx(1.0)
    assert np.linalg.norm(x[2] - x[1]) == pytest.approx(1.0)
    # the two stretching modes, against finite differences of V written here with NumPy
    masses = np.repeat([1.0, 16.0, 1.0], 2)

    def potential(q):
        r = q.reshape(3, 2)
        return sum(0.5 * (np.linalg.norm(r[i] - r[1]) - 1.0) ** 2 for i in (0, 2))

    h, q0, n = 1e-4, x.ravel(), 6
    hessian = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            e_i, e_j = np.eye(n)[i] * h, np.eye(n)[j] * h
            hessian[i, j] = (
                potential(q0 + e_i + e_j)
                - potential(q0 + e_i - e_j)
                - potential(q0 - e_i + e_j)
                + potential(q0 - e_i - e_j)
            ) / (4 * h * h)
    expected = np.sort(np.linalg.eigvals(hessian / masses[:, None]).real)
    omega_squared = np.sort([float(w) for w in member.omega_squared])
    assert omega_squared == pytest.approx(expected, abs=1e-6)
    assert sorted(member.zero_modes) == sorted(
        [
            "translation of all particles along x (L is invariant)",
            "translation of all particles along y (L is invariant)",
            "rotation of all particles about the origin (in their plane) (L is invariant)",
            "along the family of equilibria",
        ]
    )


@pytest.mark.slow
def test_complex_branches_of_a_family_are_not_equilibria():
    # V = k r^4/4 for a pair: x1 = x2 + i (y1 - y2) solves G = 0 but is no real configuration
    from lagrangian.model import Particle

    pair = lg.System.from_particles(
        ["x1", "y1", "x2", "y2"],
        [Particle("a", "m1", ("x1", "y1")), Particle("b", "m2", ("x2", "y2"))],
        potential="k*((x1 - x2)**2 + (y1 - y2)**2)**2/4",
        parameters={"m1": 1.0, "m2": 2.0, "k": 1.0},
    )
    (family,) = pair.equilibria()
    assert all(not v.has(sympy.I) for v in family.point.values())
    assert len(family.free) == 2
    # quartic, not flat: the relative motion is neutral to linear order, not a family
    assert (
        family.zero_modes.count("neutral direction (zero stiffness; linear theory undecided)") == 2
    )

"""Conserved quantities: the worked examples' by-products, and systems not in the project."""

from __future__ import annotations

import pytest
import sympy

import lagrangian as lg
from lagrangian.analysis.conserved import conserved_quantities, noether_charge
from lagrangian.analysis.motion import total_derivative, vanishes_along_motion


def conservation(system):
    return conserved_quantities(system.equations_of_motion())


def same(a, b):
    return sympy.simplify(a - b) == 0


def test_central_force_conserves_r2_theta_dot():
    system = lg.load("central_force")
    result = conservation(system)
    r, theta_dot = system.symbol("r"), system.symbol("theta_dot")
    assert result.cyclic_coordinates == ("theta",)
    assert same(result["p_theta"].expression, r**2 * theta_dot)
    assert "energy" in result.names


def test_spherical_pendulum_conserves_p_phi():
    system = lg.load("spherical_pendulum")
    result = conservation(system)
    m, l, theta, phi_dot = (system.symbol(n) for n in ("m", "l", "theta", "phi_dot"))
    assert same(result["p_phi"].expression, m * l**2 * sympy.sin(theta) ** 2 * phi_dot)
    assert "T + V" in result["energy"].description


def test_free_particle_conserves_p_phi_only_among_momenta():
    system = lg.load("free_particle_spherical")
    result = conservation(system)
    assert result.cyclic_coordinates == ("phi",)
    m, r, theta, phi_dot = (system.symbol(n) for n in ("m", "r", "theta", "phi_dot"))
    assert same(result["p_phi"].expression, m * r**2 * sympy.sin(theta) ** 2 * phi_dot)


def test_rotating_wire_has_jacobi_integral_and_t_is_not_conserved():
    system = lg.load("rotating_wire_bead")
    result = conservation(system)
    m, r, r_dot, omega = (system.symbol(n) for n in ("m", "r", "r_dot", "omega"))
    assert same(result["energy"].expression, m * (r_dot**2 - r**2 * omega**2) / 2)
    assert "Jacobi" in result["energy"].description
    (mechanical,) = [q for q in result.not_conserved if q.name == "mechanical_energy"]
    assert same(mechanical.expression, m * (r_dot**2 + r**2 * omega**2) / 2)
    assert "constraints move" in mechanical.reason
    eom = system.equations_of_motion()
    assert not vanishes_along_motion(mechanical.expression, eom)


@pytest.mark.parametrize(
    "options, reason",
    [
        ({"forces": {"x": "-b*x_dot"}}, "Q_x does work"),
        ({"dissipation": "b*x_dot^2/2"}, "dissipation"),
    ],
)
def test_energy_not_conserved_with_its_reason(options, reason):
    system = lg.System.from_energies("m*x_dot^2/2", "k*x^2/2", ["x"], **options)
    result = conservation(system)
    assert "energy" not in result.names
    (energy,) = [q for q in result.not_conserved if q.name == "energy"]
    assert reason in energy.reason


def test_explicit_time_breaks_energy_conservation():
    system = lg.System.from_lagrangian("m*x_dot^2/2 - k*cos(w*t)*x^2/2", ["x"])
    (energy,) = [q for q in conservation(system).not_conserved if q.name == "energy"]
    assert energy.reason == "L depends on t"


def test_gyroscopic_forces_do_no_work():
    # a charge in a magnetic field, the Lorentz force given as generalized forces
    system = lg.System.from_energies(
        "m*(x_dot^2 + y_dot^2)/2",
        "k*(x^2 + y^2)/2",
        ["x", "y"],
        forces={"x": "q*B*y_dot", "y": "-q*B*x_dot"},
    )
    result = conservation(system)
    assert "energy" in result.names


def test_symmetric_top_cyclic_momenta():
    # heavy symmetric top, Euler angles (theta, phi, psi): phi and psi are cyclic
    system = lg.System.from_lagrangian(
        "I1*(theta_dot^2 + phi_dot^2*sin(theta)^2)/2 + I3*(psi_dot + phi_dot*cos(theta))^2/2"
        " - M*g*h*cos(theta)",
        ["theta", "phi", "psi"],
    )
    result = conservation(system)
    assert result.cyclic_coordinates == ("phi", "psi")
    eom = system.equations_of_motion()
    for quantity in result.conserved:
        assert vanishes_along_motion(quantity.expression, eom)
    I3, psi_dot, phi_dot, theta = (system.symbol(n) for n in ("I3", "psi_dot", "phi_dot", "theta"))
    assert same(result["p_psi"].expression, I3 * (psi_dot + phi_dot * sympy.cos(theta)))


def test_noether_charge_of_a_rotation():
    # planar particle in a central potential: rotation (x, y) -> (x - eps y, y + eps x)
    system = lg.System.from_energies("m*(x_dot^2 + y_dot^2)/2", "k*(x^2 + y^2)^2/4", ["x", "y"])
    eom = system.equations_of_motion()
    x, y, x_dot, y_dot, m = (system.symbol(n) for n in ("x", "y", "x_dot", "y_dot", "m"))
    charge = noether_charge(eom, {"x": -y, "y": x}, name="angular_momentum")
    assert same(charge.expression, m * (x * y_dot - y * x_dot))
    assert same(
        total_derivative(charge.expression, eom).subs(
            {
                system.symbol("x_ddot"): eom.accelerations["x"],
                system.symbol("y_ddot"): eom.accelerations["y"],
            }
        ),
        0,
    )
    with pytest.raises(lg.ModelError, match="not a symmetry"):
        noether_charge(eom, {"x": sympy.Integer(1)})


def test_constraint_forces_break_cyclic_momenta_but_not_energy():
    system = lg.load("rolling_disc")
    result = conservation(system)
    assert "energy" in result.names  # rolling constraints do no work
    assert "p_theta" not in result.names  # theta is absent from L but the constraint acts on it
    assert {q.name for q in result.not_conserved} >= {"p_x", "p_y", "p_theta"}
    assert result.cyclic_coordinates == ("phi",)


def test_moving_constraint_does_work():
    # bead on a rod whose length is prescribed: x^2 + y^2 = (l + a t)^2 (a reeled-in pendulum)
    system = lg.System.from_particles(
        ["x", "y"],
        [lg.Particle("bob", "m", ("x", "y"))],
        gravity=lg.Gravity("g"),
        constraints=["x^2 + y^2 - (l + a*t)^2"],
    )
    (energy,) = [q for q in conservation(system).not_conserved if q.name == "energy"]
    assert "constraints move" in energy.reason


def test_results_read_in_the_repl():
    # the REPL shows the quantities, not pages of dataclass fields (issue 22)
    system = lg.load("cart_pole")
    conservation = system.conserved_quantities()
    assert repr(conservation).splitlines() == [
        "Conservation (cyclic coordinates: x)",
        "  p_x = l*m*theta_dot*cos(theta) + x_dot*(M + m)   (x is cyclic: the Lagrangian does "
        "not depend on it)",
        "  energy = g*l*m*cos(theta) + l**2*m*theta_dot**2/2 + l*m*theta_dot*x_dot*cos(theta) "
        "+ x_dot**2*(M + m)/2   (h = T + V, the total energy)",
    ]
    assert repr(conservation["p_x"]).startswith("<conserved p_x = l*m*theta_dot*cos(theta)")
    top, bottom = system.equilibria()
    assert repr(top) == "<Equilibrium theta = 0: unstable; omega^2 = -g*(M + m)/(M*l), 0>"
    assert repr(bottom.modes) == "<NormalModes marginal: omega^2 = 0, g*(M + m)/(M*l)>"
    assert repr(system.hamiltonian()).startswith("<Hamiltonian H = g*l*m*cos(theta) + ")
    assert repr(system).startswith(
        "<System 'Cart-pole': coordinates x, theta; parameters M = 1, m = 0.1, l = 0.5, g = 9.81"
    )
    assert repr(system.equations_of_motion()).startswith("Cart-pole   (coordinates: x, θ)")


def test_a_cause_whose_rate_is_a_float_zero_at_the_values_no_longer_acts():
    # a charge pushed by the input F: with F = 0.0 (a float, as runs give) neither its
    # momentum nor the energy has a cause left
    system = lg.System.from_lagrangian(
        "m*x_dot^2/2 - k*y^2/2 + m*y_dot^2/2", coordinates=["x", "y"], forces={"x": "F"}
    )
    result = conservation(system)
    causes = {q.name: q for q in result.not_conserved}
    F = system.symbol("F")
    for name in ("p_x", "energy"):
        assert causes[name].reasons_at({F: sympy.Float(0.0)}) == ()
        assert causes[name].reasons_at({F: sympy.Float(0.5)}) != ()

"""The contacts' symbolic forms: g'' = G q'' + kappa, checked along a path written out."""

from __future__ import annotations

import sympy

import lagrangian as lg
from lagrangian.codegen.contacts import contact_forms
from lagrangian.codegen.forms import symbolic_forms
from lagrangian.model.impacts import Impact


def test_the_second_derivative_of_a_moving_curved_gap_is_gradient_times_acceleration_plus_kappa():
    system = lg.System.from_energies(
        "m*(x_dot**2 + y_dot**2)/2", "0", coordinates=["x", "y"], parameters={"m": 1.0, "w": 2.0},
        impacts=(Impact(gap="y*cos(x) - sin(w*t)*x**2", restitution="1"),),
    )  # fmt: skip
    forms = symbolic_forms(system.equations_of_motion(), {})
    contacts = contact_forms(forms)
    (x, y), (vx, vy), t = forms.coordinates, forms.velocities, forms.time
    # an independent path: q(s) = q0 + v s + a s^2 / 2 at time t + s, differentiated twice
    s, ax, ay = sympy.symbols("s a_x a_y")
    point = {x: x + vx * s + ax * s**2 / 2, y: y + vy * s + ay * s**2 / 2, t: t + s}
    along = contacts.gaps[0].subs(point, simultaneous=True)
    expected = sympy.diff(along, s, 2).subs(s, 0)
    gradient = contacts.gradient[0]
    found = gradient[0] * ax + gradient[1] * ay + contacts.curvature[0]
    assert sympy.simplify(expected - found) == 0
    assert contacts.rate[0] == sympy.diff(contacts.gaps[0], t)
    assert contacts.names == ("contact1",)


def test_a_system_without_contacts_has_no_contact_forms():
    forms = symbolic_forms(lg.load("harmonic_oscillator").equations_of_motion(), {})
    assert contact_forms(forms) is None

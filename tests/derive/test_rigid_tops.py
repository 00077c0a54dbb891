"""Tops as 3-D rigid bodies, against the textbook (Goldstein ch. 5, Landau-Lifshitz §35-37).

- Heavy symmetric top (``heavy_top``, zxz Euler angles): the equations equal
  those SymPy's ``LagrangesMethod`` derives from the hand-typed Lagrangian
  L = I1'(θ'² + φ'² sin²θ)/2 + I3 (ψ' + φ' cosθ)²/2 - M g l cosθ (I1' = I1 + M l²,
  the moment about the fixed point); p_φ, p_ψ and the energy are found
  conserved; steady precession at the rates Ω that solve
  I1' cosθ Ω² - I3 ω3 Ω + M g l = 0.
- Sleeping top (Tait-Bryan zyx angles, regular upright): the steady spin ω3
  about the vertical is stable exactly when I3² ω3² > 4 I1' M g l (eigenvalues
  of the linearized flow), and in a simulation a tilted top stays up above the
  threshold and falls below it.
- Torque-free asymmetric top: the body angular velocity obeys Euler's equations
  I1 ω1' = (I2 - I3) ω2 ω3 (cyclically); energy and |L|² stay constant; a spin
  about the middle axis flips, about the largest or smallest it stays.
"""

from __future__ import annotations

import functools
import random

import numpy as np
import pytest
import sympy
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

import lagrangian as lg
from lagrangian.integrate import simulate

SLEEPING = """
name = "Top in yaw-pitch-roll angles"
coordinates = ["a", "b", "c"]
[parameters]
M = 1.0
l = 0.3
g = 9.81
I1 = 0.02
I3 = 0.03
[[bodies]]
mass = "M"
position = ["l*(cos(a)*sin(b)*cos(c) + sin(a)*sin(c))", "l*(sin(a)*sin(b)*cos(c) - cos(a)*sin(c))",
            "l*cos(b)*cos(c)"]
inertia = ["I1", "I1", "I3"]
orientation = {euler = ["a", "b", "c"], convention = "zyx"}
[gravity]
g = "g"
"""

TORQUE_FREE = """
name = "Torque-free asymmetric top"
coordinates = ["phi", "theta", "psi"]
[parameters]
I1 = 1.0
I2 = 2.0
I3 = 3.0
[[bodies]]
mass = 1
position = [0, 0, 0]
inertia = ["I1", "I2", "I3"]
orientation = {euler = ["phi", "theta", "psi"], convention = "zxz"}
"""


@pytest.fixture(scope="module")
def heavy_top():
    system = lg.load("heavy_top")
    return system, lg.compile_equations(system.equations_of_motion())


@pytest.fixture(scope="module")
def sleeping_top():
    system = lg.loads(SLEEPING)
    return system, lg.compile_equations(system.equations_of_motion())


@pytest.fixture(scope="module")
def torque_free_top():
    system = lg.loads(TORQUE_FREE)
    return system, lg.compile_equations(system.equations_of_motion())


def rates(compiled, y, overrides=None):
    return compiled.rhs(0.0, np.asarray(y, float), compiled.parameter_vector(overrides or {}))


def body_omega(phi, theta, psi, phi_dot, theta_dot, psi_dot):
    """The body-frame angular velocity of zxz Euler angles (Goldstein eq. 4.125)."""
    return np.array(
        [
            phi_dot * np.sin(theta) * np.sin(psi) + theta_dot * np.cos(psi),
            phi_dot * np.sin(theta) * np.cos(psi) - theta_dot * np.sin(psi),
            phi_dot * np.cos(theta) + psi_dot,
        ]
    )


# -- heavy symmetric top ---------------------------------------------------------------
@functools.cache
def textbook_equations():
    """M and f of the hand-typed Lagrangian by SymPy's LagrangesMethod (formed once), with
    the parameters and the state they are functions of."""
    phi, theta, psi = dynamicsymbols("phi theta psi")
    M, l, g, I1, I3 = sympy.symbols("M l g I1 I3")
    t = dynamicsymbols._t
    d = [x.diff(t) for x in (phi, theta, psi)]
    pivot = I1 + M * l**2
    lagrangian = (
        pivot * (d[1] ** 2 + d[0] ** 2 * sympy.sin(theta) ** 2) / 2
        + I3 * (d[2] + d[0] * sympy.cos(theta)) ** 2 / 2
        - M * g * l * sympy.cos(theta)
    )
    method = LagrangesMethod(lagrangian, [phi, theta, psi])
    method.form_lagranges_equations()
    return method.mass_matrix, method.forcing, (M, l, g, I1, I3), (phi, theta, psi, *d)


def textbook_accelerations(values, state):
    """q'' of the hand-typed Lagrangian at the parameter ``values`` and ``state``."""
    mass, forcing, (M, l, g, I1, I3), state_symbols = textbook_equations()
    numbers = {M: values["M"], l: values["l"], g: values["g"], I1: values["I1"], I3: values["I3"]}
    numbers.update(dict(zip(state_symbols, state, strict=True)))
    mass = np.array(mass.subs(numbers), float)
    forcing = np.array(forcing.subs(numbers), float).ravel()
    return np.linalg.solve(mass, forcing)


@pytest.mark.slow
def test_heavy_top_equations_equal_the_textbook_lagrangians(heavy_top):
    _, compiled = heavy_top
    rng = random.Random(1)
    for _ in range(4):
        values = {"M": rng.uniform(0.5, 2), "l": rng.uniform(0.2, 1), "g": 9.81}
        values |= {"I1": rng.uniform(0.5, 1), "I3": rng.uniform(0.2, 1)}
        state = [rng.uniform(-3, 3), rng.uniform(0.3, 2.8), rng.uniform(-3, 3)]
        state += [rng.uniform(-3, 3) for _ in range(3)]
        ours = rates(compiled, state, values)[3:]
        assert np.allclose(ours, textbook_accelerations(values, state), rtol=1e-10, atol=1e-10)


def test_heavy_top_conserves_both_cyclic_momenta_and_energy(heavy_top):
    system, _ = heavy_top
    found = system.conserved_quantities()
    assert {"p_phi", "p_psi", "energy"} <= set(found.names)
    assert set(found.cyclic_coordinates) == {"phi", "psi"}
    s = system.symbols
    theta, phi_dot, psi_dot = s["theta"], s["phi_dot"], s["psi_dot"]
    pivot = s["I1"] + s["M"] * s["l"] ** 2
    spin = s["I3"] * (psi_dot + phi_dot * sympy.cos(theta))
    expected = {  # Goldstein eqs. 5.63-5.64
        "p_phi": pivot * sympy.sin(theta) ** 2 * phi_dot + spin * sympy.cos(theta),
        "p_psi": spin,
    }
    rng = random.Random(4)
    for name, reference in expected.items():
        ours = next(q.expression for q in found.conserved if q.name == name)
        for _ in range(3):
            point = {x: rng.uniform(0.3, 2.5) for x in ours.free_symbols | reference.free_symbols}
            assert float(ours.xreplace(point)) == pytest.approx(float(reference.xreplace(point)))


@pytest.mark.parametrize("theta0", [0.4, 1.0, 2.2])
def test_steady_precession_at_the_closed_form_rates(theta0, heavy_top):
    system, compiled = heavy_top
    p = system.parameter_values
    pivot = p["I1"] + p["M"] * p["l"] ** 2
    spin = 100.0  # omega3 = psi' + phi' cos(theta)
    roots = np.roots([pivot * np.cos(theta0), -p["I3"] * spin, p["M"] * p["g"] * p["l"]])
    assert np.all(np.isreal(roots))
    for precession in [*roots.real, roots.real.mean()]:
        state = [0.3, theta0, 0.0, precession, 0.0, spin - precession * np.cos(theta0)]
        theta_ddot = rates(compiled, state)[4]
        if precession in roots.real:
            assert abs(theta_ddot) < 1e-9 * (1 + precession**2)
        else:  # between the roots the top does not precess steadily
            assert abs(theta_ddot) > 1.0
    slow = float(min(roots.real, key=abs))
    run = simulate(
        compiled,
        t_end=1.0,
        initial={"theta": theta0, "phi_dot": slow, "psi_dot": spin - slow * np.cos(theta0)},
        n_out=51,
    )
    assert np.ptp(run["theta"]) < 1e-6
    assert np.allclose(run["phi_dot"], slow, rtol=1e-6)


# -- sleeping top ------------------------------------------------------------------------
def sleeping_threshold(p):
    pivot = p["I1"] + p["M"] * p["l"] ** 2
    return np.sqrt(4 * pivot * p["M"] * p["g"] * p["l"]) / p["I3"]


@pytest.mark.slow
def test_upright_spin_is_stable_exactly_above_the_sleeping_top_threshold(sleeping_top):
    system, compiled = sleeping_top
    critical = sleeping_threshold(system.parameter_values)
    for factor, stable in [(0.9, False), (0.99, False), (1.01, True), (1.5, True)]:
        upright = np.array([0.2, 0, 0, factor * critical, 0, 0])
        assert np.allclose(rates(compiled, upright)[3:], 0, atol=1e-12)  # a steady motion
        h = 1e-6
        jacobian = np.column_stack(
            [
                (rates(compiled, upright + h * e) - rates(compiled, upright - h * e)) / (2 * h)
                for e in np.eye(6)
            ]
        )
        growth = np.linalg.eigvals(jacobian).real.max()
        assert (growth < 1e-4) == stable, (factor, growth)


@pytest.mark.slow
@pytest.mark.parametrize(("factor", "stays_up"), [(1.1, True), (0.9, False)])
def test_a_top_spun_above_the_threshold_stays_up_below_it_falls(factor, stays_up, sleeping_top):
    """Released tilted by 0.02 rad, spinning about its own axis at factor x the threshold
    (omega_body = (0, 0, w): a' = w / cos b, c' = w tan b at b = 0.02, c = 0)."""
    system, compiled = sleeping_top
    spin, tilt0 = factor * sleeping_threshold(system.parameter_values), 0.02
    initial = {"b": tilt0, "a_dot": spin / np.cos(tilt0), "c_dot": spin * np.tan(tilt0)}
    run = simulate(compiled, t_end=2.0, initial=initial, n_out=201)
    tilt = np.arccos(np.cos(run["b"]) * np.cos(run["c"]))  # body axis from the vertical
    if stays_up:
        assert tilt.max() < 5 * tilt0, tilt.max()
    else:
        assert tilt.max() > 0.5, tilt.max()


# -- torque-free asymmetric top --------------------------------------------------------
@pytest.mark.slow
def test_torque_free_top_obeys_eulers_equations(torque_free_top):
    _, compiled = torque_free_top
    moments = np.array([1.0, 2.0, 3.0])
    rng = random.Random(2)
    for _ in range(4):
        y = np.array([rng.uniform(-3, 3), rng.uniform(0.3, 2.8), rng.uniform(-3, 3)]
                     + [rng.uniform(-2, 2) for _ in range(3)])  # fmt: skip
        dy = rates(compiled, y)
        h = 1e-6  # omega' along the motion: d/dt omega(q(t), q'(t)), central difference
        omega_dot = (body_omega(*(y + h * dy)) - body_omega(*(y - h * dy))) / (2 * h)
        w = body_omega(*y)
        torque_free = [
            moments[0] * omega_dot[0] - (moments[1] - moments[2]) * w[1] * w[2],
            moments[1] * omega_dot[1] - (moments[2] - moments[0]) * w[2] * w[0],
            moments[2] * omega_dot[2] - (moments[0] - moments[1]) * w[0] * w[1],
        ]
        assert np.allclose(torque_free, 0, atol=1e-7)
        assert abs(moments[0] * omega_dot[0]) > 1e-3  # not trivially zero


def spin_about(axis, rate=2.0, wobble=1e-3):
    """Initial Euler angles and rates for omega_body = rate e_axis + wobble (other axes)."""
    angles = np.array([0.3, np.pi / 2, 0.4])
    omega = np.full(3, wobble)
    omega[axis] = rate
    _phi, theta, psi = angles
    matrix = np.array(  # omega_body = E (phi', theta', psi')
        [
            [np.sin(theta) * np.sin(psi), np.cos(psi), 0],
            [np.sin(theta) * np.cos(psi), -np.sin(psi), 0],
            [np.cos(theta), 0, 1],
        ]
    )
    speeds = np.linalg.solve(matrix, omega)
    names = ["phi", "theta", "psi"]
    return dict(zip(names, angles, strict=True)) | {
        f"{n}_dot": v for n, v in zip(names, speeds, strict=True)
    }


@pytest.mark.parametrize(("axis", "flips"), [(0, False), (1, True), (2, False)])
def test_spin_about_the_middle_axis_flips_about_the_others_it_stays(axis, flips, torque_free_top):
    _, compiled = torque_free_top
    run = simulate(compiled, t_end=12.0, initial=spin_about(axis), n_out=1201)
    state = [run[n] for n in ("phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot")]
    omega = body_omega(*state)  # (3, T)
    moments = np.array([1.0, 2.0, 3.0])[:, None]
    energy = (moments * omega**2).sum(axis=0) / 2
    momentum = ((moments * omega) ** 2).sum(axis=0)
    assert np.ptp(energy) < 1e-7 * energy[0] and np.ptp(momentum) < 1e-7 * momentum[0]
    assert (omega[axis].min() < -1.0) == flips

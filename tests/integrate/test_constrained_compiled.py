"""Constrained systems in the compiled DOP853 loop (integrate.compiled_dop853), projected.

Every check is against something the loop does not compute: the constraint functions
evaluated by the NumPy backend, SciPy's loop on the same equations, the solution of the
same motion in unconstrained coordinates (the simple pendulum's angle, a bead's angle on
its hoop, the spherical pendulum's angles) integrated by SciPy's DOP853 on a hand-written
right-hand side, the rolling disc's closed form and the pendulum's tension
m (g cos theta + l theta'^2).  The four-bar linkage is written by hand: three rod angles
and the two loop-closure equations.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian as lg
from lagrangian.integrate import Event, simulate
from lagrangian.integrate.compiled_dop853 import compiled_loop
from lagrangian.integrate.simulate import along
from lagrangian.numeric import compile_equations

pytest.importorskip("numba")

#: Crank a, coupler b, rocker c, ground d (a Grashof crank-rocker): three uniform rods.
FOUR_BAR = """
name = "Four-bar linkage"
coordinates = ["th1", "th2", "th3"]
kinetic = "m1*a^2*th1_dot^2/6 + m2*(a^2*th1_dot^2 + b^2*th2_dot^2/4 + a*b*th1_dot*th2_dot*cos(th1 - th2))/2 + m2*b^2*th2_dot^2/24 + m3*c^2*th3_dot^2/6"
potential = "g*(m1*a*sin(th1)/2 + m2*(a*sin(th1) + b*sin(th2)/2) + m3*c*sin(th3)/2)"
constraints = ["a*cos(th1) + b*cos(th2) - c*cos(th3) - d", "a*sin(th1) + b*sin(th2) - c*sin(th3)"]

[parameters]
m1 = 1.0
m2 = 2.0
m3 = 1.5
a = 1.0
b = 3.0
c = 2.5
d = 3.0
g = 9.81
"""  # noqa: E501
LINKS = {"a": 1.0, "b": 3.0, "c": 2.5, "d": 3.0}

#: A bead on a hoop of radius R turning at omega about the vertical z axis, in Cartesian
#: coordinates: on the sphere of radius R and in the hoop's turning plane (rheonomic).
HOOP = """
name = "Bead on a turning hoop"
coordinates = ["x", "y", "z"]
kinetic = "m*(x_dot^2 + y_dot^2 + z_dot^2)/2"
potential = "m*g*z"
constraints = ["x^2 + y^2 + z^2 - R^2", "x*sin(omega*t) - y*cos(omega*t)"]

[parameters]
m = 1.0
g = 9.81
R = 1.0
omega = 5.0
"""

#: A particle on a sphere of radius l under gravity (the spherical pendulum).
SPHERE = """
name = "Particle on a sphere"
coordinates = ["x", "y", "z"]
kinetic = "m*(x_dot^2 + y_dot^2 + z_dot^2)/2"
potential = "m*g*z"
constraints = ["x^2 + y^2 + z^2 - l^2"]

[parameters]
m = 1.0
g = 9.81
l = 1.0
"""


#: A knife edge (Chaplygin's sled without its offset) on the plane z = 0: a holonomic and a
#: nonholonomic constraint together (the position projection leaves the latter's row out).
SKATE = """
name = "Skate on a plane"
coordinates = ["x", "y", "z", "phi"]
kinetic = "m*(x_dot^2 + y_dot^2 + z_dot^2)/2 + I*phi_dot^2/2"
potential = "m*g*z"
constraints = ["z", "sin(phi)*x_dot - cos(phi)*y_dot"]

[parameters]
m = 1.0
I = 0.2
g = 9.81
"""


@functools.cache
def compiled(model: str, backend: str):
    system = lg.loads(model) if "\n" in model else lg.load(model)
    return compile_equations(system.equations_of_motion(), backend=backend)


def states(run) -> np.ndarray:
    return np.stack([run[name] for name in (*run.coordinates, *run.velocities)])


def residual(system, run) -> np.ndarray:
    """|c(q, t)| (holonomic) or |A q' + a0| along ``run``, by the NumPy functions."""
    return np.abs(along(system.constraint_residual, run.t, states(run), params(system)))


def params(system) -> np.ndarray:
    return system.parameter_vector({})


def four_bar_start(th1: float, th1_dot: float) -> dict[str, float]:
    """A state on the loop: the coupler-rocker joint where the circles about the crank's
    end (radius b) and the rocker's pivot (radius c) meet, above the ground; the angular
    velocities from the differentiated loop equations."""
    a, b, c, d = (LINKS[k] for k in "abcd")
    crank = np.array([a * np.cos(th1), a * np.sin(th1)])
    pivot = np.array([d, 0.0])
    gap = pivot - crank
    distance = np.linalg.norm(gap)
    along_gap = (b**2 - c**2 + distance**2) / (2 * distance)
    height = np.sqrt(b**2 - along_gap**2)
    normal = np.array([-gap[1], gap[0]]) / distance
    joint = crank + along_gap * gap / distance + height * normal
    th2 = np.arctan2(*(joint - crank)[::-1])
    th3 = np.arctan2(*(joint - pivot)[::-1])
    # b th2' e2perp - c th3' e3perp = -a th1' e1perp
    matrix = np.array([[-b * np.sin(th2), c * np.sin(th3)], [b * np.cos(th2), -c * np.cos(th3)]])
    right = -th1_dot * a * np.array([-np.sin(th1), np.cos(th1)])
    th2_dot, th3_dot = np.linalg.solve(matrix, right)
    return {"th1": th1, "th2": th2, "th3": th3, "th1_dot": th1_dot, "th2_dot": th2_dot,
            "th3_dot": th3_dot}  # fmt: skip


FOUR_BAR_START = four_bar_start(1.2, 3.0)


def test_the_start_is_on_the_loop():  # the helper the tests below rely on
    system = compiled(FOUR_BAR, "numpy")
    y0 = system.state_vector(FOUR_BAR_START)
    assert np.abs(system.constraint_velocity_residual(0.0, y0, params(system))).max() < 1e-14
    assert np.abs(system.constraint_residual(0.0, y0, params(system))).max() < 1e-14


def test_the_four_bar_keeps_its_loop_closed_and_its_energy():
    system = compiled(FOUR_BAR, "numba")
    assert compiled_loop(system) is not None
    run = simulate(system, t_end=100.0, initial=FOUR_BAR_START)
    assert run.status == "success" and run.t[-1] == 100.0
    assert residual(system, run).max() <= 1e-10  # every step, projected in the loop
    assert np.abs(run["energy"] - run["energy"][0]).max() <= 1e-7 * np.abs(run["energy"]).max()
    # the velocity level too: the joints' relative velocities along the loop are 0
    velocity = along(system.constraint_velocity_residual, run.t, states(run), params(system))
    assert np.abs(velocity).max() <= 1e-10


@pytest.mark.slow  # the figure: 1000 s, about 60,000 steps
def test_the_four_bar_keeps_its_loop_closed_for_1000_s():
    system = compiled(FOUR_BAR, "numba")
    run = simulate(system, t_end=1000.0, initial=FOUR_BAR_START, n_out=20001)
    assert residual(system, run).max() <= 1e-10
    assert np.abs(run["energy"] - run["energy"][0]).max() <= 1e-6 * np.abs(run["energy"]).max()


def test_the_compiled_loop_agrees_with_scipys_loop():
    options = {"t_end": 5.0, "initial": FOUR_BAR_START, "rtol": 1e-12, "atol": 1e-12}
    ours = simulate(compiled(FOUR_BAR, "numba"), n_out=51, **options)
    scipy = simulate(compiled(FOUR_BAR, "numpy"), n_out=51, **options)
    np.testing.assert_allclose(states(ours), states(scipy), rtol=0, atol=1e-8)
    # SciPy's loop lets the residual wander at the tolerance (Baumgarte's damping only)
    assert (
        residual(compiled(FOUR_BAR, "numpy"), scipy).max()
        > 10 * residual(compiled(FOUR_BAR, "numba"), ours).max()
    )
    for name in ours.multipliers:
        np.testing.assert_allclose(ours[name], scipy[name], rtol=1e-7, atol=1e-7)


def pendulum_angle(theta0: float, t: np.ndarray, g: float = 9.81, l: float = 1.0):
    """(theta, theta') of theta'' = -(g/l) sin(theta) from rest, by SciPy at rtol 1e-13."""
    solution = solve_ivp(
        lambda _, s: [s[1], -g / l * np.sin(s[0])], (0.0, t[-1]), [theta0, 0.0],
        method="DOP853", t_eval=t, rtol=1e-13, atol=1e-14,
    )  # fmt: skip
    return solution.y


def test_the_cartesian_pendulum_follows_the_angle_and_its_tension():
    system = compiled("cartesian_pendulum", "numba")
    theta0 = 1.0  # the model's start: x = sin 1, y = -cos 1, at rest
    run = simulate(system, t_end=10.0, n_out=201, rtol=1e-12, atol=1e-14)
    theta, theta_dot = pendulum_angle(theta0, run.t)
    np.testing.assert_allclose(run["x"], np.sin(theta), rtol=0, atol=1e-9)
    np.testing.assert_allclose(run["y"], -np.cos(theta), rtol=0, atol=1e-9)
    tension = 1.0 * (9.81 * np.cos(theta) + 1.0 * theta_dot**2)  # m (g cos + l theta'^2)
    np.testing.assert_allclose(-2 * 1.0 * run["lambda1"], tension, rtol=0, atol=1e-7)
    assert residual(system, run).max() <= 1e-13  # the outputs are projected too


def test_the_rolling_disc_rolls_as_its_closed_form():
    system = compiled("rolling_disc", "numba")
    run = simulate(system, t_end=10.0, n_out=101)
    # phi' = 0.5 and theta' = 2 are constant; x' = R cos(phi) theta', y' = R sin(phi) theta'
    phi = 0.5 * run.t
    rate = 0.5 * 2.0 / 0.5  # R theta' / phi'
    np.testing.assert_allclose(run["phi"], phi, atol=1e-9)
    np.testing.assert_allclose(run["theta"], 2.0 * run.t, atol=1e-9)
    np.testing.assert_allclose(run["x"], rate * np.sin(phi), atol=1e-9)
    np.testing.assert_allclose(run["y"], rate * (1 - np.cos(phi)), atol=1e-9)
    assert residual(system, run).max() <= 1e-13
    scipy = simulate(compiled("rolling_disc", "numpy"), t_end=10.0, n_out=101)
    np.testing.assert_allclose(states(run), states(scipy), atol=1e-8)


@pytest.mark.slow  # its derivation alone takes 2.4 s (trigsimp of the Schur complement)
def test_a_bead_on_a_turning_hoop_follows_its_angle():  # held out: a rheonomic constraint
    system = compiled(HOOP, "numba")
    theta0, omega, g = 0.5, 5.0, 9.81
    start = {"x": np.sin(theta0), "y": 0.0, "z": -np.cos(theta0), "y_dot": omega * np.sin(theta0)}
    run = simulate(system, t_end=5.0, initial=start, n_out=101, rtol=1e-12, atol=1e-14)
    # theta'' = sin(theta) (omega^2 cos(theta) - g / R), theta from the bottom
    solution = solve_ivp(
        lambda _, s: [s[1], np.sin(s[0]) * (omega**2 * np.cos(s[0]) - g)], (0.0, 5.0),
        [theta0, 0.0], method="DOP853", t_eval=run.t, rtol=1e-13, atol=1e-14,
    )  # fmt: skip
    theta = solution.y[0]
    np.testing.assert_allclose(run["x"], np.sin(theta) * np.cos(omega * run.t), atol=1e-8)
    np.testing.assert_allclose(run["y"], np.sin(theta) * np.sin(omega * run.t), atol=1e-8)
    np.testing.assert_allclose(run["z"], -np.cos(theta), atol=1e-8)
    assert residual(system, run).max() <= 1e-13


def test_a_particle_on_a_sphere_moves_as_the_spherical_pendulum():  # held out
    system = compiled(SPHERE, "numba")
    theta0, phi_dot0, g = 2.0, 2.5, 9.81  # theta from the upward z axis: below the equator
    start = {"x": np.sin(theta0), "z": np.cos(theta0), "y_dot": np.sin(theta0) * phi_dot0}
    run = simulate(system, t_end=5.0, initial=start, n_out=101, rtol=1e-12, atol=1e-14)

    def angles(_, s):  # L = (theta'^2 + sin^2 theta phi'^2) / 2 - g cos theta
        theta, _, theta_dot, phi_dot = s
        return [theta_dot, phi_dot,
                np.sin(theta) * np.cos(theta) * phi_dot**2 + g * np.sin(theta),
                -2 * theta_dot * phi_dot * np.cos(theta) / np.sin(theta)]  # fmt: skip

    solution = solve_ivp(
        angles, (0.0, 5.0), [theta0, 0.0, 0.0, phi_dot0], method="DOP853", t_eval=run.t,
        rtol=1e-13, atol=1e-14,
    )  # fmt: skip
    theta, phi = solution.y[:2]
    np.testing.assert_allclose(run["x"], np.sin(theta) * np.cos(phi), atol=1e-8)
    np.testing.assert_allclose(run["y"], np.sin(theta) * np.sin(phi), atol=1e-8)
    np.testing.assert_allclose(run["z"], np.cos(theta), atol=1e-8)


def test_events_are_found_as_in_scipys_loop():
    crossing = Event(lambda t, y, p: y[0], direction=-1, name="x_down")
    stop = Event(lambda t, y, p: y[1] + 0.6, direction=1, terminal=True, name="high")
    options = {"t_end": 10.0, "events": (crossing, stop), "rtol": 1e-12, "atol": 1e-14}
    initial = {"x": 1.0, "y": 0.0}  # from horizontal: it swings through y = -0.6 upwards
    ours = simulate(compiled("cartesian_pendulum", "numba"), initial=initial, **options)
    scipy = simulate(compiled("cartesian_pendulum", "numpy"), initial=initial, **options)
    assert ours.status == scipy.status == "event"
    for name in ("x_down", "high"):
        np.testing.assert_allclose(ours.events[name].times, scipy.events[name].times, atol=1e-9)
    assert ours.events["x_down"].count == 1
    assert abs(np.hypot(ours["x"][-1], ours["y"][-1]) - 1.0) <= 1e-14  # the stop projected


def test_rk4_runs_compiled_with_its_projection_as_the_python_loop():
    from lagrangian.integrate.compiled_loop import ProjectedLoop, compiled_loop
    from lagrangian.integrate.registry import method_class

    fast, slow = compiled("cartesian_pendulum", "numba"), compiled("cartesian_pendulum", "numpy")
    rk4 = method_class("rk4").configure(t_span=(0.0, 1.0), dt=0.001, rtol=None, atol=None)
    loop = compiled_loop(fast, rk4.printed_scheme(fast), rk4.newton_settings())
    assert isinstance(loop, ProjectedLoop)
    options = {"t_end": 1.0, "method": "rk4", "dt": 0.001, "initial": {"x": 0.6, "y": -0.8}}
    ours, python = simulate(fast, **options), simulate(slow, **options)
    assert ours.dataset.attrs["steps"] == python.dataset.attrs["steps"] == 1000
    np.testing.assert_allclose(states(ours), states(python), rtol=0, atol=1e-12)
    assert residual(fast, ours).max() <= 1e-14


def test_a_skate_turns_on_its_circle_held_on_the_plane():  # holonomic and not, together
    system = compiled(SKATE, "numba")
    speed, turn = 1.5, 0.8  # along the blade, and phi' (both constant: no force does work)
    start = {"x_dot": speed, "phi_dot": turn}
    run = simulate(system, t_end=10.0, initial=start, n_out=101, rtol=1e-12, atol=1e-14)
    phi = turn * run.t
    np.testing.assert_allclose(run["phi"], phi, atol=1e-9)
    np.testing.assert_allclose(run["x"], speed / turn * np.sin(phi), atol=1e-9)
    np.testing.assert_allclose(run["y"], speed / turn * (1 - np.cos(phi)), atol=1e-9)
    assert np.abs(run["z"]).max() <= 1e-15 and np.abs(run["z_dot"]).max() <= 1e-15
    assert residual(system, run).max() <= 1e-13
    scipy = simulate(compiled(SKATE, "numpy"), t_end=10.0, initial=start, n_out=101)
    np.testing.assert_allclose(states(run), states(scipy), atol=1e-8)

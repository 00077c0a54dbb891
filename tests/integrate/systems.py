"""Hand-written `CompiledSystem`s for the integrator tests, with their exact facts.

Each function of a CompiledSystem is written out with NumPy, vectorised over a
trailing batch axis like the compiled ones (y (2n,) or (2n, B)).  They do not
depend on ``compile_equations``: the integrators are tested against them and
against analytic solutions.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from lagrangian.numeric.compiled import CompiledSystem


def vector(*entries) -> np.ndarray:
    """(n, ...) from n entries broadcast to a common shape."""
    shapes = {np.shape(entry) for entry in entries}
    if len(shapes) == 1:
        return np.array(entries, dtype=float)
    return np.stack(np.broadcast_arrays(*entries))


def matrix(rows, like) -> np.ndarray:
    """(n, n, ...) from nested entries, broadcast to the batch shape of ``like``."""
    n = len(rows)
    result = np.empty((n, n, *np.shape(like)))
    for i, row in enumerate(rows):
        for j, entry in enumerate(row):
            result[i, j] = entry
    return result


def finite_difference_jacobian(rhs):
    """d rhs / d y by central differences (for single states; used where the test needs none)."""

    def jacobian(t, y, params):
        y = np.asarray(y, dtype=float)
        columns = []
        for j in range(y.shape[0]):
            step = 1e-7 * max(1.0, abs(y[j]))
            up, down = y.copy(), y.copy()
            up[j] += step
            down[j] -= step
            columns.append((rhs(t, up, params) - rhs(t, down, params)) / (2 * step))
        return np.stack(columns, axis=1)

    return jacobian


def _system(name, coordinates, defaults, initial, functions, **flags) -> CompiledSystem:
    system = SimpleNamespace(name=name, initial=dict(initial), units=None)  # as a unitless System
    equations = SimpleNamespace(system=system)
    return CompiledSystem(
        equations=equations,
        backend="numpy",
        coordinate_names=tuple(coordinates),
        parameter_names=tuple(defaults),
        default_parameters=dict(defaults),
        **functions,
        **flags,
    )


def _zero_forces(n):
    return {
        "nonconservative_forces": lambda t, q, v, p: np.zeros_like(q, dtype=float),
        "nonconservative_forces_jacobian_v": lambda t, q, v, p: np.zeros((n, *q.shape)),
        "nonconservative_forces_jacobian_q": lambda t, q, v, p: np.zeros((n, *q.shape)),
    }


# -- harmonic oscillator (optionally damped) --------------------------------------
def oscillator(*, damping: float = 0.0, separable: bool = True) -> CompiledSystem:
    """m x'' = -k x - b x', m = 1, k = 4 (omega = 2); x(0) = 1, x'(0) = 0.5.

    ``separable=False`` declares it non-separable so that the variational
    integrator takes its implicit midpoint (Newton) branch.
    """

    def rhs(t, y, p):
        m, k, b = p[0], p[1], p[2]
        return vector(y[1], (-k * y[0] - b * y[1]) / m)

    functions = {
        "rhs": rhs,
        "accelerations": lambda t, q, v, p: (-p[1] * q - p[2] * v) / p[0],
        "mass_matrix": lambda t, q, v, p: matrix([[p[0]]], q[0]),
        "forcing": lambda t, q, v, p: -p[1] * q - p[2] * v,
        "rhs_jacobian": lambda t, y, p: matrix([[0.0, 1.0], [-p[1] / p[0], -p[2] / p[0]]], y[0]),
        "energy": lambda t, y, p: p[0] * y[1] ** 2 / 2 + p[1] * y[0] ** 2 / 2,
        "lagrangian": lambda t, q, v, p: p[0] * v[0] ** 2 / 2 - p[1] * q[0] ** 2 / 2,
        "momenta": lambda t, q, v, p: p[0] * v,
        "lagrangian_gradient": lambda t, q, v, p: -p[1] * q,
        "momenta_jacobian_q": lambda t, q, v, p: matrix([[0.0]], q[0]),
        "lagrangian_hessian_q": lambda t, q, v, p: matrix([[-p[1]]], q[0]),
        "nonconservative_forces": lambda t, q, v, p: -p[2] * v,
        "nonconservative_forces_jacobian_v": lambda t, q, v, p: matrix([[-p[2]]], q[0]),
        "nonconservative_forces_jacobian_q": lambda t, q, v, p: matrix([[0.0]], q[0]),
    }
    return _system(
        "Oscillator",
        ["x"],
        {"m": 1.0, "k": 4.0, "b": damping},
        {"x": 1.0, "x_dot": 0.5},
        functions,
        separable=separable and damping == 0.0,
        constant_mass_matrix=True,
    )


def oscillator_exact(t, x0=1.0, v0=0.5, m=1.0, k=4.0, b=0.0) -> np.ndarray:
    """[x, x'] of the (under)damped oscillator at times t."""
    gamma = b / (2 * m)
    omega = np.sqrt(k / m - gamma**2)
    a, c = x0, (v0 + gamma * x0) / omega
    decay = np.exp(-gamma * t)
    x = decay * (a * np.cos(omega * t) + c * np.sin(omega * t))
    v = decay * (
        -gamma * (a * np.cos(omega * t) + c * np.sin(omega * t))
        + omega * (-a * np.sin(omega * t) + c * np.cos(omega * t))
    )
    return np.array([x, v])


# -- plane pendulum -------------------------------------------------------------------
def pendulum(*, separable: bool = True, theta0: float = 1.0) -> CompiledSystem:
    """L = m l^2 theta'^2/2 + m g l cos(theta); m = 1, l = 2, g = 9.81."""

    def rhs(t, y, p):
        return vector(y[1], -p[2] / p[1] * np.sin(y[0]))

    functions = {
        "rhs": rhs,
        "accelerations": lambda t, q, v, p: -p[2] / p[1] * np.sin(q),
        "mass_matrix": lambda t, q, v, p: matrix([[p[0] * p[1] ** 2]], q[0]),
        "forcing": lambda t, q, v, p: -p[0] * p[2] * p[1] * np.sin(q),
        "rhs_jacobian": lambda t, y, p: matrix(
            [[0.0, 1.0], [-p[2] / p[1] * np.cos(y[0]), 0.0]], y[0]
        ),
        "energy": lambda t, y, p: (
            p[0] * p[1] ** 2 * y[1] ** 2 / 2 - p[0] * p[2] * p[1] * np.cos(y[0])
        ),
        "lagrangian": lambda t, q, v, p: (
            p[0] * p[1] ** 2 * v[0] ** 2 / 2 + p[0] * p[2] * p[1] * np.cos(q[0])
        ),
        "momenta": lambda t, q, v, p: p[0] * p[1] ** 2 * v,
        "lagrangian_gradient": lambda t, q, v, p: -p[0] * p[2] * p[1] * np.sin(q),
        "momenta_jacobian_q": lambda t, q, v, p: matrix([[0.0]], q[0]),
        "lagrangian_hessian_q": lambda t, q, v, p: matrix(
            [[-p[0] * p[2] * p[1] * np.cos(q[0])]], q[0]
        ),
        **_zero_forces(1),
    }
    return _system(
        "Pendulum",
        ["theta"],
        {"m": 1.0, "l": 2.0, "g": 9.81},
        {"theta": theta0},
        functions,
        separable=separable,
        constant_mass_matrix=True,
    )


# -- Kepler problem in the plane --------------------------------------------------------
def kepler() -> CompiledSystem:
    """L = (x'^2 + y'^2)/2 + mu/r, mu = 1; invariant ``angular_momentum`` x y' - y x'."""

    def gradient(t, q, v, p):
        r3 = (q[0] ** 2 + q[1] ** 2) ** 1.5
        return -p[0] * q / r3

    def rhs(t, y, p):
        return np.concatenate([y[2:], gradient(t, y[:2], y[2:], p)])

    def hessian(t, q, v, p):
        x, y = q[0], q[1]
        r2 = x**2 + y**2
        r3, r5 = r2**1.5, r2**2.5
        mu = p[0]
        return matrix(
            [
                [mu * (3 * x * x / r5 - 1 / r3), mu * 3 * x * y / r5],
                [mu * 3 * x * y / r5, mu * (3 * y * y / r5 - 1 / r3)],
            ],
            x,
        )

    functions = {
        "rhs": rhs,
        "accelerations": gradient,
        "mass_matrix": lambda t, q, v, p: matrix([[1.0, 0.0], [0.0, 1.0]], q[0]),
        "forcing": gradient,
        "rhs_jacobian": finite_difference_jacobian(rhs),
        "energy": lambda t, y, p: (y[2] ** 2 + y[3] ** 2) / 2 - p[0] / np.hypot(y[0], y[1]),
        "lagrangian": lambda t, q, v, p: (v[0] ** 2 + v[1] ** 2) / 2 + p[0] / np.hypot(q[0], q[1]),
        "momenta": lambda t, q, v, p: np.asarray(v, dtype=float),
        "lagrangian_gradient": gradient,
        "momenta_jacobian_q": lambda t, q, v, p: matrix([[0.0, 0.0], [0.0, 0.0]], q[0]),
        "lagrangian_hessian_q": hessian,
        **_zero_forces(2),
    }
    e = 0.5
    initial = {"x": 1 - e, "y": 0.0, "x_dot": 0.0, "y_dot": np.sqrt((1 + e) / (1 - e))}
    return _system(
        "Kepler",
        ["x", "y"],
        {"mu": 1.0},
        initial,
        functions,
        invariants={"angular_momentum": lambda t, y, p: y[0] * y[3] - y[1] * y[2]},
        separable=True,
        constant_mass_matrix=True,
    )


# -- spherical pendulum -------------------------------------------------------------------
def spherical_pendulum() -> CompiledSystem:
    """L = m l^2 (theta'^2 + sin^2 theta phi'^2)/2 + m g l cos theta; phi is cyclic.

    m = 1.5, l = 0.8, g = 9.81; invariant ``p_phi`` = m l^2 sin^2 theta phi'.
    """

    def rhs(t, y, p):
        th, _, w_th, w_ph = y
        return vector(
            w_th,
            w_ph,
            np.sin(th) * np.cos(th) * w_ph**2 - p[2] / p[1] * np.sin(th),
            -2 * np.cos(th) / np.sin(th) * w_th * w_ph,
        )

    def momenta(t, q, v, p):
        ml2 = p[0] * p[1] ** 2
        return vector(ml2 * v[0], ml2 * np.sin(q[0]) ** 2 * v[1])

    def gradient(t, q, v, p):
        ml2 = p[0] * p[1] ** 2
        th = q[0]
        return vector(
            ml2 * np.sin(th) * np.cos(th) * v[1] ** 2 - p[0] * p[2] * p[1] * np.sin(th),
            np.zeros_like(th),
        )

    def mass(t, q, v, p):
        ml2 = p[0] * p[1] ** 2
        return matrix([[ml2, 0.0], [0.0, ml2 * np.sin(q[0]) ** 2]], q[0])

    def momenta_q(t, q, v, p):  # dp_i / dq_j
        ml2 = p[0] * p[1] ** 2
        return matrix([[0.0, 0.0], [ml2 * np.sin(2 * q[0]) * v[1], 0.0]], q[0])

    def hessian(t, q, v, p):
        ml2 = p[0] * p[1] ** 2
        th = q[0]
        d2 = ml2 * np.cos(2 * th) * v[1] ** 2 - p[0] * p[2] * p[1] * np.cos(th)
        return matrix([[d2, 0.0], [0.0, 0.0]], th)

    def energy(t, y, p):
        ml2 = p[0] * p[1] ** 2
        kinetic = ml2 * (y[2] ** 2 + np.sin(y[0]) ** 2 * y[3] ** 2) / 2
        return kinetic - p[0] * p[2] * p[1] * np.cos(y[0])

    functions = {
        "rhs": rhs,
        "accelerations": lambda t, q, v, p: rhs(t, np.concatenate([q, v]), p)[2:],
        "mass_matrix": mass,
        "forcing": lambda t, q, v, p: gradient(t, q, v, p),  # not used here
        "rhs_jacobian": finite_difference_jacobian(rhs),
        "energy": energy,
        "lagrangian": lambda t, q, v, p: energy(t, np.concatenate([q, v]), p),  # not used
        "momenta": momenta,
        "lagrangian_gradient": gradient,
        "momenta_jacobian_q": momenta_q,
        "lagrangian_hessian_q": hessian,
        **_zero_forces(2),
    }
    return _system(
        "Spherical pendulum",
        ["theta", "phi"],
        {"m": 1.5, "l": 0.8, "g": 9.81},
        {"theta": 1.0, "theta_dot": 0.3, "phi_dot": 2.0},
        functions,
        invariants={
            "p_phi": lambda t, y, p: p[0] * p[1] ** 2 * np.sin(y[0]) ** 2 * y[3],
        },
    )


# -- a pendulum as a constrained particle -------------------------------------------------
def constrained_pendulum(baumgarte: float = 10.0) -> CompiledSystem:
    """A particle (x, y) with x^2 + y^2 = l^2 (multiplier lambda1), l = 1, g = 9.81.

    m a = (0, -m g) + 2 lambda (x, y), with Baumgarte stabilisation
    phi'' + 2 alpha phi' + alpha^2 phi = 0 of phi = x^2 + y^2 - l^2.
    """
    alpha = baumgarte

    def multiplier(t, y, p):
        m, l, g = p[0], p[1], p[2]
        x, yy, vx, vy = y
        r2 = x**2 + y[1] ** 2
        phi = r2 - l**2
        phi_dot = 2 * (x * vx + yy * vy)
        mu = (-(vx**2 + vy**2) + g * yy - alpha * phi_dot - alpha**2 * phi / 2) / r2
        return m * mu / 2

    def rhs(t, y, p):
        mu = 2 * multiplier(t, y, p) / p[0]
        return vector(y[2], y[3], mu * y[0], -p[2] + mu * y[1])

    def project(t, y, p):
        y = np.array(y, dtype=float)
        r = np.hypot(y[0], y[1])
        y[:2] = y[:2] * (p[1] / r)
        radial = (y[0] * y[2] + y[1] * y[3]) / p[1] ** 2
        y[2:] = y[2:] - radial * y[:2]
        return y

    unused = lambda t, q, v, p: np.zeros_like(q, dtype=float)  # noqa: E731
    functions = {
        "rhs": rhs,
        "accelerations": lambda t, q, v, p: rhs(t, np.concatenate([q, v]), p)[2:],
        "mass_matrix": lambda t, q, v, p: matrix([[p[0], 0.0], [0.0, p[0]]], q[0]),
        "forcing": unused,
        "rhs_jacobian": finite_difference_jacobian(rhs),
        "energy": lambda t, y, p: p[0] * (y[2] ** 2 + y[3] ** 2) / 2 + p[0] * p[2] * y[1],
        "lagrangian": unused,
        "momenta": lambda t, q, v, p: p[0] * v,
        "lagrangian_gradient": lambda t, q, v, p: vector(
            np.zeros_like(q[0]), -p[0] * p[2] + 0 * q[1]
        ),
        "momenta_jacobian_q": lambda t, q, v, p: np.zeros((2, *q.shape)),
        "lagrangian_hessian_q": lambda t, q, v, p: np.zeros((2, *q.shape)),
        **_zero_forces(2),
    }
    return _system(
        "Constrained pendulum",
        ["x", "y"],
        {"m": 1.0, "l": 1.0, "g": 9.81},
        {"x": np.sin(1.0), "y": -np.cos(1.0)},
        functions,
        has_constraints=True,
        constraint_names=("lambda1",),
        multipliers=lambda t, y, p: multiplier(t, y, p)[None],
        constraint_residual=lambda t, y, p: (y[0] ** 2 + y[1] ** 2 - p[1] ** 2)[None],
        project=project,
    )

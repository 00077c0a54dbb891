"""The normal modes of a model about an equilibrium, drawn.

For a model with particles each mode is a stroboscopic picture of the
mechanism moving in that mode alone, q(φ) = q0 + A s cos φ for a few phases φ
(s the mode shape), the equilibrium in grey; A is chosen so that the largest
displacement of a particle is :data:`DISPLACEMENT` of the size of the
mechanism (the shapes fix only ratios).  Without particles the shapes are bar
charts, one bar per coordinate.  Titles give ω², ω and the period 2π/ω at the
parameter values.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from ..algebra import as_expression
from ..analysis import linearize, rest_points
from ..derive import derive
from ..errors import ModelError
from ..model import System
from .geometry import ORIGIN, geometry, rods
from .plots import math, new_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis import NormalModes

#: Largest particle displacement in a mode picture, as a fraction of the mechanism's size.
DISPLACEMENT = 0.25
PHASES = np.linspace(0, np.pi, 5)
#: Gauss-Newton steps at most that bring a drawn configuration back onto the constraints.
PROJECTION_STEPS = 20
#: Width of the pictures of a mechanism's modes with one panel, inches.
STROBE_MIN_WIDTH = 6.4


def mode_numbers(
    system: System,
    at: Mapping[str, object] | None = None,
    parameters=None,
    modes: NormalModes | None = None,
):
    """(point, ω² (k,), shapes (k, n)) of the normal modes about ``at``, as numbers.

    ``at`` None: the first stable equilibrium of :meth:`System.equilibria`;
    ``modes``: the normal modes about ``at`` when already computed.
    """
    values = dict(system.parameter_values)
    values.update(parameters or {})
    substitution = {p.symbol: values[p.name] for p in system.parameters if p.name in values}
    if at is None:
        chosen = equilibrium_for_modes(system, substitution)
        # the equilibrium's own modes: a family's are those at its representative member,
        # a singular point's those of its regular directions (linearize alone has neither)
        at = dict(getattr(chosen, "representative", None) or chosen.point)
        shapes = chosen.modes.shapes
        if modes is None and shapes and len(shapes[0]) == len(system.coordinates):
            modes = chosen.modes
    if modes is None:
        modes = linearize(derive(system.without_inputs()), at).normal_modes()
    if not modes.shapes:
        raise ModelError(
            f"no mode shapes about this point{': ' + modes.note if modes.note else ''}"
        )
    omega_squared = np.array(
        [complex(as_expression(w).subs(substitution)) for w in modes.omega_squared]
    ).real
    shapes = np.array(
        [[float(as_expression(x).subs(substitution)) for x in shape] for shape in modes.shapes]
    )
    point = {
        name: float(as_expression(at.get(name, 0)).subs(substitution))
        for name in system.coordinate_names
    }
    return point, omega_squared[: len(shapes)], shapes


def equilibrium_for_modes(system: System, substitution: Mapping) -> object:
    """The equilibrium whose modes are drawn: the first stable one, else the first that is
    stable apart from free motions (the sliding pendulum, the hanging cart-pole: marginal,
    each ω² = 0 a translation or rotation that leaves L unchanged, named in ``zero_modes``,
    and every other ω² > 0 at the values ``substitution``)."""
    points = rest_points(derive(system.without_inputs()))
    stable = [e for e in points if e.stable]
    free = [e for e in points if _stable_but_free(e, substitution)]
    if not stable and not free:
        raise ModelError("the model has no stable equilibrium to show normal modes about")
    return (stable or free)[0]


def _stable_but_free(e, substitution: Mapping) -> bool:
    zero_modes = getattr(e, "zero_modes", ())
    if not zero_modes or not e.modes.shapes:
        return False
    squares = [as_expression(w) for w in e.modes.omega_squared]
    zeros = [w for w in squares if w.is_zero]
    others = [complex(w.subs(substitution)) for w in squares if not w.is_zero]
    return len(zeros) == len(zero_modes) and all(w.real > 0 and w.imag == 0 for w in others)


def _mode_title(i: int, omega_squared: float, shape: np.ndarray, free: str = "") -> str:
    vector = "(" + ", ".join(f"{x:.3g}" for x in shape) + ")"
    if omega_squared > 0:
        omega = np.sqrt(omega_squared)
        return (
            f"mode {i + 1}: $\\omega$ = {omega:.4g}, $T$ = {2 * np.pi / omega:.4g}\nshape {vector}"
        )
    if omega_squared == 0 and free:
        return f"mode {i + 1}: $\\omega^2$ = 0, free motion:\n{free}"
    kind = "neutral" if omega_squared == 0 else "unstable"
    return f"mode {i + 1}: $\\omega^2$ = {omega_squared:.4g} ({kind})\nshape {vector}"


def plot_normal_modes(
    system: System,
    at: Mapping[str, object] | None = None,
    *,
    parameters=None,
    modes: NormalModes | None = None,
) -> Figure:
    """One panel per normal mode about ``at`` (see the module docstring, :func:`mode_numbers`);
    ``at`` None: about :func:`equilibrium_for_modes`, its free motions named."""
    free: list[str] = []
    if at is None:
        values = {**system.parameter_values, **(parameters or {})}
        substitution = {p.symbol: values[p.name] for p in system.parameters if p.name in values}
        chosen = equilibrium_for_modes(system, substitution)
        free = list(getattr(chosen, "zero_modes", ()))
        at = dict(getattr(chosen, "representative", None) or chosen.point)
        shapes = chosen.modes.shapes
        if modes is None and shapes and len(shapes[0]) == len(system.coordinates):
            modes = chosen.modes
    point, omega_squared, shapes = mode_numbers(system, at, parameters, modes)
    # the free motions, in the order of the zero ω² they explain
    names_of = iter(free)
    frees = [next(names_of, "") if w == 0 else "" for w in omega_squared]
    names = system.coordinate_names
    where = ", ".join(f"{math(n)} = {v:.3g}" for n, v in point.items())
    if free:
        where += " (stable apart from its free motion)"
    if system.particles:
        figure = _strobe(system, point, omega_squared, shapes, parameters, frees)
    else:
        figure, axes = new_figure(1, len(shapes), height=3.6)
        for i, (ax, shape) in enumerate(zip(axes[0], shapes, strict=True)):
            ax.bar(range(len(names)), shape, color=f"C{i}")
            ax.set_xticks(range(len(names)), [math(n) for n in names])
            ax.axhline(0, color="0.3", lw=0.8)
            ax.set_ylabel("relative amplitude")
            ax.set_title(_mode_title(i, omega_squared[i], shape, frees[i]), fontsize=9)
    figure.suptitle(f"{system.name}: normal modes about {where}")
    return figure


def _strobe(system, point, omega_squared, shapes, parameters, frees) -> Figure:
    scene = geometry(system, parameters)
    q0 = np.array([point[n] for n in system.coordinate_names])
    rest = scene.at(np.zeros(1), q0[:, None])
    size = max(
        float(
            np.ptp(np.concatenate([rest.particles[:, :, 0], [[0] * scene.dimension]]), axis=0).max()
        ),
        1e-9,
    )
    a, b = scene.views[0]
    # one panel alone is narrower than the figure's title ("Spherical pendulum: normal modes
    # about θ = 0, φ = 0" lost its ends at 4.2 in)
    width = max(3.6 * len(shapes) + 0.6, STROBE_MIN_WIDTH)
    figure, axes = new_figure(1, len(shapes), height=4.4, width=width)
    for i, (ax, shape) in enumerate(zip(axes[0], shapes, strict=True)):
        probe = scene.at(np.zeros(1), (q0 + 1e-6 * shape)[:, None])
        moved = float(np.abs(probe.particles - rest.particles).max()) / 1e-6
        amplitude = DISPLACEMENT * size / moved if moved > 0 else 0.0
        swing = q0[:, None] + amplitude * np.outer(shape, np.cos(PHASES))
        q = on_constraints(system, swing, parameters)
        snapshots = scene.at(np.zeros(PHASES.size), q)
        links = rods(snapshots)
        for k in range(PHASES.size):
            alpha = 0.25 + 0.75 * (k in (0, PHASES.size - 1))
            color = f"C{i}" if k in (0, PHASES.size - 1) else "0.6"
            _draw(ax, snapshots, links, k, a, b, color, alpha)
        _draw(ax, rest, rods(rest) or links, 0, a, b, "0.2", 1.0, dashed=True)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"${'xyz'[a]}$")
        ax.set_ylabel(f"${'xyz'[b]}$")
        ax.grid(True, alpha=0.3)
        ax.set_title(_mode_title(i, omega_squared[i], shape, frees[i]), fontsize=9)
    return figure


def on_constraints(system: System, q: np.ndarray, parameters=None) -> np.ndarray:
    """Configurations ``q`` (n, k) moved onto the system's holonomic constraints by
    Gauss-Newton steps of least norm: a constrained system's mode shape is tangent to its
    constraint surface, and q0 + A s cos(phi) alone would draw a pendulum's rod stretched."""
    if not system.constraints:
        return q
    import sympy

    values = {**system.parameter_values, **(parameters or {})}
    table = {p.symbol: values[p.name] for p in system.parameters if p.name in values}
    symbols = [c.q for c in system.coordinates]
    constraints = sympy.Matrix(list(system.constraints)).xreplace(table)
    gap = sympy.lambdify([symbols], list(constraints), "numpy")
    gradient = sympy.lambdify([symbols], constraints.jacobian(symbols).tolist(), "numpy")
    q = np.array(q, dtype=float)
    for k in range(q.shape[1]):
        for _ in range(PROJECTION_STEPS):
            residual = np.array(gap(list(q[:, k])), dtype=float).ravel()
            if not np.all(np.isfinite(residual)) or np.abs(residual).max() < 1e-12:
                break
            matrix = np.array(gradient(list(q[:, k])), dtype=float).reshape(len(residual), -1)
            q[:, k] -= np.linalg.lstsq(matrix, residual, rcond=None)[0]
    return q


def _draw(ax, positions, links, k, a, b, color, alpha, dashed=False) -> None:
    for first, second in links:
        p, r = positions.point(first)[:, k], positions.point(second)[:, k]
        ax.plot(
            [p[a], r[a]],
            [p[b], r[b]],
            "--" if dashed else "-",
            color=color,
            lw=1.0 if dashed else 1.8,
            alpha=alpha,
        )
    if any(ORIGIN in link for link in links):
        ax.plot([0], [0], "o", ms=5, mfc="white", mec="black", zorder=5)
    ax.plot(
        positions.particles[:, a, k],
        positions.particles[:, b, k],
        "o",
        ls="none",
        color=color,
        alpha=alpha,
        ms=4 if dashed else 8,
        zorder=4,
    )

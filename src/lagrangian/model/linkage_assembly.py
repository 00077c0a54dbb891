"""Assembling a linkage: the initial state moved onto its loops, the independent
coordinates held.

Of the linkage's coordinates (in the order of the model's ``coordinates``), the first
``degrees of freedom - drives`` are *held*: their given values (and velocities) are kept.
The others start from their given values, a guess that picks the branch of the assembly
(a four-bar's coupler above or below the line of its pivots), and are solved by Newton's
method onto the loop-closure and drive constraints G(q, t) = 0; their velocities then solve
G_q q' + G_t = 0.  Where Newton's method does not converge (the loop cannot close at the
held values: a crank past the limit a Grashof linkage allows, lengths that cannot meet) or
its Jacobian is singular (dependent closures: a redundant joint, or a position where the
held coordinates do not determine the others), the start is refused in one line naming the
held values and the joint.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np
import sympy

from ..errors import ModelError

if TYPE_CHECKING:
    from .system import System

#: Newton steps at most, and the residual (relative to 1 + the largest length) that ends them.
MAX_STEPS = 60
TOLERANCE = 1e-13


def assembled(
    system: System, t: float, q: np.ndarray, v: np.ndarray, params: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) of one state (in the system's coordinate order) on the linkage's constraints;
    ``params`` in the order of ``system.parameters``."""
    linkage = system.linkage
    functions = _functions(system)
    index = {c.q: k for k, c in enumerate(system.coordinates)}
    held = [index[s] for s in linkage.held]
    free = [index[s] for s in linkage.coordinates if s not in linkage.held]
    q, v = np.array(q, dtype=float), np.array(v, dtype=float)
    if not free:
        return q, v
    scale = 1.0 + max((abs(x) for x in _lengths(system, params)), default=0.0)
    step_limit = 0.5  # radians (or lengths): a step of Newton's method from far is damped
    for _ in range(MAX_STEPS):
        residual = np.asarray(functions.residual(t, q, params), dtype=float).ravel()
        if not np.all(np.isfinite(residual)):
            break
        if np.max(np.abs(residual), initial=0.0) <= TOLERANCE * scale:
            break
        jacobian = np.asarray(functions.jacobian(t, q, params), dtype=float)[:, free]
        try:
            step = np.linalg.solve(jacobian, -residual)
        except np.linalg.LinAlgError:
            raise _singular(system, q, held) from None
        largest = np.max(np.abs(step))
        if largest > step_limit:
            step *= step_limit / largest
        q[free] += step
    residual = np.asarray(functions.residual(t, q, params), dtype=float).ravel()
    if not (np.all(np.isfinite(residual)) and np.max(np.abs(residual)) <= 1e3 * TOLERANCE * scale):
        raise _cannot_close(system, q, held, residual)
    jacobian = np.asarray(functions.jacobian(t, q, params), dtype=float)
    rate = np.asarray(functions.rate(t, q, params), dtype=float).ravel()
    if np.linalg.matrix_rank(jacobian[:, free]) < len(free):
        raise _singular(system, q, held)
    v[free] = np.linalg.solve(jacobian[:, free], -(jacobian[:, held] @ v[held] + rate))
    return q, v


def assembled_state(
    system: System, state: Mapping[str, float], values: Mapping[str, float], t: float = 0.0
) -> dict[str, float]:
    """``state`` ({q: value, q_dot: value} of every coordinate) assembled as
    :func:`assembled` does, at the parameter ``values`` (by name); unchanged without a
    linkage."""
    if system.linkage is None:
        return dict(state)
    q = np.array([state[c.name] for c in system.coordinates], dtype=float)
    v = np.array([state[c.q_dot.name] for c in system.coordinates], dtype=float)
    params = np.array([values[p.name] for p in system.parameters], dtype=float)
    q, v = assembled(system, t, q, v, params)
    moved = dict(state)
    for k, c in enumerate(system.coordinates):
        moved[c.name], moved[c.q_dot.name] = float(q[k]), float(v[k])
    return moved


class _Functions:
    def __init__(self, residual, jacobian, rate):
        self.residual, self.jacobian, self.rate = residual, jacobian, rate


@lru_cache(maxsize=16)
def _functions(system: System) -> _Functions:
    """G, G_q and G_t of the linkage's constraints, as NumPy functions of (t, q, params)."""
    linkage = system.linkage
    q = [c.q for c in system.coordinates]
    p = [parameter.symbol for parameter in system.parameters]
    g = sympy.Matrix(linkage.constraints)
    arguments = [system.time, q, p]
    return _Functions(
        sympy.lambdify(arguments, g, "numpy"),
        sympy.lambdify(arguments, g.jacobian(q), "numpy"),
        sympy.lambdify(arguments, g.diff(system.time), "numpy"),
    )


def _lengths(system: System, params: np.ndarray) -> list[float]:
    values = {
        parameter.symbol: value for parameter, value in zip(system.parameters, params, strict=True)
    }
    lengths = []
    for link in system.linkage.links:
        try:
            lengths.append(float(link.length.xreplace(values)))
        except TypeError:  # a length that is not a number at these values
            continue
    return lengths


def _held_text(system: System, q: np.ndarray, held: list[int]) -> str:
    names = system.coordinate_names
    return ", ".join(f"{names[k]} = {q[k]:.6g}" for k in held) or "t = 0"


def _cannot_close(system: System, q, held, residual) -> ModelError:
    linkage = system.linkage
    worst, gap = None, -1.0
    for joint in linkage.joints:
        rows = [*joint.constraints]
        if joint.drive_constraint is not None:
            rows.append(joint.drive_constraint)
        if rows:
            size = (
                float(np.linalg.norm(residual[rows]))
                if np.all(np.isfinite(residual[rows]))
                else np.inf
            )
            if size > gap:
                worst, gap = joint, size
    return ModelError(
        f"the linkage cannot close at {_held_text(system, q, held)}: joint '{worst.name}' "
        f"stays {gap:.3g} apart (Newton's method found no assembly near the given angles; "
        "check the link lengths (Grashof's condition) and the held values)",
        field="joints",
    )


def _singular(system: System, q, held) -> ModelError:
    closing = [
        j.name for j in system.linkage.joints if j.constraints or j.drive_constraint is not None
    ]
    return ModelError(
        f"the linkage cannot be assembled at {_held_text(system, q, held)}: the constraints "
        f"of joints {', '.join(closing)} are dependent there (a redundant joint, or a "
        "position where the held coordinates do not fix the others; give other values or "
        "list another coordinate first)",
        field="joints",
    )

"""The impact law and the rule for contacts closing at once; the dynamics of held contacts.

Newton's law of restitution in the mass metric: a contact k closing (g_k = 0,
g_k' = G_k q' + g_t < 0) changes the velocities by an impulse along M^-1 G_k^T,

    q'+ = q'- - (1 + e) (G_k q'- + g_t) / (G_k M^-1 G_k^T)  M^-1 G_k^T,

the only change of q' that acts along the contact's normal in the kinetic metric: it makes
g_k'+ = -e g_k'-, keeps every momentum component orthogonal to the contact (p . u for u
with G_k u = 0), and takes the kinetic energy (1 - e^2) (g_k'-)^2 / (2 G_k M^-1 G_k^T)
(for g_t = 0; Brogliato, *Nonsmooth Mechanics*, 3rd ed. 2016, ch. 4).

Contacts closed at one instant (Newton's cradle: the balls touching) are resolved
**sequentially, pairwise, in order of approach velocity**: among the closed contacts
(|g| within :data:`TOUCH`) that approach (g' < 0), the law is applied to the one that
approaches fastest, and again until none approaches.  Each step conserves momentum and,
with e = 1, energy; for the cradle it gives the textbook answer (the last ball leaves with
the first one's velocity).  At most :data:`MAX_RESOLUTIONS` steps (an endless exchange is
an error).

A held contact (persistent contact, g = 0 kept as a constraint) adds a force G^T lambda:
q'' = a + M^-1 G^T lambda with lambda from G q'' + kappa = -2 alpha g' - alpha^2 g
(Baumgarte's terms keep the drift of a long contact down; :data:`HOLD_RATE`).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np

from ..errors import ModelError

#: |g| below this (relative to 1 + |q|) is a closed contact.
TOUCH = 1e-9
#: Steps of the sequential rule at one instant at most.
MAX_RESOLUTIONS = 10_000
#: Baumgarte's rate (1 / time) of a held contact's drift: a drift decays like exp(-rate t).
HOLD_RATE = 10.0


def restitute(mass: np.ndarray, gradient: np.ndarray, rate: float, v: np.ndarray, e: float):
    """q'+ of Newton's law for one contact: ``gradient`` G_k (n,), ``rate`` g_t."""
    response = np.linalg.solve(mass, gradient)
    approach = float(gradient @ v) + rate
    metric = float(gradient @ response)
    if not metric > 0.0:  # a gradient of 0 at the contact: the normal is undefined
        raise ModelError(
            "a contact closed where its gap has no gradient (dg/dq = 0): its normal is "
            "undefined; write the gap so that it changes sign through the contact"
        )
    return v - (1.0 + e) * approach / metric * response


def touching(gaps: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Which contacts are closed at the gaps ``gaps`` (a boolean array)."""
    return np.abs(gaps) <= TOUCH * (1.0 + float(np.max(np.abs(q), initial=0.0)))


def resolve(
    mass: np.ndarray,
    gradient: np.ndarray,
    rate: np.ndarray,
    v: np.ndarray,
    restitution: np.ndarray,
    closed: np.ndarray,
    on_impact: Callable[[int, np.ndarray, np.ndarray], None],
) -> np.ndarray:
    """The velocities after every closed contact has stopped approaching (the sequential
    rule of the module docstring); ``restitution`` e per contact (a held contact: 0);
    ``on_impact(k, before, after)`` is told of each step."""
    scale = np.sqrt(
        np.maximum(np.einsum("kn,kn->k", gradient, np.linalg.solve(mass, gradient.T).T), 0)
    )
    for _ in range(MAX_RESOLUTIONS):
        approach = (gradient @ v + rate) / np.where(scale > 0, scale, 1.0)
        candidates = np.flatnonzero(closed & (approach < -1e-14 * (1 + np.max(np.abs(v)))))
        if not candidates.size:
            return v
        k = int(candidates[np.argmin(approach[candidates])])
        after = restitute(mass, gradient[k], float(rate[k]), v, float(restitution[k]))
        on_impact(k, v, after)
        v = after
    raise ModelError(
        f"the contacts closed at one instant did not settle in {MAX_RESOLUTIONS} impacts"
    )


def held_multipliers(mass, forcing, gradient, rate, curvature, gaps, v):
    """(q'' with the held contacts' forces, their multipliers lambda) for the rows given."""
    free = np.linalg.solve(mass, forcing)
    if not gradient.shape[0]:
        return free, np.empty(0)
    response = np.linalg.solve(mass, gradient.T)  # n x k
    speed = gradient @ v + rate
    target = -2.0 * HOLD_RATE * speed - HOLD_RATE**2 * gaps
    multipliers = np.linalg.solve(gradient @ response, target - gradient @ free - curvature)
    return free + response @ multipliers, multipliers


def plastic(mass: np.ndarray, gradient: np.ndarray, rate: np.ndarray, v: np.ndarray):
    """(q'+, the impulses) of a plastic impact of the contacts given at once: q' projected
    in the mass metric onto G q' + g_t = 0 (the rows given), by the impulses G^T P."""
    response = np.linalg.solve(mass, gradient.T)  # n x k
    impulses = np.linalg.solve(gradient @ response, -(gradient @ v + rate))
    return v + response @ impulses, impulses


def contact_set(resting, gradient, curvature, accelerations, *, enumerated: int) -> np.ndarray:
    """The held ones among the closed contacts at rest ``resting`` (their indices): the set
    S whose multipliers are all >= 0 while every other one separates (g'' = G q'' + kappa
    >= 0), the complementarity conditions of unilateral contact, found by trying the sets,
    largest first (the solution is unique where the contacts' gradients are independent).
    ``accelerations(rows)`` gives (q'', lambda) with the contacts ``rows`` held.  Above
    ``enumerated`` contacts (2^k sets), or where no set fits: :func:`greedy_set`."""
    tol = 1e-9
    if resting.size > enumerated:
        return greedy_set(resting, accelerations)
    for size in range(resting.size, -1, -1):
        for rows in itertools.combinations(resting.tolist(), size):
            rows = np.array(rows, dtype=int)
            try:
                acceleration, multipliers = accelerations(rows)
            except np.linalg.LinAlgError:  # dependent contacts: another set
                continue
            if rows.size and multipliers.min() < -tol * (1 + np.abs(multipliers).max()):
                continue
            others = np.setdiff1d(resting, rows)
            approach = gradient[others] @ acceleration + curvature[others]
            if np.all(approach >= -tol * (1 + np.abs(acceleration).max())):
                return rows
    return greedy_set(resting, accelerations)


def greedy_set(resting, accelerations) -> np.ndarray:
    """All of ``resting`` held, then the one whose multiplier pulls most released, until
    none pulls: not the complementarity solution in every case, but bounded work (a pile of
    many contacts)."""
    rows = np.array(resting, dtype=int)
    while rows.size:
        try:
            _, multipliers = accelerations(rows)
        except np.linalg.LinAlgError:  # dependent contacts: one of them is enough
            rows = rows[1:]
            continue
        if multipliers.min() >= 0:
            break
        rows = np.delete(rows, int(np.argmin(multipliers)))
    return rows

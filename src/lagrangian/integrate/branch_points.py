"""Bifurcations along a branch of periodic orbits: detected between consecutive points by
test functions, located by the Illinois method along the arclength.

Test functions of a point of a branch (M the monodromy of the K-fold map, t the unit
tangent; Kuznetsov, Elements of Applied Bifurcation Theory, 3rd ed. 2004, 10.2):

- period doubling, a real multiplier through -1: det(M + I) changes sign;
- fold, the branch turns back in A (a multiplier through +1): dA/ds = t_A changes sign;
- branch point, a multiplier through +1 where the branch goes on (another branch crosses
  it: a pitchfork or transcritical point, by a symmetry of the system): det(M - I)
  changes sign and t_A does not;
- Neimark-Sacker, a complex pair through the unit circle: |mu|^2 - 1 of the pair changes
  sign.  Not looked for where det M = 1 (a Hamiltonian map, volume-preserving: its
  complex pairs stay on the circle, and leave it only by colliding, as pairs mu, 1/mu).

Where a test function's signs differ at two consecutive points, its zero is found on
the branch between them (each value of the function a corrected point at arclength s
from the first, along its tangent) by the Illinois variant of regula falsi, until the
bracket in s is :data:`LOCATED` wide or :data:`SEARCHES` points have been corrected.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import floquet
from .arclength import Follower, State

#: The bracket of a located bifurcation in arclength (so in A: |dA/ds| <= 1).
LOCATED = 1e-10
#: The most corrected points per location.
SEARCHES = 60
#: |det M - 1| below this at both points: a volume-preserving map (no Neimark-Sacker).
CONSERVATIVE = 1e-6

PERIOD_DOUBLING, FOLD, BRANCH_POINT, NEIMARK_SACKER = (
    "period doubling", "fold", "branch point", "Neimark-Sacker",
)  # fmt: skip


@dataclass(frozen=True)
class Bifurcation:
    """A bifurcation on a branch: its ``kind`` (period doubling, fold, branch point,
    Neimark-Sacker), the parameter's ``value``, the orbit's ``points`` (2n, K; angles in
    [-π, π)) and its ``multipliers`` there; ``state``: the corrected point."""

    kind: str
    value: float
    points: np.ndarray
    multipliers: np.ndarray
    state: State = field(repr=False, compare=False)


def doubling(state: State) -> float:
    size = state.value.monodromy.shape[0]
    return float(np.linalg.det(state.value.monodromy + np.eye(size)))


def turning(state: State) -> float:
    return float(state.tangent[-1])


def crossing(state: State) -> float:
    size = state.value.monodromy.shape[0]
    return float(np.linalg.det(state.value.monodromy - np.eye(size)))


def torus(state: State) -> float | None:
    """|mu|^2 - 1 of the complex multiplier nearest the unit circle, None if none."""
    values = floquet.multipliers(state.value.monodromy)
    pairs = values[np.abs(values.imag) > floquet.REAL * np.maximum(1.0, np.abs(values))]
    if pairs.size == 0:
        return None
    nearest = pairs[np.argmin(np.abs(np.abs(pairs) - 1.0))]
    return float(abs(nearest) ** 2 - 1.0)


def bifurcations_between(
    follower: Follower, first: State, second: State, period: int
) -> list[Bifurcation]:
    """The bifurcations between two consecutive points of a branch, located, in the
    order of the branch."""
    kinds = []
    if _changes(doubling, first, second):
        kinds.append((PERIOD_DOUBLING, doubling))
    if _changes(turning, first, second):
        kinds.append((FOLD, turning))
    elif _changes(crossing, first, second):
        kinds.append((BRANCH_POINT, crossing))
    volume = [abs(np.linalg.det(s.value.monodromy) - 1.0) for s in (first, second)]
    if max(volume) > CONSERVATIVE and _changes(torus, first, second):
        kinds.append((NEIMARK_SACKER, torus))
    found = []
    for kind, function in kinds:
        state = locate(follower, first, second, period, function)
        found.append(
            Bifurcation(
                kind=kind,
                value=state.a,
                points=follower.map.wrapped(state.value.points[:, :period]),
                multipliers=floquet.multipliers(state.value.monodromy),
                state=state,
            )
        )
    found.sort(key=lambda b: float(first.tangent @ (b.state.u - first.u)))
    return found


def _changes(function, first: State, second: State) -> bool:
    a, b = function(first), function(second)
    return a is not None and b is not None and (a < 0) != (b < 0)


def locate(follower: Follower, first: State, second: State, period: int, function) -> State:
    """The point between ``first`` and ``second`` where ``function`` is 0 (Illinois)."""
    low, high = 0.0, float(first.tangent @ (second.u - first.u))
    f_low, f_high = function(first), function(second)
    best = first if abs(f_low) < abs(f_high) else second
    side = 0
    for _ in range(SEARCHES):
        if abs(high - low) <= LOCATED or f_low == 0.0 or f_high == 0.0:
            break
        s = high - f_high * (high - low) / (f_high - f_low)
        if not min(low, high) < s < max(low, high):
            s = (low + high) / 2
        state, _ = follower.at_arclength(first, s, period)
        value = None if state is None else function(state)
        if value is None:  # no point there (or no complex pair): halve the bracket instead
            s = (low + high) / 2
            state, _ = follower.at_arclength(first, s, period)
            value = None if state is None else function(state)
            if value is None:
                break
        if state.tangent @ first.tangent < 0:
            state.tangent = -state.tangent
            value = function(state)
        best = state if abs(value) <= abs(function(best)) else best
        if (value < 0) == (f_high < 0):
            high, f_high = s, value
            if side == -1:
                f_low /= 2
            side = -1
        else:
            low, f_low = s, value
            if side == 1:
                f_high /= 2
            side = 1
    return best

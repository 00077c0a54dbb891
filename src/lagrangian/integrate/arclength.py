"""The predictor-corrector of pseudo-arclength continuation (:mod:`.continuation`).

From a point u = (x, A) of a branch, F(u) = G_A^K(x) - x = 0, with unit tangent t (the
null vector of the Jacobian [M - I, dG^K/dA], oriented as the one before), the predictor
u + h t is corrected by Newton's method on F(u') = 0, t . (u' - u) = h; see the module
docstring of :mod:`.continuation` for the step-size control.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from .parameter_map import MapValue, ParameterMap

if TYPE_CHECKING:
    from .branch_points import Bifurcation

#: Newton's corrector converged: |F| <= this times (1 + |x|).
TOLERANCE = 1e-9
#: Corrector iterations before the step is halved; converged within QUICK: the step grows.
CORRECTIONS, QUICK = 8, 3
#: The step's factors after a failure and after a quick convergence.
SHRINK, GROW = 0.5, 1.5
#: The smallest step, relative to the largest: below it the branch ends.
SMALLEST = 1e-5
#: The last points of a branch not compared with a new one (its own neighbours).
RECENT = 4


@dataclass
class State:
    """A corrected point: u = (x, A), the map's value there and the unit tangent."""

    u: np.ndarray
    value: MapValue
    tangent: np.ndarray

    @property
    def x(self) -> np.ndarray:
        return self.u[:-1]

    @property
    def a(self) -> float:
        return float(self.u[-1])


class Follower:
    """The predictor-corrector over one :class:`ParameterMap`, the range [low, high] and
    the largest step ``largest``."""

    def __init__(self, strobe_map: ParameterMap, low: float, high: float, largest: float):
        self.map, self.low, self.high, self.largest = strobe_map, low, high, largest

    def residual(self, x: np.ndarray, value: MapValue, period: int) -> np.ndarray:
        return self.map.difference(value.points[:, period], x)

    def jacobian(self, value: MapValue) -> np.ndarray:
        """[M - I, dG^K/dA] (2n, 2n + 1)."""
        size = value.monodromy.shape[0]
        return np.column_stack([value.monodromy - np.eye(size), value.column])

    def tangent(self, value: MapValue, previous: np.ndarray) -> np.ndarray:
        """The unit null vector of the Jacobian, on the side of ``previous``."""
        matrix = np.vstack([self.jacobian(value), previous])
        right = np.zeros(matrix.shape[0])
        right[-1] = 1.0
        tangent = np.linalg.solve(matrix, right)
        return tangent / np.linalg.norm(tangent)

    def correct(
        self, guess: np.ndarray, row: np.ndarray, target: float, period: int, reach: float
    ) -> tuple[State | None, int]:
        """Newton's method on F(u) = 0, row . u = target from ``guess``: (the point and its
        tangent, oriented as ``row``, or None; the iterations taken).  A correction that
        moves u farther than ``reach`` from the guess fails (a jump to another branch)."""
        u = np.array(guess, dtype=float)
        for iteration in range(1, CORRECTIONS + 1):
            try:
                value = self.map(u[:-1], u[-1], period)
            except ModelError:  # the motion failed (left every bound): no point here
                return None, iteration
            residual = self.residual(u[:-1], value, period)
            if not np.all(np.isfinite(value.monodromy)) or not np.all(np.isfinite(residual)):
                return None, iteration
            scale = 1.0 + float(np.max(np.abs(u[:-1])))
            if float(np.max(np.abs(residual))) <= TOLERANCE * scale and abs(
                float(row @ u) - target
            ) <= TOLERANCE * max(1.0, abs(target)):
                try:
                    return State(u, value, self.tangent(value, row)), iteration
                except np.linalg.LinAlgError:
                    return None, iteration
            matrix = np.vstack([self.jacobian(value), row])
            try:
                step = np.linalg.solve(matrix, -np.append(residual, float(row @ u) - target))
            except np.linalg.LinAlgError:
                return None, iteration
            u = u + step
            if np.linalg.norm(u - guess) > reach:
                return None, iteration
        return None, CORRECTIONS

    def at_arclength(self, state: State, h: float, period: int) -> tuple[State | None, int]:
        """The point at arclength ``h`` along the tangent from ``state``."""
        return self.correct(
            state.u + h * state.tangent, state.tangent, float(state.tangent @ state.u) + h,
            period, max(abs(h), self.largest * SMALLEST),
        )  # fmt: skip

    def at_value(self, state: State, value: float, period: int) -> State | None:
        """The point of the branch at A = ``value`` near ``state`` (its tangent oriented as
        the state's)."""
        row = np.zeros_like(state.u)
        row[-1] = 1.0
        guess = state.u.copy()
        if abs(state.tangent[-1]) > 0:  # the tangent's prediction of the state at ``value``
            guess = state.u + (value - state.a) / state.tangent[-1] * state.tangent
        found, _ = self.correct(guess, row, value, period, 2 * self.largest + abs(value - state.a))
        if found is not None and found.tangent @ state.tangent < 0:
            found.tangent = -found.tangent
        return found


def follow(
    follower: Follower,
    start: State,
    period: int,
    *,
    first_step: float,
    test_from_start: bool,
    locate: Callable[[State, State, int], list[Bifurcation]],
    max_points: int,
) -> tuple[list[State], list[Bifurcation], str]:
    """The states of the branch through ``start`` in the direction of its tangent, the
    bifurcations ``locate`` finds between consecutive ones, and why it ended."""
    states, found = [start], []
    trace = Trace(follower.map, period)
    trace.add(start)
    h = min(first_step, follower.largest)
    smallest = follower.largest * SMALLEST
    while True:
        if len(states) >= max_points:
            return states, found, "points"
        state = states[-1]
        new, iterations = follower.at_arclength(state, h, period)
        if new is None:
            h *= SHRINK
            if h < smallest:
                return states, found, "step"
            continue
        ended = None
        if not follower.low <= new.a <= follower.high:
            edge = follower.high if new.a > follower.high else follower.low
            new = follower.at_value(state, edge, period) if state.a != edge else None
            if new is None:
                return states, found, "range"
            ended = "range"
        if ended is None and trace.returns(new, h):
            return states, found, "closed"
        if test_from_start or len(states) > 1:
            found.extend(locate(state, new, period))
        states.append(new)
        trace.add(new)
        if ended is not None:
            return states, found, ended
        if iterations <= QUICK:
            h = min(h * GROW, follower.largest)


class Trace:
    """The orbits a branch has passed through, each as every shift of its points (x_j, A),
    j = 0 .. K - 1 (the same orbit started at another of its points).  A new point within
    one step of one of them, other than its last few neighbours, means the branch has come
    round a closed curve, or is going back over orbits it has passed (the second half of a
    period-doubling bubble: the doubled branch that leaves one doubling of its parent and
    joins it again at another comes back along the same orbits, their points shifted by
    half the period): it ends there rather than going round again."""

    def __init__(self, strobe_map: ParameterMap, period: int):
        self.map, self.period = strobe_map, period
        self.rows: list[np.ndarray] = []  # (K, 2n + 1) per point

    def add(self, state: State) -> None:
        points = state.value.points[:, : self.period].T
        self.rows.append(np.column_stack([points, np.full(self.period, state.a)]))

    def returns(self, state: State, reach: float, recent: int = RECENT) -> bool:
        """Whether ``state`` lies within ``reach`` of one of the orbits passed before the
        last ``recent``."""
        if len(self.rows) <= recent:
            return False
        earlier = np.concatenate(self.rows[: len(self.rows) - recent]) - state.u
        angles = self.map.angles
        earlier[:, angles] = (earlier[:, angles] + np.pi) % (2 * np.pi) - np.pi
        return bool(np.min(np.linalg.norm(earlier, axis=1)) < reach)

"""Periodic orbits followed in a parameter: pseudo-arclength continuation of the strobe map.

A periodic point of period K of the strobe map G_A (:mod:`.orbits`) solves
F(x, A) = G_A^K(x) - x = 0 (angles modulo 2π): 2n equations in the 2n + 1 unknowns
u = (x, A), whose solutions form curves, the branches.  A branch is followed by
pseudo-arclength continuation (Keller 1977; Kuznetsov, Elements of Applied Bifurcation
Theory, 3rd ed. 2004, ch. 10): from a point u with unit tangent t (the null vector of
the Jacobian [M - I, dG^K/dA], M the monodromy matrix, oriented as the last one), the
predictor u + h t is corrected by Newton's method on

    F(u') = 0,   t . (u' - u) = h,

whose Jacobian [[M - I, dG^K/dA], [t]] stays regular through a fold, where a natural
continuation in A fails.  M and dG^K/dA come from one run of the sensitivity equations
(:mod:`.parameter_map`).  The step h (:mod:`.arclength`) shrinks by half when the
corrector fails (no convergence in 8 iterations, or a point farther than h from the
prediction: a jump to another branch) and grows by half when it converges within 3, up
to the span of A over the number of values asked for less one; the branch ends at the
ends of the range (its last point exactly there), where it comes back to orbits it has
passed (a closed curve, or the second half of a period-doubling bubble: :class:`.arclength.
Trace`), after :data:`POINTS_PER_VALUE` points per value asked for, or where h falls
below 1e-5 of its largest.  The bifurcations
between consecutive points are found and located by :mod:`.branch_points`; at a period
doubling the doubled branch is followed from there (to ``max_doublings`` doublings).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Unpack

import numpy as np

from ..errors import ModelError
from . import floquet
from .arclength import Follower, State, Trace, follow
from .base import positive_setting
from .branch_points import PERIOD_DOUBLING, Bifurcation, bifurcations_between
from .orbits import DEFAULT_ATOL, DEFAULT_RTOL, SAME, SearchOptions
from .parameter_map import ParameterMap

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem
    from .orbits import OrbitSearch
    from .strobe import Strobe

#: The most points of one branch, per value of A asked for.
POINTS_PER_VALUE = 20
#: The most values of A asked for; the most period doublings followed, and unless told.
MAX_VALUES, MAX_DOUBLINGS, DEFAULT_DOUBLINGS = 100_000, 8, 3


@dataclass(frozen=True)
class BranchPoint:
    """One point of a branch: the parameter's ``value`` A, the orbit's ``points`` (2n, K)
    (angles in [-π, π)), its ``multipliers`` (of the K-fold map) and whether it is stable."""

    value: float
    points: np.ndarray
    multipliers: np.ndarray

    @property
    def stable(self) -> bool:
        return floquet.is_stable(self.multipliers)

    @property
    def kind(self) -> str:
        return floquet.kind(self.multipliers)


@dataclass(frozen=True)
class Branch:
    """A branch of orbits of least ``period`` K: its ``points`` in the order followed, the
    ``bifurcations`` on it, the branch it doubled from (``parent``, an index into the
    continuation's branches, None for one found at the start) and why it ``ended``."""

    period: int
    points: tuple[BranchPoint, ...]
    bifurcations: tuple[Bifurcation, ...]
    parent: int | None
    ended: str


@dataclass(frozen=True)
class Continuation:
    """The ``branches`` of periodic orbits of the strobe map followed in ``parameter``
    from ``low`` to ``high``, on the state ``names``; ``search``: the orbits found at
    ``low``, where the branches start."""

    parameter: str
    low: float
    high: float
    branches: tuple[Branch, ...]
    names: tuple[str, ...]
    strobe: Strobe
    settings: Mapping[str, object] = field(default_factory=dict)
    name: str = ""
    search: OrbitSearch | None = field(default=None, repr=False)


def continue_orbits(
    compiled: CompiledSystem,
    *,
    parameter: str,
    low: float,
    high: float,
    count: int,
    strobe: float,
    period: int = 1,
    max_doublings: int = DEFAULT_DOUBLINGS,
    **options: Unpack[SearchOptions],
) -> Continuation:
    """The branches of the periodic orbits of period dividing ``period`` found at
    ``parameter`` = ``low`` (:func:`~.orbits.periodic_orbits`, with its ``options``:
    ``phase``, ``starts``, ``attractor``, ``transient``, ``initial``, ``params``,
    ``rtol``, ``atol``, ``watch``) followed to ``high``, the largest step
    (high - low) / (count - 1); at each period doubling the doubled branch, to
    ``max_doublings`` doublings.  See the module docstring."""
    from .orbits import _angles, periodic_orbits

    initial, params, watch = options.get("initial"), options.get("params"), options.get("watch")

    if parameter not in compiled.parameter_names:
        known = ", ".join(compiled.parameter_names) or "none"
        raise ModelError(f"unknown parameter '{parameter}' (parameters: {known})")
    low, high, count = checked_range(low, high, count)
    max_doublings = checked_doublings(max_doublings)
    rtol, atol = tolerances(options.get("rtol"), options.get("atol"), DEFAULT_RTOL, DEFAULT_ATOL)
    at_low = {**(params or {}), parameter: low}
    progress = _Progress(watch, low, high)
    search = periodic_orbits(
        compiled, strobe=strobe, period=period,
        **{**options, "params": at_low, "rtol": rtol, "atol": atol,
           "watch": None if watch is None else (lambda done: progress.searching())},
    )  # fmt: skip
    p = compiled.parameter_vector(at_low)
    y0 = compiled.state_vector(initial)
    strobe_map = ParameterMap(
        compiled, search.strobe, parameter, p, _angles(compiled, y0[:, None], p), rtol, atol,
        progress.integrating,
    )  # fmt: skip
    follower = Follower(strobe_map, low, high, (high - low) / (count - 1))
    limit = POINTS_PER_VALUE * count
    branches: list[Branch] = []
    traces: list[Trace] = []  # the orbits each branch passed, to know a bubble's other end
    progress.map = strobe_map
    # to follow: (an orbit's first point at A = low, or a period doubling; the period;
    # the index of the branch doubled from, None for an orbit found at low)
    pending: list[tuple[object, int, int | None]] = [
        (orbit.points[:, 0], orbit.period, None) for orbit in search.orbits
    ]
    progress.pending = len(pending)
    ahead = np.zeros(2 * compiled.n + 1)
    ahead[-1] = 1.0
    while pending:
        origin, k, parent = pending.pop(0)
        if parent is None:
            x = np.asarray(origin, dtype=float)
            value = strobe_map(x, low, k)
            start = State(np.append(x, low), value, follower.tangent(value, ahead))
            first = []
        else:
            start, first = _doubled_start(follower, origin, k)
            if start is None or any(
                trace.period == k and trace.returns(start, follower.largest, recent=0)
                for trace in traces
            ):  # not found, or the other end of a bubble already followed from its first
                continue
        progress.following(start)
        states, found, ended = follow(
            follower, start, k, first_step=follower.largest / 4,
            test_from_start=parent is None,
            locate=lambda a, b, k=k: bifurcations_between(follower, a, b, k), max_points=limit,
        )  # fmt: skip
        trace = Trace(strobe_map, k)
        for state in states:
            trace.add(state)
        traces.append(trace)
        branches.append(
            Branch(
                period=k,
                points=(*first, *(_point(strobe_map, s, k) for s in states)),
                bifurcations=tuple(found),
                parent=parent,
                ended=ended,
            )
        )
        depth = _depth(branches, len(branches) - 1)
        if depth < max_doublings:
            doublings = [b for b in found if b.kind == PERIOD_DOUBLING]
            pending += [(b, 2 * k, len(branches) - 1) for b in doublings]
        progress.done(len(pending))
    return Continuation(
        parameter=parameter,
        low=low,
        high=high,
        branches=tuple(branches),
        names=search.names,
        strobe=search.strobe,
        settings={
            **search.settings,
            "parameter": parameter,
            "low": low,
            "high": high,
            "values": count,
            "max_doublings": max_doublings,
            "map_runs": strobe_map.runs,
        },
        name=search.name,
        search=search,
    )


def _point(strobe_map: ParameterMap, state: State, period: int) -> BranchPoint:
    return BranchPoint(
        value=state.a,
        points=strobe_map.wrapped(state.value.points[:, :period]),
        multipliers=floquet.multipliers(state.value.monodromy),
    )


def _depth(branches: list[Branch], index: int) -> int:
    """How many doublings lead to branch ``index``."""
    depth = 0
    while branches[index].parent is not None:
        index, depth = branches[index].parent, depth + 1
    return depth


def _doubled_start(
    follower: Follower, doubling: Bifurcation, period: int
) -> tuple[State | None, list[BranchPoint]]:
    """The first corrected point of the doubled branch (period 2K) at a period doubling of
    the K-branch, and the doubling itself as a point of it: the 2K-fold map's fixed points
    there cross the K-branch along v, the eigenvector of the multiplier -1 (a pitchfork of
    G^2K), so the corrector starts from x* + h v on the plane v . (x - x*) = h, h the
    largest step and smaller, until it reaches an orbit of least period 2K."""
    monodromy = doubling.state.value.monodromy
    values, vectors = np.linalg.eig(monodromy)
    vector = np.real(vectors[:, int(np.argmin(np.abs(values + 1.0)))])
    row = np.append(vector / np.linalg.norm(vector), 0.0)
    origin = doubling.state.u
    half = period // 2
    h = follower.largest
    for _ in range(6):
        state, _ = follower.correct(origin + h * row, row, float(row @ origin) + h, period, h)
        if state is not None:
            gap = follower.map.difference(state.value.points[:, half], state.x)
            if float(np.max(np.abs(gap))) > SAME * (1.0 + float(np.max(np.abs(state.x)))):
                twice = np.linalg.matrix_power(monodromy, 2)
                at_doubling = BranchPoint(
                    value=doubling.value,
                    points=np.tile(doubling.points, 2),
                    multipliers=floquet.multipliers(twice),
                )
                return state, [at_doubling]
        h /= 2
    return None, []


class _Progress:
    """The fraction done, told to ``watch``: the branches followed, and of the one being
    followed the part of [low, high] it has crossed."""

    def __init__(self, watch, low: float, high: float):
        self.watch, self.low, self.high = watch, low, high
        self.finished, self.pending, self.start = 0, 1, low
        self.map: ParameterMap | None = None  # its value of A: where the branch has got to

    def searching(self) -> None:
        if self.watch is not None:
            self.watch(0.0)

    def following(self, start: State) -> None:
        self.start = start.a

    def integrating(self, t: float) -> None:
        if self.watch is not None and self.map is not None:
            part = min(1.0, abs(self.map.value - self.start) / (self.high - self.low))
            self.watch((self.finished + part) / (self.finished + 1 + self.pending))

    def done(self, pending: int) -> None:
        self.finished += 1
        self.pending = pending


def checked_range(low: float, high: float, count: int) -> tuple[float, float, int]:
    """(low, high, count) checked: finite, low < high, a whole count from 2."""
    low, high = float(low), float(high)
    if not (np.isfinite(low) and np.isfinite(high)):
        raise ModelError(f"the range of the parameter must be finite, not {low:g} to {high:g}")
    if low >= high:
        raise ModelError(f"the range's low end ({low:g}) must be below its high end ({high:g})")
    if int(count) != count or not 2 <= count <= MAX_VALUES:
        raise ModelError(f"the number of values must be a whole number from 2 to {MAX_VALUES:,}")
    return low, high, int(count)


def checked_doublings(count: int) -> int:
    if int(count) != count or not 0 <= count <= MAX_DOUBLINGS:
        raise ModelError(f"max_doublings must be a whole number from 0 to {MAX_DOUBLINGS}")
    return int(count)


def tolerances(rtol, atol, default_rtol: float, default_atol: float) -> tuple[float, float]:
    rtol = default_rtol if rtol is None else positive_setting("rtol", rtol)
    atol = default_atol if atol is None else positive_setting("atol", atol)
    return rtol, atol

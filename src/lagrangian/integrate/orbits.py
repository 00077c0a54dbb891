"""Periodic orbits of a stroboscopic map, by Newton's method with the monodromy matrix.

A system driven with period P (y' = F(t, y) with F(t + P, y) = F(t, y), checked at a few
states) has the stroboscopic map G: y(phase) -> y(phase + P) (:mod:`.strobe`).  A
periodic point of period K solves G^K(x) = x.  Newton's method takes

    x <- x - (M - I)^(-1) (G^K(x) - x),    M = dG^K/dx = W_(K-1) ... W_1 W_0,

W_j the tangent map of one period from the j-th iterate: the variational equations
W' = J(t, y) W, W = I at the start of the period, integrated with the state by DOP853
(:class:`~.lyapunov.VariationalFlow`, the flow of the Lyapunov exponents: compiled where
numba is installed; J the compiled symbolic Jacobian, not finite differences).  A step
that does not lower |G^K(x) - x| is halved (at most :data:`HALVINGS` times).  On a
coordinate on which F is 2π-periodic (an angle: checked on the compiled equations) the
difference is taken modulo 2π, so an orbit that turns over in K periods is periodic on
the cylinder, and its points are given with the angle in [-π, π).

The starts are the strobe points of the motion from the model's initial state after a
transient (on its attractor) and any others given (a grid).  A start whose iteration
reaches |G^K(x) - x| <= :data:`TOLERANCE` (1 + |x|) within :data:`ITERATIONS` is an orbit;
the others are dropped.  Each orbit is given once, at its least period d (a divisor of
K), with its d points x, G(x), ..., and its Floquet multipliers, stability and kind
(:mod:`.floquet`) over the d periods.  Orbits found from several starts, or at another of
their points, are merged.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypedDict

import numpy as np

from ..errors import ModelError, setting
from . import floquet
from .base import positive_setting, transient_setting
from .guard import parameter_problem, start_problem
from .lyapunov import VariationalFlow
from .strobe import AngleWrapping, Strobe

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: |G^K(x) - x| (angles modulo 2π) at most this times (1 + |x|): converged.
TOLERANCE = 1e-9
#: Newton iterations from each start, and halvings of a step that did not help.
ITERATIONS, HALVINGS = 40, 10
#: Points closer than this (times 1 + |x|) are the same point: orbits merged, periods cut.
SAME = 1e-6
#: The largest orbit period asked for, and the most starts.
MAX_PERIOD, MAX_STARTS = 64, 100_000
#: DOP853's tolerances unless told: the multipliers are as accurate as the tangent maps.
DEFAULT_RTOL, DEFAULT_ATOL = 1e-11, 1e-12


@dataclass(frozen=True)
class PeriodicOrbit:
    """One periodic orbit of the strobe map: its least ``period`` d, its d ``points``
    (2n, d) x, G(x), ..., the ``monodromy`` dG^d/dx at the first, its ``multipliers``
    (complex, largest modulus first) and ``residual`` |G^d(x) - x|; of a section's map
    (:mod:`.shell_orbits`), d returns to the section in the ``time`` T, M = dphi_T/dx."""

    period: int
    points: np.ndarray
    monodromy: np.ndarray
    multipliers: np.ndarray
    residual: float
    time: float | None = None
    trivial: int = 0  # multipliers 1 by the flow's symmetry (2 on an energy shell)

    @property
    def stable(self) -> bool:
        return floquet.is_stable(self.multipliers, self.trivial)

    @property
    def kind(self) -> str:
        return floquet.kind(self.multipliers, self.trivial)


@dataclass(frozen=True)
class OrbitSearch:
    """The periodic orbits found (``orbits``, by period then by first point) of period
    dividing ``period`` at the ``strobe`` (None: of a section, named in ``settings``),
    from ``starts`` starts, on the state ``names``."""

    orbits: tuple[PeriodicOrbit, ...]
    names: tuple[str, ...]
    strobe: Strobe | None
    period: int
    starts: int
    settings: Mapping[str, object] = field(default_factory=dict)
    name: str = ""


class SearchOptions(TypedDict, total=False):
    """The keywords of :func:`periodic_orbits` besides the strobe and the period, which
    :func:`~.continuation.continue_orbits` passes on to it."""

    phase: float | None
    starts: np.ndarray | None
    attractor: int
    transient: float | None
    initial: Mapping[str, float] | None
    params: Mapping[str, float] | None
    rtol: float | None
    atol: float | None
    watch: Callable[[float], None] | None


def periodic_orbits(
    compiled: CompiledSystem,
    *,
    strobe: float,
    period: int,
    phase: float | None = None,
    starts: np.ndarray | None = None,
    attractor: int = 20,
    transient: float | None = None,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    watch: Callable[[float], None] | None = None,
) -> OrbitSearch:
    """The periodic orbits of period dividing ``period`` (K) of the map at t = ``phase`` +
    k ``strobe``: Newton's method from the ``attractor`` strobe points after ``transient``
    (default 50 periods) of the motion from ``initial``, and from ``starts`` (2n, N);
    see the module docstring.  ``watch`` is told the fraction done (0 to 1)."""
    if compiled.has_constraints:
        raise ModelError("periodic orbits of constrained systems are not supported")
    clock = Strobe.of(strobe, phase)
    if int(period) != period or not 1 <= period <= MAX_PERIOD:
        raise ModelError(
            f"the period must be a whole number from 1 to {MAX_PERIOD}, not {period!r}"
        )
    period = int(period)
    transient = 50 * clock.period if transient is None else transient_setting(transient)
    rtol = DEFAULT_RTOL if rtol is None else positive_setting("rtol", rtol)
    atol = DEFAULT_ATOL if atol is None else positive_setting("atol", atol)
    size = 2 * compiled.n
    given = np.empty((size, 0)) if starts is None else np.asarray(starts, dtype=float)
    given = given.reshape(size, -1)
    if not 0 <= int(attractor) <= MAX_STARTS or given.shape[1] + int(attractor) == 0:
        raise ModelError(f"give from 1 to {MAX_STARTS:,} starts, not {int(attractor)}")
    y0 = compiled.state_vector(initial)
    p = compiled.parameter_vector(params)
    problem = parameter_problem(compiled, 0.0, y0, p) or start_problem(compiled, 0.0, y0, p)
    if problem is not None:
        raise ModelError(problem)
    _check_periodic(compiled, clock, np.column_stack([y0, given]), p)
    angles = _angles(compiled, np.column_stack([y0, given]), p)
    total = int(attractor) + given.shape[1]
    done = [0.0]  # the fraction of the starts done, told at every step (a budget is checked)
    told = None if watch is None else (lambda t: watch(done[0]))
    flow = VariationalFlow(compiled, p, size, rtol, atol, told)
    strobe_map = _StrobeMap(flow, clock, angles, size)
    found: list[PeriodicOrbit] = []
    first = clock.first(transient)
    for k, x in enumerate(_attractor_starts(strobe_map, y0, first, int(attractor))):
        done[0] = k / total
        _merge(found, _newton(strobe_map, x, period), strobe_map)
    for k in range(given.shape[1]):
        done[0] = (int(attractor) + k) / total
        _merge(found, _newton(strobe_map, given[:, k], period), strobe_map)
    if watch is not None:
        watch(1.0)
    names = compiled.coordinate_names
    found.sort(key=lambda orbit: (orbit.period, *np.round(orbit.points[:, 0], 6)))
    return OrbitSearch(
        orbits=tuple(found),
        names=(*names, *(f"{q}_dot" for q in names)),
        strobe=clock,
        period=period,
        starts=total,
        settings={
            "strobe": clock.period,
            "phase": clock.phase,
            "transient": transient,
            "attractor_starts": int(attractor),
            "rtol": rtol,
            "atol": atol,
        },
        name=compiled.equations.system.name if compiled.derived else "",
    )


class _StrobeMap(AngleWrapping):
    """G and its tangent maps by the variational flow, from t = phase + k P."""

    def __init__(self, flow: VariationalFlow, clock: Strobe, angles: np.ndarray, size: int):
        self.flow, self.clock, self.angles, self.size = flow, clock, angles, size

    def advance(self, x: np.ndarray, k: int) -> np.ndarray:
        """G(x) from t_k (the state alone)."""
        return self.flow.state(self.clock.time(k), self.clock.time(k + 1), x)

    def iterates(self, x: np.ndarray, count: int) -> tuple[np.ndarray, list[np.ndarray]]:
        """((2n, count + 1) x, G(x), ..., G^count(x); the tangent maps of each period)."""
        points, tangents = [np.asarray(x, dtype=float)], []
        identity = np.eye(self.size)
        for j in range(count):
            y, w = self.flow.extended(
                self.clock.time(j), self.clock.time(j + 1), points[-1], identity
            )
            points.append(y)
            tangents.append(w)
        return np.column_stack(points), tangents


def _attractor_starts(strobe_map: _StrobeMap, y0: np.ndarray, first: int, count: int):
    """The ``count`` strobe points from t_first on of the motion from y0 at t = 0."""
    if count == 0:
        return
    x = strobe_map.flow.state(0.0, float(strobe_map.clock.time(first)), y0)
    for k in range(count):
        yield x
        if k + 1 < count:
            x = strobe_map.advance(x, first + k)


def _newton(strobe_map: _StrobeMap, x: np.ndarray, period: int) -> PeriodicOrbit | None:
    """The orbit Newton's method reaches from x, or None (no convergence, a failed run)."""
    try:
        x = strobe_map.wrapped(x)
        points, tangents = strobe_map.iterates(x, period)
        residual = strobe_map.difference(points[:, -1], x)
        for _ in range(ITERATIONS):
            if _small(residual, x, TOLERANCE):
                return _orbit(strobe_map, x, points, tangents)
            monodromy = _product(tangents)
            step = -np.linalg.lstsq(monodromy - np.eye(len(x)), residual, rcond=None)[0]
            for _ in range(HALVINGS):
                trial = strobe_map.wrapped(x + step)
                trial_points, trial_tangents = strobe_map.iterates(trial, period)
                trial_residual = strobe_map.difference(trial_points[:, -1], trial)
                if np.linalg.norm(trial_residual) < np.linalg.norm(residual):
                    break
                step = step / 2
            else:
                return None
            x, points, tangents, residual = trial, trial_points, trial_tangents, trial_residual
        return _orbit(strobe_map, x, points, tangents) if _small(residual, x, TOLERANCE) else None
    except (ModelError, np.linalg.LinAlgError):  # a motion failed, or M - I was not finite
        return None


def _small(difference: np.ndarray, x: np.ndarray, tolerance: float) -> bool:
    return bool(np.all(np.isfinite(difference))) and (
        float(np.max(np.abs(difference))) <= tolerance * (1.0 + float(np.max(np.abs(x))))
    )


def _product(tangents: list[np.ndarray]) -> np.ndarray:
    """W_(d-1) ... W_1 W_0."""
    product = np.eye(tangents[0].shape[0])
    for w in tangents:
        product = w @ product
    return product


def _orbit(strobe_map, x, points, tangents) -> PeriodicOrbit:
    """The orbit through x at its least period d (the first d dividing K with G^d(x) = x)."""
    period = len(tangents)
    least = next(
        d for d in range(1, period + 1)
        if period % d == 0 and _small(strobe_map.difference(points[:, d], x), x, SAME)
    )  # fmt: skip
    monodromy = _product(tangents[:least])
    residual = strobe_map.difference(points[:, least], x)
    return PeriodicOrbit(
        period=least,
        points=np.column_stack([strobe_map.wrapped(points[:, j]) for j in range(least)]),
        monodromy=monodromy,
        multipliers=floquet.multipliers(monodromy),
        residual=float(np.max(np.abs(residual))),
    )


def _merge(found: list[PeriodicOrbit], orbit: PeriodicOrbit | None, strobe_map) -> None:
    """Add ``orbit`` unless one of ``found`` has its period and passes through its first
    point (the same orbit, found from another start or at another of its points)."""
    if orbit is None:
        return
    start = orbit.points[:, 0]
    for other in found:
        if other.period == orbit.period and any(
            _small(strobe_map.difference(point, start), start, SAME) for point in other.points.T
        ):
            return
    found.append(orbit)


def _check_periodic(compiled, clock: Strobe, states: np.ndarray, p: np.ndarray) -> None:
    """ModelError unless F(t + P, y) = F(t, y) at a few times and the given states: the
    strobe map is then the same every period (Newton's method needs one map)."""
    times = clock.phase + clock.period * np.array([0.0, 0.37, 0.71])
    for t in times:
        now = np.asarray(compiled.rhs(t, states, p), dtype=float)
        later = np.asarray(compiled.rhs(t + clock.period, states, p), dtype=float)
        scale = 1.0 + np.abs(now)
        if not np.all(np.abs(later - now) <= 1e-9 * scale):
            raise ModelError(
                f"the equations are not periodic in t with the strobe period {clock.period:g} "
                f"(they differ at t = {t:g} and t + {clock.period:g}): periodic orbits of a "
                f"strobe need the drive's period (or a multiple) as {setting('strobe')}"
            )


def _angles(compiled, states: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The indices of the coordinates on which F is 2π-periodic, at the given states and
    a few times."""
    n = compiled.n
    angles = []
    for c in range(n):
        shifted = np.array(states, dtype=float)
        shifted[c] += 2 * math.pi
        same = True
        for t in (0.0, 0.3, 1.1):
            a = np.asarray(compiled.rhs(t, states, p), dtype=float)
            b = np.asarray(compiled.rhs(t, shifted, p), dtype=float)
            if not np.all(np.abs(a - b) <= 1e-9 * (1.0 + np.abs(a))):
                same = False
                break
        if same:
            angles.append(c)
    return np.array(angles, dtype=int)

"""Crossings of a surface of section along motions sampled at every step of a fixed grid.

An ensemble keeps the states of its members at the step times t_0 < t_1 < ... (the
fixed-step method's grid); between two of them the motion is the cubic Hermite
interpolant of the states y_k, y_k+1 and slopes F(t_k, y_k), F(t_k+1, y_k+1)
(error O(h^4), the order of rk4 itself).  A crossing of g = 0
(:mod:`lagrangian.integrate.section`) in the direction asked for is a step where g
changes sign that way (``+``: g_k < 0 <= g_k+1); its time is the root of g along the
interpolant, found by bisection to the last bits of the step, and its state is the
interpolant's there.  This is how a bifurcation diagram is read from a section
rather than a strobe (:mod:`lagrangian.ensemble.bifurcation`): every backend of the
ensemble delivers the same sampled paths.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import sympy

from .events import hermite_at
from .section import Section, section_arguments

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem

#: Halvings of the step in the search of a crossing's time: 2^-52 of the step.
BISECTIONS = 52


@dataclass(frozen=True)
class SampledCrossings:
    """The first crossings of each member: ``times`` (B, limit) and ``states``
    (2n, B, limit), NaN where a member crossed fewer than ``limit`` times."""

    times: np.ndarray
    states: np.ndarray

    @property
    def counts(self) -> np.ndarray:
        """Crossings found per member (B,), at most the limit."""
        return np.sum(np.isfinite(self.times), axis=1)


def section_values(compiled: CompiledSystem, section: Section):
    """g(t, y, params) of ``section`` for arrays: t, each row of y and of params broadcast
    together (the section's expression, printed for NumPy)."""
    arguments = section_arguments(compiled.equations.system)
    evaluate = sympy.lambdify(arguments, section.expression, "numpy")

    def values(t, y, params) -> np.ndarray:
        g = evaluate(t, *y, *params)
        return np.broadcast_to(g, np.broadcast_shapes(np.shape(t), np.shape(y[0])))

    return values


def sampled_crossings(
    compiled: CompiledSystem,
    section: Section,
    times: np.ndarray,
    paths: np.ndarray,
    params: np.ndarray,
    *,
    after: float,
    limit: int,
) -> SampledCrossings:
    """The first ``limit`` crossings later than ``after`` of each member's motion through
    ``section``, from its states ``paths`` (2n, B, S) at the step ``times`` (S,);
    ``params`` (P,) shared or (P, B) per member.  See the module docstring."""
    size, count, _ = paths.shape
    g_of = section_values(compiled, section)
    member_params = params[:, :, None] if params.ndim == 2 else params[:, None, None]
    g = g_of(times[None, :], paths, member_params)  # (B, S)
    before, later = g[:, :-1], g[:, 1:]
    rising = (before < 0) & (later >= 0)
    falling = (before > 0) & (later <= 0)
    found = {1: rising, -1: falling, 0: rising | falling}[section.direction]
    found &= times[None, 1:] > after
    members, steps = np.nonzero(found)  # in time order within each member
    rank = np.arange(members.size) - np.searchsorted(
        members, members
    )  # k-th crossing of its member
    keep = rank < limit
    members, steps, rank = members[keep], steps[keep], rank[keep]
    p = params[:, members] if params.ndim == 2 else params[:, None]
    t, y = _located(compiled, g_of, times, paths, p, members, steps)
    crossing_times = np.full((count, limit), np.nan)
    states = np.full((size, count, limit), np.nan)
    crossing_times[members, rank] = t
    states[:, members, rank] = y
    return SampledCrossings(crossing_times, states)


def _located(compiled, g_of, times, paths, p, members, steps):
    """(t (K,), y (2n, K)) of the K crossings in the steps ``steps`` of ``members``: the
    roots of g along each step's cubic Hermite interpolant."""
    t0, t1 = times[steps], times[steps + 1]
    h = t1 - t0
    y0, y1 = paths[:, members, steps], paths[:, members, steps + 1]
    f0, f1 = np.empty_like(y0), np.empty_like(y1)
    for step in np.unique(steps):  # one time per call: any compiled backend's batch form
        at = steps == step
        ps = p[:, at] if p.shape[1] > 1 else p
        f0[:, at] = compiled.rhs(times[step], y0[:, at], ps)
        f1[:, at] = compiled.rhs(times[step + 1], y1[:, at], ps)

    def state(s):
        return hermite_at(s, h, y0, f0, y1, f1)

    def g(s):
        return g_of(t0 + s * h, state(s), p)

    low, high = np.zeros_like(t0), np.ones_like(t0)
    sign_low = np.sign(g(low))
    for _ in range(BISECTIONS):
        middle = 0.5 * (low + high)
        same = np.sign(g(middle)) == sign_low
        low, high = np.where(same, middle, low), np.where(same, high, middle)
    s = 0.5 * (low + high)
    return t0 + s * h, state(s)

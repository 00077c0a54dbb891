"""Periodic orbits of an autonomous system on an energy shell, through a section.

A periodic orbit of y' = F(y) returns to its start x after a time T.  Through the
section g = 0 (:mod:`.section`) at energy h = E, x and T solve

    phi_T(x) - x = 0,    g(x) = 0,    h(x) - E = 0,

2n + 2 equations in 2n + 1 unknowns (one periodicity equation is redundant: h is
conserved), solved by Gauss-Newton (least squares) with the Jacobian

    [ M - I   F(phi_T(x)) ]
    [ dg/dx       0       ]      M = dphi_T/dx, the monodromy matrix,
    [ dh/dx       0       ]

M from the variational equations (:class:`~.lyapunov.VariationalFlow`), dg/dx and dh/dx
by central differences of the compiled section function and energy.  The starts are
points of the section on the shell (:func:`~.poincare.shell_starts`) and T the time of
their K-th return through the section in its direction (:func:`~.poincare.poincare_section`).
A converged orbit is given at its least number of returns d <= K, with its d points on the
section, its time T and its multipliers: two of them 1 (along the flow and across the
shell), the others in pairs mu, 1/mu for a Hamiltonian flow (:mod:`.floquet`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from ..errors import ModelError
from . import floquet
from .lyapunov import VariationalFlow
from .orbits import (
    DEFAULT_ATOL,
    DEFAULT_RTOL,
    HALVINGS,
    ITERATIONS,
    MAX_PERIOD,
    SAME,
    TOLERANCE,
    OrbitSearch,
    PeriodicOrbit,
    _angles,
    _merge,
    _small,
    _StrobeMap,
)
from .poincare import poincare_section
from .section import Section, state_names
from .strobe import Strobe

#: The step of the central differences of g and h (times 1 + |x_i|).
DIFFERENCE = 1e-6


def shell_orbits(
    compiled,
    *,
    section: Section,
    energy: float,
    period: int,
    starts: np.ndarray,
    t_end: float,
    params: Mapping[str, float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    watch: Callable[[float], None] | None = None,
) -> OrbitSearch:
    """The periodic orbits through ``section`` on the shell h = ``energy`` returning
    to it after at most ``period`` (K) crossings, by Newton's method from ``starts``
    (2n, N) on the section and shell, whose returns are looked for up to ``t_end``;
    see the module docstring."""
    if compiled.has_constraints:
        raise ModelError("periodic orbits of constrained systems are not supported")
    if int(period) != period or not 1 <= period <= MAX_PERIOD:
        raise ModelError(
            f"the period must be a whole number from 1 to {MAX_PERIOD}, not {period!r}"
        )
    period = int(period)
    rtol = DEFAULT_RTOL if rtol is None else rtol
    atol = DEFAULT_ATOL if atol is None else atol
    p = compiled.parameter_vector(params)
    starts = np.asarray(starts, dtype=float).reshape(2 * compiled.n, -1)
    check_autonomous(compiled, starts, p)
    names = state_names(compiled)
    returns = poincare_section(
        compiled, starts, axes=names[:2], t_end=t_end, section=section, params=params,
        rtol=rtol, atol=atol,
    )  # fmt: skip
    size = 2 * compiled.n
    flow = VariationalFlow(compiled, p, size, rtol, atol)
    # the strobe map's helpers (angles modulo 2π) serve the differences; no strobe is taken
    helper = _StrobeMap(flow, Strobe(1.0), _angles(compiled, starts, p), size)
    shell = _Shell(compiled, section, float(energy), p, flow, helper)
    found: list[PeriodicOrbit] = []
    for k in range(starts.shape[1]):
        if watch is not None:
            watch(k / starts.shape[1])
        times = returns.times[returns.orbits == k]
        times = times[times > 0.0]
        if times.size >= period:
            _merge(found, shell.newton(starts[:, k], float(times[period - 1]), period), helper)
    if watch is not None:
        watch(1.0)
    found.sort(key=lambda orbit: (orbit.period, *np.round(orbit.points[:, 0], 6)))
    return OrbitSearch(
        orbits=tuple(found),
        names=names,
        strobe=None,
        period=period,
        starts=starts.shape[1],
        settings={
            "section": section.text,
            "direction": section.direction_name,
            "energy": float(energy),
            "t_end": float(t_end),
            "rtol": rtol,
            "atol": atol,
        },
        name=compiled.equations.system.name if compiled.derived else "",
    )


class _Shell:
    """The equations of an orbit through the section on the shell, and Newton's method."""

    def __init__(self, compiled, section, energy, p, flow, helper):
        self.compiled, self.section, self.energy, self.p = compiled, section, energy, p
        self.flow, self.helper = flow, helper

    def conditions(self, x: np.ndarray) -> np.ndarray:
        """(g(x), h(x) - E)."""
        g = float(self.section.function(0.0, x, self.p))
        h = float(np.asarray(self.compiled.energy(0.0, x[:, None], self.p)).reshape(-1)[0])
        return np.array([g, h - self.energy])

    def gradients(self, x: np.ndarray) -> np.ndarray:
        """(2, 2n): dg/dx and dh/dx by central differences."""
        columns = []
        for i in range(x.size):
            step = DIFFERENCE * (1.0 + abs(x[i]))
            up, down = x.copy(), x.copy()
            up[i] += step
            down[i] -= step
            columns.append((self.conditions(up) - self.conditions(down)) / (2 * step))
        return np.column_stack(columns)

    def residual(self, x: np.ndarray, time: float):
        """(the residual [phi_T(x) - x, g, h - E], M, phi_T(x))."""
        y, w = self.flow.extended(0.0, time, x, np.eye(x.size))
        r = np.concatenate([self.helper.difference(y, x), self.conditions(x)])
        return r, w, y

    def newton(self, x: np.ndarray, time: float, period: int) -> PeriodicOrbit | None:
        """The orbit Newton's method reaches from (x, T), or None."""
        try:
            r, w, y = self.residual(x, time)
            for _ in range(ITERATIONS):
                if _small(r, x, TOLERANCE) and time > 0:
                    return self.orbit(x, time, period)
                slope = np.asarray(self.compiled.rhs(0.0, y, self.p), dtype=float)
                top = np.column_stack([w - np.eye(x.size), slope])
                bottom = np.column_stack([self.gradients(x), np.zeros(2)])
                step = -np.linalg.lstsq(np.vstack([top, bottom]), r, rcond=None)[0]
                for _ in range(HALVINGS):
                    trial_x, trial_time = x + step[:-1], time + step[-1]
                    if trial_time > 0:
                        trial = self.residual(trial_x, trial_time)
                        if np.linalg.norm(trial[0]) < np.linalg.norm(r):
                            break
                    step = step / 2
                else:
                    return None
                x, time = trial_x, trial_time
                r, w, y = trial
            return self.orbit(x, time, period) if _small(r, x, TOLERANCE) else None
        except (ModelError, np.linalg.LinAlgError):
            return None

    def orbit(self, x: np.ndarray, time: float, period: int) -> PeriodicOrbit | None:
        """The orbit through x of time T at its least number of returns to the section."""
        crossings = poincare_section(
            self.compiled, x[:, None], axes=state_names(self.compiled)[:2],
            t_end=time * (1 + 1e-9), section=self.section,
            params=dict(zip(self.compiled.parameter_names, self.p, strict=True)),
            rtol=self.flow._rtol, atol=self.flow._atol,
        )  # fmt: skip
        points = crossings.values[: x.size, crossings.times > 1e-9 * time]
        times = crossings.times[crossings.times > 1e-9 * time]
        least = next(
            (j + 1 for j in range(points.shape[1])
             if _small(self.helper.difference(points[:, j], x), x, SAME)),
            period,
        )  # fmt: skip
        if least < period:
            time = float(times[least - 1])
        r, w, _ = self.residual(x, time)
        orbit_points = [x, *(points[:, j] for j in range(least - 1))]
        return PeriodicOrbit(
            period=least,
            points=np.column_stack([self.helper.wrapped(point) for point in orbit_points]),
            monodromy=w,
            multipliers=floquet.multipliers(w),
            residual=float(np.max(np.abs(r))),
            time=float(time),
            trivial=2,
        )


def check_autonomous(compiled, states: np.ndarray, p: np.ndarray) -> None:
    """ModelError unless F does not depend on t (at a few times and the given states)."""
    now = np.asarray(compiled.rhs(0.0, states, p), dtype=float)
    for t in (0.37, 1.1, 7.3):
        later = np.asarray(compiled.rhs(t, states, p), dtype=float)
        if not np.all(np.abs(later - now) <= 1e-9 * (1.0 + np.abs(now))):
            raise ModelError(
                "periodic orbits through a section need equations that do not depend on t "
                "(an autonomous system): for a driven one, give the drive's period as the strobe"
            )

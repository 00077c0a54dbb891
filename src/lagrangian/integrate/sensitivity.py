"""Parameter sensitivities: dy(t)/dp and dy(t)/dy0 along one motion.

The state y = [q, q'] and its sensitivities S (2n x k) to the k names asked for (the
model's parameters, or initial values: a coordinate ``x`` for x(0), ``x_dot`` for
x'(0)) are integrated together, z = [y, S], by DOP853 over the forward sensitivity
equations S' = J S + [dF/dp | 0], S(0) = [0 | I] (:mod:`lagrangian.codegen.sensitivity`;
J and dF/dp are compiled symbolic derivatives, not finite differences): in SciPy's
loop, or, on the ``numba`` backend, in the compiled loop (:mod:`.compiled_sensitivity`:
the same steps, without Python per step; its first build takes seconds, then it is
loaded from the code cache).  The error control covers S as well as y, so S is as
accurate as the tolerances, and is the derivative of the continuous motion (not of
the discrete one): central differences of two full runs agree with it to their own
truncation error.  Defaults (echoed in the result): rtol 1e-10, atol 1e-12, 201
output times.  Constrained systems are refused.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError, setting
from .base import check_time_span, positive_setting
from .guard import parameter_problem, start_problem

if TYPE_CHECKING:
    import xarray

    from ..numeric.compiled import CompiledSystem

DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-12
DEFAULT_POINTS = 201


@dataclass(frozen=True)
class Sensitivities:
    """The motion y(t) and its sensitivities dy(t)/dw to each name w in ``wrt``.

    ``times`` (m,); ``states`` (m, 2n) in the order of ``state_names`` (q, then
    q_dot); ``values`` (m, 2n, k): values[i, j, l] = d state_j / d wrt_l at times[i].
    """

    times: np.ndarray
    states: np.ndarray
    values: np.ndarray
    state_names: tuple[str, ...]
    wrt: tuple[str, ...]
    initial: Mapping[str, float]
    parameters: Mapping[str, float]
    rtol: float
    atol: float
    name: str = ""

    def of(self, state: str, wrt: str) -> np.ndarray:
        """d state / d wrt at every output time, (m,)."""
        if state not in self.state_names:
            raise ModelError(f"'{state}' is not among {', '.join(self.state_names)}")
        if wrt not in self.wrt:
            raise ModelError(f"'{wrt}' is not among {', '.join(self.wrt)}")
        return self.values[:, self.state_names.index(state), self.wrt.index(wrt)]

    def settings(self) -> dict[str, float]:
        return {"t_end": float(self.times[-1]), "rtol": self.rtol, "atol": self.atol}

    def to_dataset(self) -> xarray.Dataset:
        """An xarray Dataset: ``y`` (time, state), the motion, and ``sensitivity`` (time, state,
        wrt), with the parameters, initial values and tolerances as attributes."""
        import xarray as xr

        coords = {"time": self.times, "state": list(self.state_names), "wrt": list(self.wrt)}
        attrs = {"model": self.name, "rtol": self.rtol, "atol": self.atol}
        attrs |= {f"parameter_{k}": v for k, v in self.parameters.items()}
        attrs |= {f"initial_{k}": v for k, v in self.initial.items()}
        return xr.Dataset(
            {
                "y": (("time", "state"), self.states),
                "sensitivity": (("time", "state", "wrt"), self.values),
            },
            coords=coords,
            attrs=attrs,
        )


def sensitivities(
    compiled: CompiledSystem,
    *,
    wrt: Sequence[str],
    t_end: float,
    initial: Mapping[str, float] | None = None,
    params: Mapping[str, float] | None = None,
    points: int = DEFAULT_POINTS,
    rtol: float | None = None,
    atol: float | None = None,
    watch: Callable[[float], None] | None = None,
) -> Sensitivities:
    """d(q, q')(t)/dw for each w in ``wrt`` at ``points`` times from 0 to ``t_end``.

    ``initial`` and ``params`` as for :func:`~lagrangian.integrate.simulate`; ``watch`` is
    told the time reached and may end the run by raising (its time budget).
    """
    from .compiled_sensitivity import sensitivity_loop, solve_on_grid

    if compiled.has_constraints:
        raise ModelError("sensitivities of constrained systems are not supported")
    check_time_span((0.0, t_end))
    rtol = DEFAULT_RTOL if rtol is None else positive_setting("rtol", rtol)
    atol = DEFAULT_ATOL if atol is None else positive_setting("atol", atol)
    if int(points) != points or points < 2:
        raise ModelError(
            f"the number of output times must be a whole number >= 2, not {points}",
            field=setting("points"),
        )
    names = compiled.coordinate_names
    state_names = (*names, *(f"{q}_dot" for q in names))
    wrt = _checked_wrt(wrt, compiled.parameter_names, state_names)
    size = len(state_names)
    y0 = compiled.state_vector(initial)
    p = np.ascontiguousarray(compiled.parameter_vector(params), dtype=float)
    problem = parameter_problem(compiled, 0.0, y0, p) or start_problem(compiled, 0.0, y0, p)
    if problem is not None:
        raise ModelError(problem)
    # integrated with the parameters' columns first (the order the compiled loop takes)
    parameters = [w for w in wrt if w not in state_names]
    order = [*parameters, *(w for w in wrt if w in state_names)]
    start = np.zeros((size, len(wrt)))
    for column, w in enumerate(order[len(parameters) :], len(parameters)):
        start[state_names.index(w), column] = 1.0
    z0 = np.concatenate((y0, start.ravel()))
    times = np.linspace(0.0, float(t_end), int(points))
    # the compiled loop on the numba backend only: its first build takes seconds (then it is
    # cached on disk), more than a SciPy run of the sizes a single call usually has
    loop = sensitivity_loop(compiled, parameters) if compiled.backend == "numba" else None
    if loop is not None:
        z = solve_on_grid(loop, z0, p, times, rtol, atol, watch)
    else:
        z = scipy_on_grid(compiled, parameters, z0, p, times, rtol, atol, watch)
    values = z[:, size:].reshape(len(times), size, len(wrt))[:, :, [order.index(w) for w in wrt]]
    return Sensitivities(
        times=times,
        states=z[:, :size],
        values=values,
        state_names=state_names,
        wrt=wrt,
        initial=dict(zip(state_names, map(float, y0), strict=True)),
        parameters=dict(zip(compiled.parameter_names, map(float, p), strict=True)),
        rtol=rtol,
        atol=atol,
        name=compiled.equations.system.name if compiled.derived else "",
    )


def scipy_on_grid(
    compiled, parameters, z0, p, times, rtol, atol, watch, functions=None
) -> np.ndarray:
    """z at ``times`` by SciPy's DOP853 over the state and S, the ``parameters``' columns
    first: S' = J S + [dF/dp | 0] from the lambdified derivatives (``functions``, the
    :class:`~lagrangian.numeric.sensitivity.SensitivityFunctions` of ``parameters``, made
    here unless given)."""
    from scipy.integrate import solve_ivp

    from ..numeric.sensitivity import SensitivityFunctions

    if functions is None:
        functions = SensitivityFunctions(compiled, parameters)
    size, count = 2 * compiled.n, len(parameters)

    def function(t: float, z: np.ndarray) -> np.ndarray:
        if watch is not None:
            watch(t)
        slope, jacobian, forcing = functions.derivatives(t, z[:size], p)
        flow = jacobian @ z[size:].reshape(size, -1)
        flow[:, :count] += forcing
        return np.concatenate((slope, flow.ravel()))

    solution = solve_ivp(
        function, (times[0], times[-1]), z0, method="DOP853", t_eval=times, rtol=rtol,
        atol=atol,
    )  # fmt: skip
    if solution.status != 0 or not np.all(np.isfinite(solution.y)):
        reached = solution.t[-1] if solution.t.size else 0.0
        raise ModelError(
            f"the integration failed at t = {reached:g}: "
            + (solution.message if solution.status != 0 else "the state is not finite")
        )
    return solution.y.T


class SensitivitySolver:
    """The forward sensitivity equations of ``compiled`` for the names ``wrt``, made once
    and solved for any start, parameters and output times (a fit solves them at every
    step of its search: the compiled loop, or SciPy's functions, are built here only).

    ``solve(y0, p, times)`` -> (states (m, 2n), values (m, 2n, k)), values[i, j, l] =
    d state_j / d wrt_l at times[i], the run starting at times[0].
    """

    def __init__(
        self,
        compiled: CompiledSystem,
        wrt: Sequence[str],
        *,
        rtol: float = DEFAULT_RTOL,
        atol: float = DEFAULT_ATOL,
    ):
        from .compiled_sensitivity import sensitivity_loop

        if compiled.has_constraints:
            raise ModelError("sensitivities of constrained systems are not supported")
        names = compiled.coordinate_names
        self.state_names = (*names, *(f"{q}_dot" for q in names))
        self.wrt = _checked_wrt(wrt, compiled.parameter_names, self.state_names)
        self.compiled, self.rtol, self.atol = compiled, rtol, atol
        # integrated with the parameters' columns first (the order the compiled loop takes)
        self._parameters = [w for w in self.wrt if w not in self.state_names]
        self._order = [*self._parameters, *(w for w in self.wrt if w in self.state_names)]
        # the compiled loop on the numba backend only, as in sensitivities()
        self._loop = (
            sensitivity_loop(compiled, self._parameters) if compiled.backend == "numba" else None
        )
        self._functions = None
        if self._loop is None:
            from ..numeric.sensitivity import SensitivityFunctions

            self._functions = SensitivityFunctions(compiled, self._parameters)

    @property
    def compiled_loop(self) -> bool:
        """Whether the equations run in the compiled loop (numba), not SciPy's."""
        return self._loop is not None

    def solve(
        self,
        y0: np.ndarray,
        p: np.ndarray,
        times: np.ndarray,
        watch: Callable[[float], None] | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        from .compiled_sensitivity import solve_on_grid

        size, count = len(self.state_names), len(self.wrt)
        start = np.zeros((size, count))
        for column, w in enumerate(self._order[len(self._parameters) :], len(self._parameters)):
            start[self.state_names.index(w), column] = 1.0
        z0 = np.concatenate((np.asarray(y0, dtype=float), start.ravel()))
        p = np.ascontiguousarray(p, dtype=float)
        if self._loop is not None:
            z = solve_on_grid(self._loop, z0, p, times, self.rtol, self.atol, watch)
        else:
            z = scipy_on_grid(
                self.compiled, self._parameters, z0, p, times, self.rtol, self.atol, watch,
                self._functions,
            )  # fmt: skip
        columns = [self._order.index(w) for w in self.wrt]
        values = z[:, size:].reshape(len(times), size, count)[:, :, columns]
        return z[:, :size], values


def _checked_wrt(
    wrt: Sequence[str], parameters: Sequence[str], state_names: Sequence[str]
) -> tuple[str, ...]:
    """``wrt`` as a tuple; an error for none, a repeat, or a name that is neither a
    parameter nor a coordinate or velocity (a coordinate means its initial value)."""
    wrt = tuple(wrt)
    if not wrt:
        raise ModelError("give at least one name to differentiate by", field=setting("wrt"))
    for index, name in enumerate(wrt):
        if name in wrt[:index]:
            raise ModelError(f"'{name}' is given twice", field=setting("wrt"))
        if name not in parameters and name not in state_names:
            raise ModelError(
                f"'{name}' is neither a parameter nor a coordinate or velocity "
                f"(parameters: {', '.join(parameters) or 'none'}; "
                f"initial values: {', '.join(state_names)})",
                field=setting("wrt"),
            )
    return wrt

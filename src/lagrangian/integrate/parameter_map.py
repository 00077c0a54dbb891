"""The K-fold strobe map with its derivatives in the state and in one parameter.

For the continuation of periodic orbits (:mod:`.continuation`): the map x -> G_A^K(x)
(G the strobe map from t = phase, :mod:`.strobe`), its Jacobian M = dG^K/dx (the
monodromy matrix) and its parameter column dG^K/dA, all from one run of the forward
sensitivity equations S' = J S + [dF/dA | 0], S(t_0) = [0 | I] over the K periods
(:mod:`.sensitivity`; J and dF/dA the compiled symbolic derivatives, not finite
differences): in the compiled DOP853 loop of :mod:`.compiled_sensitivity` where numba is
installed, else in SciPy's DOP853.  The run's error control covers S, so M and dG^K/dA
are as accurate as the tolerances.  On the angles (coordinates on which F is 2π-periodic)
the residual G^K(x) - x is taken modulo 2π.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .strobe import AngleWrapping, Strobe

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem


@dataclass(frozen=True)
class MapValue:
    """G^K at one (x, A): the ``points`` (2n, K + 1) x, G(x), ..., G^K(x), the
    ``monodromy`` dG^K/dx (2n, 2n) and ``column`` dG^K/dA (2n,)."""

    points: np.ndarray
    monodromy: np.ndarray
    column: np.ndarray


class ParameterMap(AngleWrapping):
    """G_A^K of ``compiled`` at the ``clock``'s times, A the parameter ``name``; the other
    parameters' values ``params`` (its entry of A is replaced at each call)."""

    def __init__(
        self,
        compiled: CompiledSystem,
        clock: Strobe,
        name: str,
        params: np.ndarray,
        angles: np.ndarray,
        rtol: float,
        atol: float,
        watch: Callable[[float], None] | None = None,
    ):
        from .compiled_dop853 import loop_applies
        from .compiled_sensitivity import sensitivity_loop

        self.compiled, self.clock, self.name = compiled, clock, name
        self.index = compiled.parameter_names.index(name)
        self.params = np.array(params, dtype=float)
        self.angles = np.asarray(angles, dtype=int)
        self.size = 2 * compiled.n
        self.rtol, self.atol, self.watch = rtol, atol, watch
        self.loop = sensitivity_loop(compiled, (name,)) if loop_applies(compiled) else None
        self.runs, self.value = 0, float(params[self.index])

    def __call__(self, x: np.ndarray, value: float, count: int) -> MapValue:
        """G^count and its derivatives at (x, A = ``value``)."""
        from .compiled_sensitivity import solve_on_grid
        from .sensitivity import scipy_on_grid

        size = self.size
        start = np.zeros((size, size + 1))
        start[:, 1:] = np.eye(size)
        z0 = np.concatenate((np.asarray(x, dtype=float), start.ravel()))
        params = self.params.copy()
        params[self.index] = self.value = float(value)
        times = np.asarray(self.clock.time(np.arange(count + 1)), dtype=float)
        self.runs += 1
        if self.loop is not None:
            z = solve_on_grid(self.loop, z0, params, times, self.rtol, self.atol, self.watch)
        else:
            z = scipy_on_grid(
                self.compiled, (self.name,), z0, params, times, self.rtol, self.atol, self.watch
            )
        sensitivity = z[-1, size:].reshape(size, size + 1)
        return MapValue(z[:, :size].T, sensitivity[:, 1:], sensitivity[:, 0])

"""Explicit Runge-Kutta methods with a fixed step, from a Butcher tableau.

For y' = F(t, y) with F = ``compiled.rhs`` and the tableau (A, b, c):

    k_i     = F(t + c_i h, y + h sum_{j<i} a_ij k_j),
    y_{n+1} = y_n + h sum_i b_i k_i,

s evaluations of F per step, global error O(h^p) for a tableau of order p.
Not symplectic: on a conservative system the energy error grows with time
(linearly for RK4; Hairer, Lubich & Wanner, *Geometric Numerical
Integration*, 2nd ed. 2006, VI.4 and IX), which the variational method avoids.
The step works on a batch of states y (2n, B) unchanged, because F does.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from . import tableaus
from .fixed_step import AbstractFixedStepIntegrator


@dataclass(frozen=True)
class AbstractExplicitRungeKutta(AbstractFixedStepIntegrator):
    """A fixed-step explicit Runge-Kutta method; leaves set ``tableau`` (explicit)."""

    tableau: ClassVar[tableaus.ButcherTableau]
    symplectic: ClassVar[bool] = False
    needs: ClassVar[str] = "first_order"

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        tableau = getattr(cls, "tableau", None)
        if tableau is not None and not tableau.explicit:
            raise TypeError(f"{cls.__name__}: tableau {tableau.name} is not explicit")

    def init(self, compiled, t, y, params, work):
        return None

    def printed_scheme(self, compiled) -> str | None:
        return "rk4" if self.tableau is tableaus.RK4 else None

    def step(self, compiled, t, h, y, state, params, work):
        a, b, c = self.tableau.a, self.tableau.b, self.tableau.c
        stages: list[np.ndarray] = []
        for i in range(self.tableau.stages):
            y_stage = y
            for j in range(i):
                if a[i, j] != 0.0:
                    y_stage = y_stage + (h * a[i, j]) * stages[j]
            stages.append(compiled.rhs(t + c[i] * h, y_stage, params))
        work.rhs_evaluations += self.tableau.stages
        increment = sum(b_i * k for b_i, k in zip(b, stages, strict=True) if b_i != 0.0)
        return y + h * increment, None


@dataclass(frozen=True)
class RK4(AbstractExplicitRungeKutta):
    """The classical fourth-order Runge-Kutta method (4 evaluations of rhs per step).

    >>> RK4(dt=0.1).settings()
    {'method': 'rk4', 'dt': 0.1}
    """

    name: ClassVar[str] = "rk4"
    order: ClassVar[int] = 4
    default_omega_dt: ClassVar[float] = 0.05  # phase error (ω dt)^4/120 = 5e-8 per radian
    stability_limit: ClassVar[float] = 2.8  # 2 sqrt(2) on the imaginary axis
    tableau: ClassVar[tableaus.ButcherTableau] = tableaus.RK4


@dataclass(frozen=True)
class RK38(AbstractExplicitRungeKutta):
    """Kutta's 3/8 rule, fourth order (4 evaluations of rhs per step)."""

    name: ClassVar[str] = "rk38"
    order: ClassVar[int] = 4
    default_omega_dt: ClassVar[float] = 0.05
    stability_limit: ClassVar[float] = 2.8
    tableau: ClassVar[tableaus.ButcherTableau] = tableaus.RK38

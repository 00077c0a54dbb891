"""Butcher tableaus as validated data.

A Runge-Kutta method with s stages advances y' = F(t, y) by

    k_i     = F(t + c_i h, y + h sum_j a_ij k_j),   i = 1..s,
    y_{n+1} = y_n + h sum_i b_i k_i.

A :class:`ButcherTableau` checks on construction what every consistent tableau
satisfies: sum(b) = 1, the row sums of A equal c (the stage times are those
the stages integrate to), and the order conditions of its declared order, up
to order 4 (the rooted trees of Hairer, Norsett & Wanner, *Solving Ordinary
Differential Equations I*, 2nd ed. 1993, II.2, table 2.2).  ``explicit`` is
true when A is strictly lower triangular.

>>> RK4.order, RK4.stages, RK4.explicit
(4, 4, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TOLERANCE = 1e-14


@dataclass(frozen=True, eq=False)
class ButcherTableau:
    """Coefficients (A, b, c) of a Runge-Kutta method, validated when built."""

    name: str
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    order: int

    def __post_init__(self) -> None:
        a, b, c = (np.array(x, dtype=float) for x in (self.a, self.b, self.c))
        s = b.shape[0] if b.ndim == 1 else -1
        if b.ndim != 1 or c.shape != (s,) or a.shape != (s, s):
            raise ValueError(
                f"tableau {self.name}: A must be s x s, b and c of length s "
                f"(got A {a.shape}, b {b.shape}, c {c.shape})"
            )
        for array in (a, b, c):
            array.setflags(write=False)
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "b", b)
        object.__setattr__(self, "c", c)
        if abs(b.sum() - 1.0) > TOLERANCE:
            raise ValueError(f"tableau {self.name}: the weights b sum to {float(b.sum())!r}, not 1")
        rows = a.sum(axis=1)
        if np.max(np.abs(rows - c)) > TOLERANCE:
            raise ValueError(f"tableau {self.name}: the row sums of A {rows.tolist()} are not c")
        if not 1 <= self.order <= 4:
            raise ValueError(f"tableau {self.name}: orders 1 to 4 can be checked, not {self.order}")
        residuals = order_conditions(a, b, c, self.order)
        worst = max(residuals, key=lambda item: abs(item[1]))
        if abs(worst[1]) > TOLERANCE:
            raise ValueError(
                f"tableau {self.name}: order condition {worst[0]} fails by {worst[1]:.3e} "
                f"(declared order {self.order})"
            )

    @property
    def stages(self) -> int:
        return self.b.shape[0]

    @property
    def explicit(self) -> bool:
        """A strictly lower triangular: each stage uses only the stages before it."""
        return bool(np.all(np.triu(self.a) == 0.0))


def order_conditions(
    a: np.ndarray, b: np.ndarray, c: np.ndarray, order: int
) -> list[tuple[str, float]]:
    """Residuals of the order conditions up to ``order`` (<= 4): (condition, lhs - rhs)."""
    ac = a @ c
    conditions = [("sum b = 1", b.sum() - 1.0)]
    if order >= 2:
        conditions.append(("b.c = 1/2", b @ c - 1 / 2))
    if order >= 3:
        conditions += [("b.c^2 = 1/3", b @ c**2 - 1 / 3), ("b.Ac = 1/6", b @ ac - 1 / 6)]
    if order >= 4:
        conditions += [
            ("b.c^3 = 1/4", b @ c**3 - 1 / 4),
            ("b.(c*Ac) = 1/8", b @ (c * ac) - 1 / 8),
            ("b.Ac^2 = 1/12", b @ (a @ c**2) - 1 / 12),
            ("b.AAc = 1/24", b @ (a @ ac) - 1 / 24),
        ]
    return conditions


#: The classical Runge-Kutta method (Kutta 1901), order 4.
RK4 = ButcherTableau(
    name="rk4",
    a=[[0, 0, 0, 0], [1 / 2, 0, 0, 0], [0, 1 / 2, 0, 0], [0, 0, 1, 0]],
    b=[1 / 6, 1 / 3, 1 / 3, 1 / 6],
    c=[0, 1 / 2, 1 / 2, 1],
    order=4,
)

#: Kutta's 3/8 rule, order 4 (smaller error constant than RK4 on many problems).
RK38 = ButcherTableau(
    name="rk38",
    a=[[0, 0, 0, 0], [1 / 3, 0, 0, 0], [-1 / 3, 1, 0, 0], [1, -1, 1, 0]],
    b=[1 / 8, 3 / 8, 3 / 8, 1 / 8],
    c=[0, 1 / 3, 2 / 3, 1],
    order=4,
)

#: The explicit midpoint rule (Runge 1895), order 2.
MIDPOINT = ButcherTableau(
    name="midpoint",
    a=[[0, 0], [1 / 2, 0]],
    b=[0, 1],
    c=[0, 1 / 2],
    order=2,
)

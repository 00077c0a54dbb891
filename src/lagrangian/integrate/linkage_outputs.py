"""A linkage's joint reactions along a run (:mod:`lagrangian.model.linkage_reactions`
gives them as expressions in t, q, q', q'', the parameters and the multipliers)."""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np
import sympy

if TYPE_CHECKING:
    from ..model import System
    from ..numeric.compiled import CompiledSystem


def reactions_along(
    compiled: CompiledSystem,
    t: np.ndarray,
    y: np.ndarray,
    params: np.ndarray,
    multipliers: Mapping[str, np.ndarray],
) -> dict[str, np.ndarray]:
    """{column: values at the times t} of the linkage of ``compiled``'s system, or {}."""
    system = getattr(compiled.equations, "system", None)
    linkage = getattr(system, "linkage", None)
    if linkage is None or not linkage.reactions or t.shape[0] == 0:
        return {}
    from .simulate import along

    n = compiled.n
    names = compiled.constraint_names[linkage.offset : linkage.offset + len(linkage.multipliers)]
    if len(names) != len(linkage.multipliers) or any(name not in multipliers for name in names):
        return {}
    accelerations = np.asarray(along(compiled.rhs, t, y, params), dtype=float)[n:]
    position = {name: k for k, name in enumerate(compiled.coordinate_names)}
    order = [position[name] for name in system.coordinate_names]
    values = {name: k for k, name in enumerate(compiled.parameter_names)}
    arguments = [
        t,
        *(y[k] for k in order),
        *(y[n + k] for k in order),
        *(accelerations[k] for k in order),
        *(np.asarray(multipliers[name], dtype=float) for name in names),
        *(np.full(t.shape, params[values[p.name]]) for p in system.parameters),
    ]
    values = _function(system)(*arguments)
    return {
        name: np.broadcast_to(np.asarray(value, dtype=float), t.shape).copy()
        for name, value in zip(linkage.reactions, values, strict=True)
    }


@lru_cache(maxsize=16)
def _function(system: System):
    """All the reactions as one NumPy function (one lambdify with shared subexpressions:
    0.03 s for the four-bar's nine, where one each took 0.17 s)."""
    linkage = system.linkage
    symbols = [
        system.time,
        *(c.q for c in system.coordinates),
        *(c.q_dot for c in system.coordinates),
        *(c.q_ddot for c in system.coordinates),
        *linkage.multipliers,
        *(p.symbol for p in system.parameters),
    ]
    return sympy.lambdify(symbols, list(linkage.reactions.values()), "numpy", cse=True)

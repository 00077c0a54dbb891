"""The numerical functions of a system's contacts (:mod:`lagrangian.model.impacts`).

For the gaps g_k(q, t) of the model's ``[[impacts]]`` (the model's functions defined, as
in the equations): the gaps, their gradients G = dg/dq (k x n), their partial time
derivatives g_t, and the part of g'' that is not G q'',

    kappa_k = q'^T (d^2 g_k / dq^2) q' + 2 (d^2 g_k / dq dt) . q' + d^2 g_k / dt^2,

so that g'' = G q'' + kappa along a motion: what holding a contact closed (g = 0) as a
constraint needs.  Each is one function of the plain numbers (t, q, q', params),
lambdified once (NumPy's functions on scalars: a contact's events evaluate one state at a
time), and ``restitutions(params)`` gives each contact's e.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import sympy

from ..codegen.definitions import substitute
from .compiled import CompiledSystem


@dataclass(frozen=True, eq=False)
class ContactFunctions:
    """The contacts of one compiled system (see the module docstring)."""

    names: tuple[str, ...]
    gaps: tuple[sympy.Expr, ...]
    restitution: tuple[sympy.Expr, ...]
    coordinates: tuple[sympy.Symbol, ...]
    velocities: tuple[sympy.Symbol, ...]
    time: sympy.Symbol
    parameters: tuple[sympy.Symbol, ...]

    @property
    def count(self) -> int:
        return len(self.names)

    def _lambdify(self, expressions):
        arguments = (self.time, *self.coordinates, *self.velocities, *self.parameters)
        return sympy.lambdify(arguments, expressions, modules="numpy", cse=True, dummify=True)

    @cached_property
    def _gap_function(self):
        return self._lambdify(list(self.gaps))

    @cached_property
    def _geometry_function(self):
        q, v, t = self.coordinates, self.velocities, self.time
        gradient = [[sympy.diff(g, x) for x in q] for g in self.gaps]
        rate = [sympy.diff(g, t) for g in self.gaps]
        curvature = []
        for row, g_t in zip(gradient, rate, strict=True):
            first = sum((d * w for d, w in zip(row, v, strict=True)), g_t)  # g' = G q' + g_t
            second = sum(sympy.diff(first, x) * w for x, w in zip(q, v, strict=True))
            curvature.append(second + sympy.diff(first, t))
        return self._lambdify([[d for row in gradient for d in row], rate, curvature])

    @cached_property
    def _restitution_function(self):
        return sympy.lambdify(self.parameters, list(self.restitution), modules="numpy")

    def gap_values(self, t: float, y: np.ndarray, params: np.ndarray) -> np.ndarray:
        """g_k at (t, y) for every contact, shape (k,)."""
        return np.asarray(self._gap_function(t, *y, *params), dtype=float).reshape(self.count)

    def geometry(self, t: float, y: np.ndarray, params: np.ndarray):
        """(G (k, n), g_t (k,), kappa (k,)) at (t, y)."""
        gradient, rate, curvature = self._geometry_function(t, *y, *params)
        n = len(self.coordinates)
        return (
            np.asarray(np.broadcast_arrays(*gradient), dtype=float).reshape(self.count, n),
            np.asarray(np.broadcast_arrays(*rate), dtype=float).reshape(self.count),
            np.asarray(np.broadcast_arrays(*curvature), dtype=float).reshape(self.count),
        )

    def restitutions(self, params: np.ndarray) -> np.ndarray:
        """e_k at the parameter values ``params``, shape (k,)."""
        values = self._restitution_function(*params)
        return np.asarray(np.broadcast_arrays(*values), dtype=float).reshape(self.count)


def contact_functions(compiled: CompiledSystem) -> ContactFunctions | None:
    """The contacts of ``compiled`` (None when its model has none)."""
    system = compiled.equations.system
    impacts = getattr(system, "impacts", ())
    if not impacts:
        return None
    definitions = compiled.forms.definitions if compiled.forms is not None else {}
    return ContactFunctions(
        names=tuple(impact.name for impact in impacts),
        gaps=tuple(substitute(impact.gap, definitions) for impact in impacts),
        restitution=tuple(sympy.sympify(impact.restitution) for impact in impacts),
        coordinates=tuple(c.q for c in system.coordinates),
        velocities=tuple(c.q_dot for c in system.coordinates),
        time=system.time,
        parameters=tuple(p.symbol for p in system.parameters),
    )

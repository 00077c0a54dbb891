"""The numerical functions of a system's contacts (:mod:`lagrangian.model.impacts`).

The contacts' symbolic forms (gaps, gradients G, g_t, kappa with g'' = G q'' + kappa, and
the restitutions; :mod:`lagrangian.codegen.contacts`) as functions of the plain numbers
(t, q, q', params), each lambdified once (NumPy's functions on scalars: a contact's
events evaluate one state at a time).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import sympy

from ..codegen.contacts import ContactForms, contact_forms
from .compiled import CompiledSystem


@dataclass(frozen=True, eq=False)
class ContactFunctions:
    """The contacts of one compiled system (see the module docstring)."""

    forms: ContactForms
    arguments: tuple[sympy.Symbol, ...]  # t, q, q', params
    parameters: tuple[sympy.Symbol, ...]

    @property
    def names(self) -> tuple[str, ...]:
        return self.forms.names

    @property
    def count(self) -> int:
        return len(self.forms.names)

    def _lambdify(self, expressions):
        return sympy.lambdify(self.arguments, expressions, modules="numpy", cse=True, dummify=True)

    @cached_property
    def _gap_function(self):
        return self._lambdify(list(self.forms.gaps))

    @cached_property
    def _geometry_function(self):
        forms = self.forms
        flat = [d for row in forms.gradient for d in row]
        return self._lambdify([flat, list(forms.rate), list(forms.curvature)])

    @cached_property
    def _restitution_function(self):
        return sympy.lambdify(self.parameters, list(self.forms.restitution), modules="numpy")

    def gap_values(self, t: float, y: np.ndarray, params: np.ndarray) -> np.ndarray:
        """g_k at (t, y) for every contact, shape (k,)."""
        return np.asarray(self._gap_function(t, *y, *params), dtype=float).reshape(self.count)

    def geometry(self, t: float, y: np.ndarray, params: np.ndarray):
        """(G (k, n), g_t (k,), kappa (k,)) at (t, y)."""
        gradient, rate, curvature = self._geometry_function(t, *y, *params)
        n = (len(self.arguments) - 1 - len(self.parameters)) // 2
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
    """The contacts of ``compiled`` (None when its model has none, or its functions were
    given by hand, without symbolic forms)."""
    forms = compiled.forms
    if forms is None or not getattr(compiled.equations.system, "impacts", ()):
        return None
    contacts = contact_forms(forms)
    arguments = (forms.time, *forms.coordinates, *forms.velocities, *forms.parameters)
    return ContactFunctions(contacts, arguments, forms.parameters)

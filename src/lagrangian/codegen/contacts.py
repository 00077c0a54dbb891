"""The symbolic forms of a system's contacts (``[[impacts]]``), beside the equations' forms.

For each contact k: the gap g_k(q, t) (the model's functions put in, as in the equations),
its gradient G_k = dg_k/dq, its partial time derivative g_t, the part of g'' that is not
G q'',

    kappa_k = q'^T (d^2 g_k / dq^2) q' + 2 (d^2 g_k / dq dt) . q' + d^2 g_k / dt^2,

so that g'' = G q'' + kappa along a motion (what holding a contact closed needs), and its
restitution e_k.  The numerical stages compile these (:mod:`lagrangian.numeric.impacts`).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy

from ..algebra import as_expression
from .definitions import substitute
from .forms import SymbolicForms


@dataclass(frozen=True)
class ContactForms:
    """The contacts' expressions (see the module docstring), over the forms' symbols."""

    names: tuple[str, ...]
    gaps: tuple[sympy.Expr, ...]
    gradient: tuple[tuple[sympy.Expr, ...], ...]  # k rows of n
    rate: tuple[sympy.Expr, ...]
    curvature: tuple[sympy.Expr, ...]
    restitution: tuple[sympy.Expr, ...]


def contact_forms(forms: SymbolicForms) -> ContactForms | None:
    """The contacts of the system of ``forms`` (None when it has none)."""
    impacts = getattr(forms.equations.system, "impacts", ())
    if not impacts:
        return None
    q, v, t = forms.coordinates, forms.velocities, forms.time
    gaps = tuple(substitute(impact.gap, forms.definitions) for impact in impacts)
    gradient = tuple(tuple(sympy.diff(g, x) for x in q) for g in gaps)
    rate = tuple(sympy.diff(g, t) for g in gaps)
    curvature = []
    for row, g_t in zip(gradient, rate, strict=True):
        first = sum((d * w for d, w in zip(row, v, strict=True)), g_t)  # g' = G q' + g_t
        second = sum(sympy.diff(first, x) * w for x, w in zip(q, v, strict=True))
        curvature.append(second + sympy.diff(first, t))
    return ContactForms(
        names=tuple(impact.name for impact in impacts),
        gaps=gaps,
        gradient=gradient,
        rate=rate,
        curvature=tuple(curvature),
        restitution=tuple(as_expression(impact.restitution) for impact in impacts),
    )

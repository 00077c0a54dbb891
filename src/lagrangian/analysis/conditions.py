"""When symbolic omega^2 decide stability only at the default values: the condition.

With symmetric M0 > 0, K0 and no velocity terms, the equilibrium is linearly
stable exactly when every root omega^2 of det(K0 - omega^2 M0) = 0 is
positive.  A root whose sign the parameters' assumptions (positive, real,
non-zero for generic values) do not decide was judged at the default values;
this module states that, and writes the condition omega^2 > 0 in the parameters
the way a textbook does: factors known to be positive dropped, negative ones
flipping the inequality, and the rest as ``positive terms > negative terms``
(a bead on a parabola z = a r^2 turning at omega: omega^2 = 2 a g - omega^2 > 0
reads 2 a g > omega^2; the bottom of a turning hoop: g > R omega^2).

Roots that are rational functions of the parameters give root > 0; a pair
with opposite square roots of a discriminant D (gyroscopic terms) gives D > 0
and a positive sum and product.  Damped systems get no condition here.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy

from ..sizes import ops_exceed
from .modes import NormalModes, Stability, assumed_sign

#: Largest root (operation count) turned into a condition.
CONDITION_MAX_OPS = 200


@dataclass(frozen=True)
class StabilityVerdict:
    """``at_defaults``: the verdict holds at the default values only; ``condition``:
    the parameters' condition for stability (None when not found or not needed)."""

    at_defaults: bool
    condition: sympy.Basic | None = None


def stability_verdict(modes: NormalModes, *, damped: bool = False) -> StabilityVerdict:
    """Whether the stability of ``modes`` was judged at the defaults, and the condition.

    Without damping the condition is that every omega^2 be real and positive:
    rational roots r give r > 0; a pair r+-, r- = (P +- Q sqrt(D))/R (gyroscopic
    terms: a charge in a Penning trap) gives D > 0, r+ + r- > 0 and r+ r- > 0.
    """
    if not modes.closed_form or modes.stability is Stability.ASYMPTOTICALLY_STABLE:
        return StabilityVerdict(False)
    undecided = [r for r in modes.omega_squared if r.free_symbols and _sign(r) is None]
    if not undecided:
        return StabilityVerdict(False)
    if damped or any(_sign(r) in ("-", "0") for r in modes.omega_squared):
        return StabilityVerdict(True)  # damped, or never stable: no condition
    parts: list[sympy.Basic] = []
    remaining = list(undecided)
    while remaining:
        root = remaining.pop(0)
        found = _positive(root)
        if found is None:
            found = _pair(root, remaining)
        if found is None:
            return StabilityVerdict(True)
        parts += [c for c in found if c not in parts]
    condition = sympy.And(*parts) if len(parts) > 1 else parts[0]
    return StabilityVerdict(True, condition)


def _pair(root: sympy.Expr, others: list[sympy.Expr]) -> list[sympy.Basic] | None:
    """Conditions for ``root`` and its partner with the opposite square root (taken out of
    ``others``) to be real and positive: D > 0, their sum and product positive."""
    roots_of = [a for a in root.atoms(sympy.Pow) if a.exp == sympy.Rational(1, 2)]
    if len(roots_of) != 1:
        return None
    (radical,) = roots_of
    partner = sympy.expand(root.xreplace({radical: -radical}))
    match = next((o for o in others if sympy.expand(o - partner) == 0), None)
    if match is None:
        return None
    others.remove(match)
    conditions = []
    for quantity in (radical.base, root + match, root * match):
        quantity = sympy.cancel(sympy.expand(quantity))
        sign = _sign(quantity)
        if sign == "+":
            continue
        condition = _positive(quantity)
        if sign in ("-", "0") or condition is None:
            return None
        conditions += condition
    return conditions


def _sign(expr: sympy.Expr) -> str | None:
    """'+', '0' or '-' where the assumptions decide it (a complex value decides nothing)."""
    sign = assumed_sign(expr)
    return None if sign == "complex" else sign


def _positive(root: sympy.Expr) -> list[sympy.Basic] | None:
    """``[root > 0]`` written in the parameters, or None for roots not handled."""
    if ops_exceed(root, CONDITION_MAX_OPS) or not root.is_rational_function(*root.free_symbols):
        return None
    numerator, denominator = sympy.fraction(sympy.factor(sympy.together(root)))
    flip = False
    kept = []
    for factor in (*sympy.Mul.make_args(numerator), *sympy.Mul.make_args(denominator)):
        sign = _sign(factor)
        if sign == "+":
            continue
        if sign == "-":
            flip = not flip
            continue
        kept.append(factor)
    if not kept:
        return None
    expr = sympy.expand(sympy.Mul(*kept))
    if flip:
        expr = -expr
    terms = sympy.Add.make_args(expr)
    left = sympy.Add(*(t for t in terms if not t.could_extract_minus_sign()))
    right = -sympy.Add(*(t for t in terms if t.could_extract_minus_sign()))
    return [sympy.StrictGreaterThan(left, right, evaluate=False)]

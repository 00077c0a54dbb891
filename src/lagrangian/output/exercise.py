"""The exercise of a model's page: the right answers as data the page's checker reads.

``lagrangian page MODEL --exercise kinetic,potential,lagrangian,equations`` hides the
worked solution and asks the student for the steps a teacher chose; the page checks each
answer in the browser, offline, as :func:`lagrangian.analysis.check.check` does
(``page_assets/exercise.js``: the same numerical identity tests and term-by-term split).
Its right answers travel here as expression trees (JSON, never code: the page's
Content-Security-Policy runs no generated text, and the student's text is parsed by the
page's own small parser, never evaluated):

    ["n", 2.5]  ["s", "theta"]  ["+", a, b, ...]  ["*", a, b, ...]  ["^", base, exponent]
    ["f", "cos", argument, ...]

with each right answer's groups of terms (:mod:`lagrangian.analysis.check.terms`: a key,
the group's value and its printed form) made by the same rules as ``check``'s.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy

from ..analysis.check import raw_equations, right_kinetic, right_potential, state_symbols
from ..analysis.check.answers import euler_lagrange
from ..analysis.check.sampling import points
from ..analysis.check.terms import groups, printed_term
from ..derive import EquationsOfMotion
from ..errors import ModelError, setting
from .large import latex_printer
from .notation import latex_name

#: The steps a page can ask, in the order it asks them.
STEPS = ("kinetic", "potential", "lagrangian", "equations")
#: SymPy's functions by the name the page's parser knows them by.
FUNCTIONS = {
    sympy.sin: "sin", sympy.cos: "cos", sympy.tan: "tan", sympy.cot: "cot",
    sympy.sec: "sec", sympy.csc: "csc", sympy.asin: "asin", sympy.acos: "acos",
    sympy.atan: "atan", sympy.atan2: "atan2", sympy.sinh: "sinh", sympy.cosh: "cosh",
    sympy.tanh: "tanh", sympy.exp: "exp", sympy.log: "log", sympy.Abs: "Abs",
    sympy.sign: "sign",
}  # fmt: skip


NO_FUNCTIONS = "No exercise: the model's unspecified functions have no values to check answers at."
NO_CONSTRAINTS = (
    "The equations of motion are not asked: with constraints they hold Lagrange "
    "multipliers, which the page's checker does not handle (lagrangian check neither)."
)


def exercise_steps(text: str | Sequence[str]) -> tuple[str, ...]:
    """The steps named in ``text`` (``kinetic,potential``; ``all``: every one), checked."""
    names = text.split(",") if isinstance(text, str) else list(text)
    names = [name.strip() for name in names if name.strip()]
    if names == ["all"]:
        return STEPS
    unknown = [name for name in names if name not in STEPS]
    if unknown or not names:
        raise ModelError(
            f"unknown exercise step '{unknown[0] if unknown else ''}' (steps: all or "
            f"{', '.join(STEPS)}, separated by commas)",
            field=setting("exercise"),
        )
    return tuple(step for step in STEPS if step in names)


def exercise_document(eom: EquationsOfMotion, steps: Sequence[str]) -> dict:
    """What the page's checker needs for ``steps``: the names, and per step the right
    answer's tree, its groups and its LaTeX (shown on request); ``notes`` say what is not
    asked and why (the page then asks the rest: a teacher's page, or serve's Exercise box
    on any model, is still made)."""
    system = eom.system
    if system.functions:  # nothing can be checked at points: the solution stays in view
        return {"steps": [], "notes": [NO_FUNCTIONS]}
    notes = []
    if "equations" in steps and eom.constraints is not None:
        steps = [step for step in steps if step != "equations"]
        notes.append(NO_CONSTRAINTS)
    state = state_symbols(eom)
    at = points(state, [p.symbol for p in system.parameters])
    show = latex_printer(system)

    def answer(expr: sympy.Expr, up_to_constant: bool = False) -> dict:
        found = groups(expr, state, at)
        return {
            "tree": tree(expr),
            "latex": show(expr),
            "groups": [
                {
                    "key": tree(g.key),
                    "value": tree(g.term),
                    "printed": printed_term(g.term),
                    "coefficient": printed_term(g.term / g.key),
                    "monomial": monomial(g.term),
                }
                for g in found
            ],
            "up_to_constant": up_to_constant,
        }

    document: dict = {
        "names": {
            "state": sorted(s.name for s in state),
            "parameters": [
                {"name": p.name, "positive": bool(p.symbol.is_positive)} for p in system.parameters
            ],
            "coordinates": [
                {
                    "name": c.name,
                    "velocity": c.q_dot.name,
                    "acceleration": c.q_ddot.name,
                    "latex": latex_name(c.name),
                }
                for c in system.coordinates
            ],
        },
        "steps": list(steps),
        "notes": notes,
    }
    if "kinetic" in steps:
        document["kinetic"] = answer(right_kinetic(eom))
    if "potential" in steps:
        document["potential"] = answer(right_potential(eom), up_to_constant=True)
    if "lagrangian" in steps:
        document["lagrangian"] = answer(eom.lagrangian, up_to_constant=True)
        document["lagrangian"]["euler_lagrange"] = [
            tree(e) for e in euler_lagrange(eom.lagrangian, eom)
        ]
    if "equations" in steps:
        document["equations"] = [
            answer(raw) | {"shown": tree(step.equation), "coordinate": step.coordinate.name}
            for raw, step in zip(raw_equations(eom), eom.steps, strict=True)
        ]
    return document


def monomial(term: sympy.Expr) -> dict | None:
    """A one-term group as ``{"c": number, "factors": [[tree, exponent], ...]}`` (the page
    prints an equation's right term in the student's scale from it); None for a sum."""
    if len(sympy.Add.make_args(sympy.expand(term))) != 1:
        return None
    coefficient, rest = term.as_coeff_Mul()
    powers = rest.as_powers_dict() if rest != 1 else {}
    return {
        "c": float(coefficient),
        "factors": [[tree(base), float(exponent)] for base, exponent in powers.items()],
    }


def tree(expr: sympy.Expr) -> list:
    """``expr`` as the page's expression tree (see the module's docstring)."""
    if expr.is_Symbol:
        return ["s", expr.name]
    if expr.is_Number or expr in (sympy.pi, sympy.E):
        return ["n", float(expr)]
    if expr.is_Add:
        return ["+", *(tree(arg) for arg in expr.args)]
    if expr.is_Mul:
        return ["*", *(tree(arg) for arg in expr.args)]
    if expr.is_Pow:
        return ["^", tree(expr.base), tree(expr.exp)]
    name = FUNCTIONS.get(expr.func)
    if name is not None:
        return ["f", name, *(tree(arg) for arg in expr.args)]
    raise ModelError(f"the exercise page cannot evaluate {expr.func.__name__}()",
                     field=setting("exercise"))  # fmt: skip

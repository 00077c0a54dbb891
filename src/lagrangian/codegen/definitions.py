"""Definitions of a model's unspecified functions, so that its equations can be compiled.

A model may declare functions without giving them (``[functions] A = ["x", "y",
"z"]``): the equations of motion then hold ``A(x, y, z)`` and its derivatives,
which have no numerical value.  A definition supplies the function, either as
text over the declared argument names, the parameters and ``t`` (read by the
safe parser, :func:`lagrangian.parsing.parse_expression`) or as a
:class:`sympy.Lambda`.  :func:`substitute` puts the definitions in and
evaluates the derivatives (``.doit()``).
"""

from __future__ import annotations

from collections.abc import Mapping

import sympy
from sympy.core.function import AppliedUndef

from ..errors import LagrangianError, ModelError, setting
from ..model import FunctionDeclaration, System
from ..parsing import Namespace, parse_expression

Definition = str | sympy.Lambda
Definitions = Mapping[sympy.FunctionClass, sympy.Lambda]


def function_definitions(
    system: System, definitions: Mapping[str, Definition] | None
) -> dict[sympy.FunctionClass, sympy.Lambda]:
    """Each declared function that ``definitions`` gives, as a Lambda of its arguments."""
    declared = {f.name: f for f in system.functions}
    result = {}
    for name, definition in (definitions or {}).items():
        declaration = declared.get(name)
        if declaration is None:
            known = ", ".join(declared) or "none"
            raise ModelError(
                f"'{name}' is not a declared function (declared: {known})", field="definitions"
            )
        where = f"definitions.{name}"
        if isinstance(definition, sympy.Lambda):
            result[declaration.function] = _adopted_lambda(definition, declaration, system, where)
        elif isinstance(definition, str):
            result[declaration.function] = _parsed(definition, declaration, system, where)
        else:
            raise ModelError(
                f"expected text or a sympy.Lambda, got {type(definition).__name__}", field=where
            )
    return result


def check_specified(system: System, definitions: Definitions) -> None:
    """Raise ModelError naming every function the model uses but nobody defined."""
    parts = [
        system.lagrangian,
        system.dissipation,
        *system.forces.values(),
        *system.constraints,
    ]
    used = {applied.func for part in parts for applied in part.atoms(AppliedUndef)}
    missing = [f for f in system.functions if f.function in used and f.function not in definitions]
    if missing:
        raise unspecified_error([str(f.applied) for f in missing])


def unspecified_error(names: list[str]) -> ModelError:
    """The error for functions without a definition, e.g. ``A(x, y, z)``."""
    if len(names) == 1:
        return ModelError(
            f"function {names[0]} is unspecified: give a definition ({setting('definitions=')})"
        )
    return ModelError(
        f"functions {', '.join(names)} are unspecified: give a definition of each"
        f" ({setting('definitions=')})"
    )


def substitute(expr: sympy.Expr, definitions: Definitions) -> sympy.Expr:
    """``expr`` with the defined functions put in and their derivatives evaluated."""
    if not definitions or not expr.has(*definitions):
        return expr
    for function, body in definitions.items():
        expr = expr.replace(function, body)
    return expr.doit()


def substitute_matrix(matrix: sympy.MatrixBase, definitions: Definitions) -> sympy.ImmutableMatrix:
    return sympy.ImmutableMatrix(matrix.applyfunc(lambda e: substitute(e, definitions)))


def _namespace(declaration: FunctionDeclaration, system: System) -> dict[str, sympy.Expr]:
    """Names a definition may use: the function's arguments, the parameters and t."""
    names: dict[str, sympy.Expr] = {p.name: p.symbol for p in system.parameters}
    names["t"] = system.time
    names.update({str(a): a for a in declaration.arguments})
    return names


def _checked(
    body: sympy.Expr, declaration: FunctionDeclaration, system: System, where: str, text: str
) -> sympy.Lambda:
    """Lambda(arguments, body), refused when the body depends on t but the function does not.

    The equations were derived with dA/dt = 0 for a function A(x, y, z) declared
    without t, so a definition that moves with time would make them wrong.
    """
    if body.has(system.time) and system.time not in declaration.arguments:
        raise ModelError(
            f"the definition depends on t but {declaration.applied} does not: "
            "declare t among its arguments",
            field=where,
            text=text,
        )
    return sympy.Lambda(declaration.arguments, body)


def _parsed(
    text: str, declaration: FunctionDeclaration, system: System, where: str
) -> sympy.Lambda:
    try:
        body = parse_expression(text, Namespace(_namespace(declaration, system)))
    except LagrangianError as error:
        raise ModelError(str(error), field=where, text=text) from None
    return _checked(body, declaration, system, where, text)


def _adopted_lambda(
    definition: sympy.Lambda, declaration: FunctionDeclaration, system: System, where: str
) -> sympy.Lambda:
    """The Lambda over the declared arguments, its free symbols matched to the model's by name."""
    if len(definition.variables) != len(declaration.arguments):
        raise ModelError(
            f"{declaration.applied} takes {len(declaration.arguments)} argument(s), "
            f"the Lambda {len(definition.variables)}",
            field=where,
        )
    body = definition(*declaration.arguments)
    names = _namespace(declaration, system)
    mapping = {}
    for symbol in body.free_symbols - set(declaration.arguments):
        if symbol.name not in names:
            raise ModelError(
                f"unknown symbol '{symbol.name}' (a definition may use its arguments, "
                "the parameters and t)",
                field=where,
                text=str(definition),
            )
        mapping[symbol] = names[symbol.name]
    return _checked(body.xreplace(mapping), declaration, system, where, str(definition))

"""The text of one system's y' module for the compiled DOP853 loop (:mod:`.compiled_dop853`).

The template :mod:`.numba_derivative` filled for one system: the imports of its generated
fillers (:mod:`lagrangian.codegen.numba`), of the Jacobian G of its variational (or, for
:mod:`.compiled_sensitivity`, sensitivity) equations,
or, with constraints, of its saddle-point fillers
(:mod:`lagrangian.codegen.numba_constrained`) and the projection's settings.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..codegen.cache import filled_template

if TYPE_CHECKING:
    from types import ModuleType

    from ..numeric.compiled import CompiledSystem

_TEMPLATE = Path(__file__).with_name("numba_derivative.py")


def jacobian_filler(compiled: CompiledSystem) -> ModuleType:
    """The generated ``jacobian(t, y, p, a, G)``: G = d(f - M a)/d(q, q') (n x 2n, row by
    row) with the accelerations a as an argument (see :mod:`lagrangian.numeric.dynamics`)."""
    import sympy

    from ..codegen.numba import load_functions

    forms = compiled.forms
    accelerations = tuple(sympy.Symbol(f"_a{i}") for i in range(forms.n))
    residual = sympy.Matrix(forms.forcing) - forms.mass_matrix * sympy.Matrix(accelerations)
    entries = list(residual.jacobian([*forms.coordinates, *forms.velocities]))
    return load_functions(
        forms, "tangent", [("jacobian", [("G", entries)])],
        vectors={"jacobian": ("a", accelerations)},
    )  # fmt: skip


def derivative_text(
    compiled: CompiledSystem, jacobian: str | None = None, parameters: int = 0
) -> tuple[str, str]:
    """(sha256, text) of the module of the system's y': the template with N and the
    fillers' imports (with ``jacobian``, the module of G: the variational equations, or the
    sensitivity equations whose first ``parameters`` columns are parameters)."""
    from ..codegen.numba import fillers_module

    if compiled.has_constraints:
        return constrained_text(compiled)
    fillers = fillers_module(compiled.forms)
    generated = [
        f"N = {compiled.n}",
        f"SOLVED = {compiled.n}",
        f"TANGENT = {jacobian is not None}",
        f"PARAMETERS = {parameters}",
        f"from {fillers} import eliminate, fill",
        f"from {jacobian} import jacobian" if jacobian else "jacobian = None",
        "positions = velocities = None",
        "HOLONOMIC = False",
        "PROJECTION_STEPS, STEP_TOLERANCE = 0, 0.0",
    ]
    return filled_template(_TEMPLATE, generated)


def constrained_text(compiled: CompiledSystem) -> tuple[str, str]:
    """(sha256, text) of a constrained system's y' and projection: the generated saddle-point
    fillers (:mod:`lagrangian.codegen.numba_constrained`, loaded now: the text imports them)
    and the solve for n + m, with the projection's settings of
    :mod:`lagrangian.numeric.projection`."""
    from ..codegen.numba import linear_import
    from ..codegen.numba_constrained import FILLERS, constrained_fillers
    from ..numeric.projection import MAX_ITERATIONS, STEP_TOLERANCE

    fillers = constrained_fillers(compiled.forms, compiled.baumgarte)
    augmented, positions, velocities = FILLERS
    size = compiled.n + len(compiled.constraint_names)
    generated = [
        f"N = {compiled.n}",
        f"SOLVED = {size}",
        "TANGENT = False",
        "PARAMETERS = 0",
        f"from {fillers.__name__} import {augmented} as fill, {positions}, {velocities}",
        linear_import(size),
        "jacobian = None",
        f"HOLONOMIC = {any(compiled.constraint_holonomic)}",
        f"PROJECTION_STEPS, STEP_TOLERANCE = {MAX_ITERATIONS}, {STEP_TOLERANCE!r}",
    ]
    return filled_template(_TEMPLATE, generated)

"""Code export: a model's right-hand side as a self-contained C, Julia, MATLAB, NumPy or
JavaScript file.

``lagrangian export MODEL --to c|javascript|julia|matlab|numpy [--out FILE]`` and
:func:`export_code` write, for M(q, t) q'' = f(q, q', t, u) (see
:class:`~lagrangian.derive.EquationsOfMotion`), the functions ``mass_matrix``,
``forcing`` and ``rhs`` of (t, y, params, u), y = [q, q'], with common
subexpressions computed once (:func:`sympy.cse`) and printed by SymPy's code
printers; the file names every argument entry and the default parameter
values in its header, and depends on nothing of ours.  The right-hand side is
the same as our own compiled one (:func:`~lagrangian.numeric.compile_equations`):
the same expressions, M q'' = f solved numerically (Gaussian elimination with
partial pivoting written out in C and JavaScript; ``numpy.linalg.solve``; ``\\`` in
Julia and MATLAB).  Constraints are handled with their multipliers and Baumgarte's
stabilisation, exactly as :mod:`lagrangian.numeric.dynamics` does (see
:mod:`lagrangian.codegen.program`).  The languages are the targets of
:data:`lagrangian.codegen.TARGETS` that render a file: :data:`LANGUAGES`.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from types import MappingProxyType

from ..codegen import TARGETS, AbstractTarget, Program, program
from ..codegen.forms import DEFAULT_BAUMGARTE
from ..derive import derive
from ..errors import ModelError, setting
from ..model import System

#: ``--to`` name -> target class: the targets of :data:`lagrangian.codegen.TARGETS` that
#: render a self-contained file.
LANGUAGES: Mapping[str, type[AbstractTarget]] = MappingProxyType(
    {name: target for name, target in TARGETS.items() if target.standalone}
)

#: The name a MATLAB file gets when no output file names it.
DEFAULT_NAME = "lagrangian_model"


def export_code(
    system,
    language: str,
    *,
    name: str | None = None,
    definitions: Mapping[str, str] | None = None,
    baumgarte: float = DEFAULT_BAUMGARTE,
) -> str:
    """The text of the exported file of ``system`` (a System or EquationsOfMotion).

    ``language``: a key of :data:`LANGUAGES`; ``name``: the MATLAB function's
    name (the file must be ``name.m``); ``definitions``: the model's unspecified
    functions as text (as for ``simulate --define``); ``baumgarte``: the rate
    alpha of the constraints' stabilisation.
    """
    target_class = LANGUAGES.get(language)
    if target_class is None:
        known = ", ".join(LANGUAGES)
        raise ModelError(
            f"unknown language {language!r} (languages: {known})", field=setting("language")
        )
    eom = derive(system) if isinstance(system, System) else system
    made = program(eom, definitions=definitions, baumgarte=baumgarte)
    units = _units_note(eom.system)
    if units:  # the header comment says what the numbers are in (codegen knows no units)
        made = replace(made, description="\n".join(filter(None, (made.description, units))))
    target = target_class()
    target.check()  # a package the target needs, before the work
    try:
        return target.render(made, _identifier(name or DEFAULT_NAME))
    except Exception as error:  # SymPy's printers in strict mode: no equivalent in the language
        if type(error).__name__ != "PrintMethodNotImplementedError":
            raise
        # "Unsupported by <class ...>: DiracDelta" and advice on the printer's settings
        what = str(error).splitlines()[0].rsplit(": ", 1)[-1][:100] if str(error) else "?"
        raise ModelError(
            f"cannot export to {target.language}: it has no equivalent of {what}"
        ) from None


def write_code(system, language: str, path: str | Path, **options: object) -> Path:
    """Write :func:`export_code` to ``path`` atomically (:mod:`lagrangian.files`); a MATLAB
    function is named after the file, and a name the language would misread (a Python
    module that shadows one it imports, a MATLAB keyword...) is refused."""
    from ..files import check_output_path, write_atomically

    check_output_path(path)
    target_class = LANGUAGES.get(language)
    if target_class is not None:
        target_class().check_file_name(Path(path))
    text = export_code(system, language, name=options.pop("name", None) or Path(path).stem,
                       **options)  # fmt: skip
    return write_atomically(path, lambda target: Path(target).write_text(text, encoding="utf-8"))


def _units_note(system: System) -> str | None:
    """The units of a dimensioned model's arguments, for the header: every value of y,
    params and u is in SI base units (the model converted its own when it was loaded)."""
    units = system.units
    if units is None:
        return None
    states = [*system.coordinate_names, *(f"{q}_dot" for q in system.coordinate_names)]
    named = ", ".join(f"{name} [{units.unit(name)}]" for name in (*states, *system.parameter_names))
    return f"Units (SI base units, t in s): {named}."


def _identifier(name: str) -> str:
    """``name`` as a MATLAB/Julia identifier: letters, digits, underscores, a letter first."""
    cleaned = re.sub(r"[^A-Za-z0-9_]", "_", name)
    if not cleaned or not cleaned[0].isalpha():
        cleaned = "model_" + cleaned
    return cleaned[:63]


__all__ = ["DEFAULT_NAME", "LANGUAGES", "AbstractTarget", "Program", "export_code", "write_code"]

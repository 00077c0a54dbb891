"""The compiled fixed-step loops of the numba target: one generated module per system and scheme.

:func:`numba_loop` writes the template :mod:`.numba_loop` out for one system and one
scheme (``rk4``, ``midpoint``, ``stormer-verlet``, or ``rk4-tangent``: rk4 carrying one
displacement for the ``lyapunov`` observable): the template's globals get the
system's values (``N``, ``W`` and the import of its generated fillers,
:mod:`lagrangian.codegen.numba`), the scheme's step printed from :mod:`.steps` goes
between the ``scheme`` markers, and the text is written to the code cache under a hash
of itself (:func:`~lagrangian.codegen.cache.load_text`), where numba keeps the machine
code.  The module's ``run`` is the numba ensemble's loop, its ``advance`` a stretch of
one single run: the same step in both.  Importing this module does not import numba.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from types import ModuleType

from .cache import built, load_text
from .forms import SymbolicForms
from .schemes import MATRICES, scheme_expressions, scheme_scalars
from .steps import NumbaStepPrinter, scheme_program

#: The generated fillers each scheme's loop calls (see numba_loop's globals).
_FILLERS = {
    "rk4": ("fill as mass_force",),
    "midpoint": ("momenta", "momenta_force", "mass", "jacobian"),
    "stormer-verlet": ("mass", "gradient"),
    "rk4-tangent": ("mass_force", "tangent"),
}
_SELECTED = {
    "rk4": "rk4", "midpoint": "midpoint", "stormer-verlet": "verlet", "rk4-tangent": "tangent"
}  # fmt: skip
#: Displacement entries carried with each member's state (``W`` of the template).
_CARRIED = {"rk4-tangent": 2}
_BEGIN, _END = "# -- generated: begin", "# -- generated: end"
_SCHEME_BEGIN, _SCHEME_END = "# -- scheme: begin", "# -- scheme: end"
_SELECTION = "workspace, init, step = rk4_workspace, rk4_init, rk4_step"


def numba_loop(forms: SymbolicForms, scheme: str, *, tableau, stall: float) -> ModuleType:
    """The loop module of ``forms`` (unconstrained) and ``scheme``, built once per process.

    ``tableau``: the RK4 tableau (a, b, c) printed into the rk4 step; ``stall``: the
    Newton test's STALL_RATIO (see :func:`.steps.scheme_program`)."""
    build = lambda: _loop_module(forms, scheme, tableau, stall)  # noqa: E731
    return built(forms.fingerprint, "numba-loop", build, scheme)


def scheme_fillers(forms: SymbolicForms, scheme: str) -> ModuleType:
    """The module of jitted fillers ``scheme`` calls (generated, cached on disk)."""
    from .numba import load_functions, load_module

    if scheme == "rk4":
        return load_module(forms)
    expressions = scheme_expressions(forms, scheme)
    scalars = scheme_scalars(forms.n)
    return load_functions(forms, scheme, expressions, scalars=scalars, matrices=MATRICES)


def _loop_module(forms: SymbolicForms, scheme: str, tableau, stall: float) -> ModuleType:
    fillers = scheme_fillers(forms, scheme)
    generated = [
        f"N = {forms.n}",
        f"W = {_CARRIED.get(scheme, 0) * forms.n}",
        f"from {fillers.__name__} import {', '.join(_FILLERS[scheme])}",
    ]
    program = scheme_program(scheme, forms.n, tableau=tableau, stall=stall)
    template = Path(__file__).with_name("numba_loop.py").read_text(encoding="utf-8")
    head, rest = template.split(_BEGIN, 1)
    tail = rest.split(_END, 1)[1].split("\n", 1)[1]
    before, rest = tail.split(_SCHEME_BEGIN, 1)
    after = rest.split(_SCHEME_END, 1)[1].split("\n", 1)[1]
    printed = NumbaStepPrinter(forms.n).scheme(program)
    tail = "\n".join([before.rstrip("\n"), "", "", printed, "", after.lstrip("\n")])
    chosen = _SELECTED[scheme]
    selection = f"workspace, init, step = {chosen}_workspace, {chosen}_init, {chosen}_step"
    tail = tail.replace(_SELECTION, selection)
    text = "\n".join([head.rstrip("\n"), "", *generated, "", tail])
    return load_text(hashlib.sha256(text.encode()).hexdigest(), text)

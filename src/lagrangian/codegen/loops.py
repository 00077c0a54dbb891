"""The compiled fixed-step loops of the numba target: steps per system, loops shared.

:func:`numba_loop` writes the template :mod:`.numba_loop` out for one system and one
scheme (``rk4``, ``midpoint``, ``stormer-verlet``, or ``rk4-tangent``: rk4 carrying one
displacement for the ``lyapunov`` observable, or k for the chaos indicators): the
template's globals get the import of the system's generated fillers
(:mod:`lagrangian.codegen.numba`), the scheme's step printed from :mod:`.steps` goes
between the ``scheme`` markers, and the text is written to the code cache under a hash
of itself (:func:`~lagrangian.codegen.cache.load_text`), where numba keeps the machine
code.  The loops that take the steps, ``run`` (the numba ensemble's) and ``advance`` (a
stretch of one single run), are :mod:`.numba_stepping`, written once (every scheme's
workspace has one type) and compiled once for every system and scheme: they get the
system's functions as pointers (:class:`SteppingLoop`).
Importing this module does not import numba.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from types import ModuleType

import numpy as np

from .cache import built, filled_template, load_text, package_text
from .forms import SymbolicForms
from .schemes import MATRICES, scheme_expressions, scheme_scalars
from .steps import NumbaStepPrinter, WorkspaceLayout, scheme_program, workspace_layout

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
#: Displacement entries carried with each member's state per coordinate and displacement.
_CARRIED = {"rk4-tangent": 2}
_SCHEME_BEGIN, _SCHEME_END = "# -- scheme: begin", "# -- scheme: end"
_SELECTION = "init, step = rk4_init, rk4_step"


class SteppingLoop:
    """The shared loops (:mod:`.numba_stepping`) with one system's functions of one
    scheme (its module of :mod:`.numba_loop`) and the sizes of its workspace:
    ``workspace()``, ``init(...)``, and ``run(...)`` and ``advance(...)`` with the
    arguments after the function pointers."""

    def __init__(
        self, loops: ModuleType, system: ModuleType, layout: WorkspaceLayout, carried: int
    ):
        self.loops, self.system = loops, system
        self.init = system.init
        self._sizes = (layout.size, *layout.stack)
        self._carried = carried
        self._inits = loops.inits(system.init)
        self._steppers = loops.steppers(system.step)

    def workspace(self) -> tuple:
        """The arrays the scheme keeps and works in, for one state."""
        return self.loops.workspace(*self._sizes)

    def run(self, *arguments: object, below: float = 0.0, crossings=None) -> None:
        """The ensemble's loop over members (see :mod:`.numba_stepping`); ``below`` > 0:
        SALI's first crossing of it into ``crossings``."""
        pointers = (*self._sizes, self._inits, self._steppers, self._carried)
        watched = np.empty(0) if crossings is None else crossings
        self.loops.run(*pointers, *arguments, float(below), watched)

    def advance(self, *arguments: object) -> tuple[int, int]:
        """A stretch of steps of one single run (see :mod:`.numba_stepping`)."""
        return self.loops.advance(self._steppers, *arguments)


def numba_loop(
    forms: SymbolicForms, scheme: str, *, tableau, stall: float, vectors: int = 1
) -> SteppingLoop:
    """The loops of ``forms`` (unconstrained) and ``scheme``, built once per process.

    ``tableau``: the RK4 tableau (a, b, c) printed into the rk4 step; ``stall``: the
    Newton test's STALL_RATIO; ``vectors``: the displacements ``rk4-tangent`` carries (see
    :func:`.steps.scheme_program`)."""
    build = lambda: _loop_module(forms, scheme, tableau, stall, vectors)  # noqa: E731
    return built(forms.fingerprint, "numba-loop", build, scheme, vectors)


def scheme_fillers(forms: SymbolicForms, scheme: str) -> ModuleType:
    """The module of jitted fillers ``scheme`` calls (generated, cached on disk)."""
    from .numba import load_functions, load_module

    if scheme == "rk4":
        return load_module(forms)
    expressions = scheme_expressions(forms, scheme)
    scalars = scheme_scalars(forms.n)
    return load_functions(forms, scheme, expressions, scalars=scalars, matrices=MATRICES)


def _loop_module(
    forms: SymbolicForms, scheme: str, tableau, stall: float, vectors: int
) -> SteppingLoop:
    from .numba import linear_import

    fillers = scheme_fillers(forms, scheme)
    generated = [
        f"from {fillers.__name__} import {', '.join(_FILLERS[scheme])}",
        linear_import(forms.n),
    ]
    program = scheme_program(scheme, forms.n, tableau=tableau, stall=stall, vectors=vectors)
    text = filled_template(Path(__file__).with_name("numba_loop.py"), generated)[1]
    before, rest = text.split(_SCHEME_BEGIN, 1)
    after = rest.split(_SCHEME_END, 1)[1].split("\n", 1)[1]
    printed = NumbaStepPrinter(forms.n).scheme(program)
    text = "\n".join([before.rstrip("\n"), "", "", printed, "", after.lstrip("\n")])
    chosen = _SELECTED[scheme]
    selection = f"init, step = {chosen}_init, {chosen}_step"
    text = text.replace(_SELECTION, selection)
    system = load_text(hashlib.sha256(text.encode()).hexdigest(), text)
    layout = workspace_layout(program)
    carried = _CARRIED.get(scheme, 0) * forms.n * vectors
    return SteppingLoop(stepping_module(), system, layout, carried)


def stepping_module() -> ModuleType:
    """:mod:`.numba_stepping` in the code cache: one module for every scheme and system
    (numba compiles its loops once on a machine)."""
    return load_text(*package_text(Path(__file__).with_name("numba_stepping.py")))

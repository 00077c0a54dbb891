"""The Target protocol: what turns a :class:`~lagrangian.codegen.program.Program` into code.

A target is one class.  :class:`AbstractTarget` renders the program as the text of
one file (``render``); :class:`AbstractLoadedTarget` also loads it as functions this
process calls (``load``).  Capabilities are class constants, as an integrator's are:

* ``name``: its key in :data:`lagrangian.codegen.TARGETS` (``export --to NAME``);
* ``language``: its name in words, as a generated file's header gives it;
* ``suffix``: the usual file ending (``.c``, ``.jl``);
* ``base``: the index of a first element in the language (0 or 1);
* ``standalone``: the rendered text is a self-contained file a user keeps (the export
  languages); a loaded target's text (a numba module) is only ours to run.

``check()`` raises :class:`~lagrangian.errors.MissingDependencyError` when a package
the target needs is not installed, before any work.
"""

from __future__ import annotations

import abc
from pathlib import Path
from typing import ClassVar

import sympy

from .program import Program, Routine


class AbstractTarget(abc.ABC):
    """Renders a :class:`~lagrangian.codegen.program.Program` as the text of one file."""

    name: ClassVar[str]
    language: ClassVar[str]
    suffix: ClassVar[str]
    base: ClassVar[int]
    standalone: ClassVar[bool] = True

    def check(self) -> None:  # noqa: B027 - optional, no-op by default
        """Raise :class:`~lagrangian.errors.MissingDependencyError` when a package this
        target needs is missing; text targets need none."""

    @abc.abstractmethod
    def render(self, program: Program, name: str) -> str:
        """The complete file; ``name`` names it where the language needs one (MATLAB's
        function, after the file)."""

    def check_file_name(self, path: Path) -> None:  # noqa: B027 - optional, no-op by default
        """Raise a :class:`~lagrangian.errors.ModelError` when the file cannot be called so
        (a name its language would misread); any name will do unless a target says so."""

    @staticmethod
    def used_symbols(routine: Routine) -> set[sympy.Symbol]:
        """The symbols the routine reads (so that only those are unpacked)."""
        used: set[sympy.Symbol] = set()
        for _, expr in routine.temporaries:
            used |= expr.free_symbols
        for _, matrix in routine.outputs:
            used |= matrix.free_symbols
        return used


class AbstractLoadedTarget(AbstractTarget):
    """A target whose code also runs here: ``load`` returns it as callables."""

    standalone: ClassVar[bool] = False

    @abc.abstractmethod
    def load(self, program: Program) -> object:
        """The program's routines as functions of this process (what they are, and their
        signature, is the target's to document)."""

"""`AbstractWriter`: the whole interface of a language of ``lagrangian export``."""

from __future__ import annotations

import abc
from pathlib import Path

import sympy

from .program import Routine


class AbstractWriter(abc.ABC):
    """Turns a :class:`~lagrangian.codegen.program.Program` into the text of one file.

    Class constants: ``language`` (its name in the header), ``suffix`` (the usual
    file ending), ``base`` (the index of a first element: 0 or 1).
    """

    language: str
    suffix: str
    base: int

    @abc.abstractmethod
    def render(self, program, name: str) -> str:
        """The complete file; ``name`` names it where the language needs one (MATLAB's
        function, after the file)."""

    def check_file_name(self, path: Path) -> None:  # noqa: B027 - optional, no-op by default
        """Raise a :class:`~lagrangian.errors.ModelError` when the file cannot be called so
        (a name its language would misread); any name will do unless a writer says so."""

    @abc.abstractmethod
    def expression(self, expr: sympy.Expr) -> str:
        """One expression in the language, by SymPy's code printer for it."""

    @staticmethod
    def used_symbols(routine: Routine) -> set[sympy.Symbol]:
        """The symbols the routine reads (so that only those are unpacked)."""
        used: set[sympy.Symbol] = set()
        for _, expr in routine.temporaries:
            used |= expr.free_symbols
        for _, matrix in routine.outputs:
            used |= matrix.free_symbols
        return used

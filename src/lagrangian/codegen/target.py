"""The Target protocol: what turns a :class:`~lagrangian.codegen.program.Program` into code.

A target is one class.  :class:`AbstractTarget` renders the program as the text of
one file (``render``); :class:`AbstractLoadedTarget` also loads it as functions this
process calls (``load``).  Capabilities are class constants, as an integrator's are,
given in the class statement (``class JuliaTarget(AbstractTarget, name="julia",
language="Julia", suffix=".jl", base=1)``):

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

#: The outputs of a routine that are vectors (f, the constraint bias b); the others are
#: matrices.
VECTORS = frozenset({"f", "b"})


class AbstractTarget(abc.ABC):
    """Renders a :class:`~lagrangian.codegen.program.Program` as the text of one file."""

    name: ClassVar[str]
    language: ClassVar[str]
    suffix: ClassVar[str]
    base: ClassVar[int]
    standalone: ClassVar[bool] = True
    #: How an argument's entry reads (MATLAB indexes with parentheses).
    element: ClassVar[str] = "{argument}[{index}]"

    def __init_subclass__(cls, **constants: object) -> None:
        """The class constants given in the class statement:
        ``class JuliaTarget(AbstractTarget, name="julia", language="Julia", ...)``."""
        unknown = set(constants) - {"name", "language", "suffix", "base", "standalone"}
        if unknown:
            raise TypeError(f"{cls.__name__}: unknown class constants {sorted(unknown)}")
        super().__init_subclass__()
        for key, value in constants.items():
            setattr(cls, key, value)

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

    def reads(self, program: Program, routine: Routine) -> list[tuple[sympy.Symbol, str, int]]:
        """(symbol, argument, index) of each argument entry the routine reads, so that only
        those are unpacked: the state ``"y"``, ``"params"``, the inputs ``"u"``; indices
        counted from :attr:`base`."""
        used = self.used_symbols(routine)
        arguments = (
            ("y", (*program.coordinates, *program.velocities)),
            ("params", program.parameters),
            ("u", program.inputs),
        )
        return [
            (quantity.symbol, argument, index + self.base)
            for argument, quantities in arguments
            for index, quantity in enumerate(quantities)
            if quantity.symbol in used
        ]

    def opening(
        self, program: Program, routine: Routine, statement: str, *, no_input: str = "{value}"
    ) -> list[str]:
        """The statements that open a routine's body: each argument entry it reads, then its
        common subexpressions, each ``statement.format(symbol=..., value=...)`` (as
        ``"    {symbol} = {value}"``).  An entry of the inputs reads
        ``no_input.format(value=...)``: what the language makes of it when no inputs were
        given (0)."""
        lines = []
        for symbol, argument, index in self.reads(program, routine):
            value = self.element.format(argument=argument, index=index)
            if argument == "u":
                value = no_input.format(value=value)
            lines.append(statement.format(symbol=symbol, value=value))
        for symbol, expr in routine.temporaries:
            lines.append(statement.format(symbol=symbol, value=self.expression(expr)))
        return lines

    def expression(self, expr: sympy.Expr) -> str:
        """One expression in the language (text targets print with SymPy's printer for it)."""
        raise NotImplementedError(f"target {self.name!r} prints no single expressions")

    def list_literal(self, matrix: sympy.MatrixBase, *, vector: bool) -> str:
        """``[e0, e1, ...]`` (a vector) or ``[[row 0], [row 1], ...]``: the list syntax
        Python and JavaScript share."""
        if vector:
            return "[" + ", ".join(self.expression(entry) for entry in matrix) + "]"
        rows = (self.list_literal(matrix.row(i), vector=True) for i in range(matrix.rows))
        return "[" + ", ".join(rows) + "]"

    def literal_outputs(self, routine: Routine, statement: str) -> tuple[list[str], list[str]]:
        """The statements that give each output of a routine its value as a list literal
        (:meth:`list_literal`), each ``statement.format(label=..., value=..., shape=...)``
        (``shape``: ``(n,)`` or ``(n, n)``), and the outputs' labels in order."""
        lines = []
        for label, matrix in routine.outputs:
            vector = label in VECTORS
            shape = f"({matrix.rows},)" if vector else str(matrix.shape)
            value = self.list_literal(matrix, vector=vector)
            lines.append(statement.format(label=label, value=value, shape=shape))
        return lines, [label for label, _ in routine.outputs]

    def entries(self, matrix: sympy.MatrixBase, *, vector: bool) -> list[tuple[str, str]]:
        """(index, expression) of each entry, indices counted from :attr:`base`: ``"i"``
        in a vector, ``"i, j"`` in a matrix (for languages that fill arrays entry by entry)."""
        if vector:
            return [(f"{i + self.base}", self.expression(e)) for i, e in enumerate(matrix)]
        return [
            (f"{i + self.base}, {j + self.base}", self.expression(matrix[i, j]))
            for i in range(matrix.rows)
            for j in range(matrix.cols)
        ]

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

"""A function of :mod:`lagrangian.codegen.steps` run over arrays: the NumPy and JAX target.

The printed languages (C, numba, JavaScript) get the text of a function; the array
libraries get its statements walked here, each entry of a matrix or vector an array
over a batch (of states, of ensemble members): one operation per node on the whole
batch, so the walk's cost is paid once per call, not per element, and under
``jax.jit`` only once, when the function is traced.  ``If`` holds where its
condition does: the assignments inside it take effect element by element (``where``),
so nothing depends on the values in Python.  Loops run over Python integers (their
bounds are compile-time lengths), which unrolls them, as in the C text.

:func:`solve` is the linear solve of the NumPy and JAX backends for small n:
:func:`lagrangian.codegen.steps.elimination` walked over the entries.
"""

from __future__ import annotations

import functools
from typing import Any

from .steps import (
    Abs,
    Assign,
    Binary,
    Choose,
    Expr,
    Function,
    If,
    Index,
    Loop,
    Name,
    Number,
    Return,
    elimination,
)

_OPERATORS = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: a / b,
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
    "==": lambda a, b: a == b,
    "!=": lambda a, b: a != b,
}


class _Returned(Exception):
    def __init__(self, value):
        self.value = value


class ArrayRun:
    """One walk of a function's statements over array values (see the module);
    ``xp`` is ``numpy`` or ``jax.numpy``."""

    def __init__(self, xp, values: dict[str, Any]):
        self.xp = xp
        self.values = values

    def run(self, function: Function) -> Any:
        try:
            self.block(function.body, None)
        except _Returned as returned:
            return returned.value
        return None

    # -- statements -------------------------------------------------------------------
    def block(self, statements: list, mask) -> None:
        declared: set[str] = set()
        for statement in statements:
            self.statement(statement, mask, declared)

    def statement(self, node, mask, declared: set[str]) -> None:
        if isinstance(node, Assign):
            self.assign(node, mask, declared)
        elif isinstance(node, Loop):
            for index in range(self.bound(node.start), self.bound(node.stop)):
                self.values[node.index] = index
                self.block(node.body, mask)
        elif isinstance(node, If):
            condition = self.expression(node.condition)
            if isinstance(condition, bool):  # a test of Python numbers: decided now
                if condition:
                    self.block(node.then, mask)
            else:
                both = condition if mask is None else self.xp.logical_and(mask, condition)
                self.block(node.then, both)
        elif isinstance(node, Return):
            raise _Returned(self.expression(node.value if isinstance(node.value, Expr)
                                            else Number(node.value)))  # fmt: skip
        else:
            raise TypeError(f"not a statement of an array function: {node!r}")

    def assign(self, node: Assign, mask, declared: set[str]) -> None:
        value = self.expression(node.value)
        target = node.target
        if isinstance(target, Name):
            if node.kind is not None:
                declared.add(target.name)
            elif mask is not None and target.name not in declared:
                value = self.xp.where(mask, value, self.values[target.name])
            self.values[target.name] = value
            return
        container, last = self._slot(target)
        if mask is not None:
            value = self.xp.where(mask, value, container[last])
        container[last] = value

    def _slot(self, node: Index) -> tuple[list, int]:
        """The list holding an entry and its index there (matrices: lists of rows)."""
        container = self.expression(node.array)
        indices = [self.expression(index) for index in node.indices]
        for index in indices[:-1]:
            container = container[index]
        return container, indices[-1]

    def bound(self, value) -> int:
        return value if isinstance(value, int) else int(self.expression(value))

    # -- expressions ------------------------------------------------------------------
    def expression(self, node: Expr):
        if isinstance(node, Name):
            return self.values[node.name]
        if isinstance(node, Number):
            return node.value
        if isinstance(node, Binary):
            left, right = self.expression(node.left), self.expression(node.right)
            if node.operator in ("and", "or"):
                if isinstance(left, bool) and isinstance(right, bool):
                    return (left and right) if node.operator == "and" else (left or right)
                logical = self.xp.logical_and if node.operator == "and" else self.xp.logical_or
                return logical(left, right)
            return _OPERATORS[node.operator](left, right)
        if isinstance(node, Abs):
            return abs(self.expression(node.operand))
        if isinstance(node, Choose):
            condition = self.expression(node.condition)
            if isinstance(condition, bool):
                return self.expression(node.then if condition else node.otherwise)
            then, otherwise = self.expression(node.then), self.expression(node.otherwise)
            return self.xp.where(condition, then, otherwise)
        if isinstance(node, Index):
            container, last = self._slot(node)
            return container[last]
        raise TypeError(f"not an expression node: {node!r}")


@functools.cache
def _elimination(n: int, pivoting: bool = True) -> Function:
    return elimination(n, pivoting=pivoting)


def eliminated(matrix: list, force: list) -> list:
    """x with matrix x = force (lists of expressions: heyoka's; both overwritten), by the
    elimination without pivoting (expressions cannot be compared)."""
    n = len(force)
    x: list[Any] = [None] * n
    values = {"a": matrix, "b": force, "x": x, "offset": 0}
    ArrayRun(None, values).run(_elimination(n, pivoting=False))
    return x


def solve(xp, matrix, rhs):
    """(x, singular) with ``matrix x = rhs`` for every batch element: ``matrix``
    (*batch, n, n) and ``rhs`` (*batch, n) arrays of ``xp``; ``singular`` per element
    (a pivot 0 or not finite: x is then inf or NaN there)."""
    n = rhs.shape[-1]
    a = [[matrix[..., i, j] for j in range(n)] for i in range(n)]
    b = [rhs[..., i] for i in range(n)]
    x: list[Any] = [None] * n
    values = {"a": a, "b": b, "x": x, "offset": 0}
    singular = ArrayRun(xp, values).run(_elimination(n))
    return xp.stack(x, axis=-1), singular

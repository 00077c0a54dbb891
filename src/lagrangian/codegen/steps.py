"""The fixed-step schemes and the linear solve written once, as a small program, printed.

Each scheme (rk4, midpoint, Stormer-Verlet) is a :class:`Scheme`: the arrays it keeps
from step to step, the scratch arrays it works in, and two bodies of statements,
``init(t, y, p)`` (the kept state at the first step) and
``step(t, h, y, p, tol, floor, iterations)`` (y, of length 2n, advanced by h in place;
it returns 0, or 1 / 2 where the Newton iteration for the midpoint velocity / for the
velocity from the momenta did not converge).  The statements call the generated
fillers of :mod:`lagrangian.codegen.schemes` (``mass_force``, ``momenta``,
``momenta_force``, ``mass``, ``jacobian``, ``gradient``) and the one linear solve,
:func:`elimination` (a :class:`Function`: Gaussian elimination with partial pivoting).
The printers turn them into text:

- :class:`CStepPrinter`: the ``lg_state`` struct and the ``__device__`` functions
  ``lg_init`` and ``lg_step`` of the CUDA kernel (:mod:`lagrangian.ensemble.cuda_source`),
  and the solve (:func:`lagrangian.codegen.c.gaussian_elimination`, ``lg_solve``);
- :class:`NumbaStepPrinter`: ``eliminate``, ``<scheme>_init`` and ``<scheme>_step`` (their
  workspace laid out by :func:`workspace_layout`) for the numba loops
  (:mod:`lagrangian.codegen.numba_loop`: the ensemble's and the single run's), counting
  evaluations;
- the JavaScript target's printer of the solve
  (:class:`lagrangian.codegen.javascript.JavaScriptStepPrinter`).

NumPy and JAX walk the solve over arrays instead (:mod:`lagrangian.codegen.arrays`).

The arithmetic is the numpy backend's, operation for operation (the tree of each
expression is printed with its parentheses, so both languages evaluate it in the same
order): the RK4 tableau, and :class:`~lagrangian.integrate.variational.Variational`'s
Newton iterations with their first guess and convergence test.  The expressions are
a few node classes with Python operators (``y[i] + h * k[i]``); loops run over
compile-time lengths (unrolled in C) except the Newton iterations.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

# -- expressions ---------------------------------------------------------------------------


def _operator(symbol: str, reflected: bool = False):
    """The method of one of Python's binary operators, building a :class:`Binary` node."""

    def method(self, other):
        left, right = (wrap(other), self) if reflected else (self, wrap(other))
        return Binary(symbol, left, right)

    return method


class Expr:
    """An expression node; Python's arithmetic and comparison operators build more."""

    __add__, __radd__ = _operator("+"), _operator("+", reflected=True)
    __sub__, __rsub__ = _operator("-"), _operator("-", reflected=True)
    __mul__, __rmul__ = _operator("*"), _operator("*", reflected=True)
    __truediv__, __rtruediv__ = _operator("/"), _operator("/", reflected=True)
    __lt__, __le__ = _operator("<"), _operator("<=")
    __gt__, __ge__ = _operator(">"), _operator(">=")

    def equals(self, other) -> Binary:
        return Binary("==", self, wrap(other))

    def differs(self, other) -> Binary:
        return Binary("!=", self, wrap(other))

    def __getitem__(self, index):
        if isinstance(index, tuple):
            return Index(self, tuple(wrap(i) for i in index))
        return Index(self, (wrap(index),))


@dataclass(frozen=True, eq=False)
class Name(Expr):
    name: str


@dataclass(frozen=True, eq=False)
class Number(Expr):
    value: float | int


@dataclass(frozen=True, eq=False)
class Binary(Expr):
    operator: str  # + - * / < <= > >= == != and or
    left: Expr
    right: Expr


@dataclass(frozen=True, eq=False)
class Abs(Expr):
    operand: Expr


@dataclass(frozen=True, eq=False)
class Choose(Expr):
    """``then`` where ``condition`` holds, else ``otherwise`` (only one is evaluated)."""

    condition: Expr
    then: Expr
    otherwise: Expr


@dataclass(frozen=True, eq=False)
class Index(Expr):
    """An entry of an array; two indices address a row-major matrix."""

    array: Expr
    indices: tuple[Expr, ...]


def wrap(value) -> Expr:
    return value if isinstance(value, Expr) else Number(value)


def both(a: Expr, b: Expr) -> Expr:
    return Binary("and", a, b)


def either(a: Expr, b: Expr) -> Expr:
    return Binary("or", a, b)


def larger(a: Expr, b: Expr) -> Expr:
    """max(a, b) that keeps a NaN, as numpy's max does, so a NaN never converges."""
    return Choose(either(b > a, b.differs(b)), b, a)


INFINITY = Number(math.inf)


# -- statements --------------------------------------------------------------------------


@dataclass(frozen=True)
class Assign:
    """``target = value``; with ``kind`` (``real`` or ``int``), the first assignment of a
    scalar (a declaration in C)."""

    target: Expr
    value: Expr
    kind: str | None = None


@dataclass(frozen=True)
class Loop:
    """``for index in range(start, stop)``; unrolled in C when ``stop`` is a number."""

    index: str
    stop: Expr | int
    body: list
    start: Expr | int = 0


@dataclass(frozen=True)
class If:
    condition: Expr
    then: list


@dataclass(frozen=True)
class Break:
    pass


@dataclass(frozen=True)
class Return:
    value: Expr | int


@dataclass(frozen=True)
class Call:
    """A generated filler ``function(arguments..., outputs...)``."""

    function: str
    arguments: tuple[Expr, ...]


@dataclass(frozen=True)
class Solve:
    """``out[offset:offset + n]`` = x with ``matrix`` x = ``rhs`` (both overwritten)."""

    matrix: Expr
    rhs: Expr
    out: Expr
    offset: int = 0


@dataclass(frozen=True)
class Count:
    """One more of ``counts[slot]`` (evaluations, for the single run's statistics)."""

    slot: int


@dataclass(frozen=True)
class Function:
    """A function ``name(arguments) -> int`` of arrays: (name, ``matrix`` | ``vector``)
    (n x n row-major, n) and integers (name, ``int``)."""

    name: str
    arguments: tuple[tuple[str, str], ...]
    body: list


@dataclass(frozen=True)
class Scheme:
    """One fixed-step scheme (see the module): arrays (name, shape) and two bodies."""

    name: str
    kept: tuple[tuple[str, tuple[int, ...]], ...]
    scratch: tuple[tuple[str, tuple[int, ...]], ...]
    init: list
    step: list


# -- the linear solve ----------------------------------------------------------------------


def elimination(n: int, name: str = "eliminate", *, pivoting: bool = True) -> Function:
    """``name(a, b, x, offset)``: x[offset:offset + n] with a x = b, by Gaussian elimination
    with partial pivoting; the one linear solve of every printed language.

    ``a`` (n x n) and ``b`` are overwritten; ``x`` may be ``b`` (offset 0).  It returns 1
    where a pivot is 0 or not finite (a singular ``a``; x is then inf or NaN), else 0.
    Rows are swapped by value while scanning for the pivot (the first largest), so every
    index is a compile-time constant once the loops are unrolled (C) and the arrays stay
    in registers; each pivot is inverted once, into the diagonal (n divisions instead of
    n(n+1)/2: a float64 division is a dozen dependent instructions on a GPU).  About
    n^3/3 multiply-adds (G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed.,
    algorithm 3.4.1).  Without ``pivoting`` (entries that are expressions, not numbers:
    heyoka's) rows are neither compared nor swapped, and nothing is flagged.
    """
    a, b, x, offset = Name("a"), Name("b"), Name("x"), Name("offset")
    k, row = Name("k"), Name("row")
    swap, pivot, factor, total, singular = (
        Name(s) for s in ("swap", "pivot", "factor", "total", "singular")
    )
    exchange = [
        Loop("j", n, [Assign(swap, a[k, j], "real"), Assign(a[k, j], a[i, j]),
                      Assign(a[i, j], swap)]),
        Assign(swap, b[k], "real"),
        Assign(b[k], b[i]),
        Assign(b[i], swap),
    ]  # fmt: skip
    body = [
        Assign(singular, Number(0), "int"),
        Loop("k", n, [
            *([Loop("i", n, [If(Abs(a[i, k]) > Abs(a[k, k]), exchange)], start=k + 1)]
              if pivoting else []),
            Assign(pivot, a[k, k], "real"),
            *([If(either(Abs(pivot).equals(0.0), (pivot - pivot).differs(0.0)),  # 0, NaN, inf
                  [Assign(singular, Number(1))])] if pivoting else []),
            Assign(a[k, k], 1.0 / pivot),
            Loop("i", n, [
                Assign(factor, a[i, k] * a[k, k], "real"),
                Loop("j", n, [Assign(a[i, j], a[i, j] - factor * a[k, j])], start=k + 1),
                Assign(b[i], b[i] - factor * b[k]),
            ], start=k + 1),
        ]),
        Loop("k", n, [  # back substitution, row = n - 1 - k
            Assign(row, (n - 1) - k, "int"),
            Assign(total, b[row], "real"),
            Loop("j", n, [Assign(total, total - a[row, j] * x[offset + j])], start=row + 1),
            Assign(x[offset + row], total * a[row, row]),
        ]),
        Return(singular),
    ]  # fmt: skip
    arguments = (("a", "matrix"), ("b", "vector"), ("x", "vector"), ("offset", "int"))
    return Function(name, arguments, body)


# -- the schemes ---------------------------------------------------------------------------

t, h, y, p = Name("t"), Name("h"), Name("y"), Name("p")
tol, floor, iterations = Name("tol"), Name("floor"), Name("iterations")
i, j = Name("i"), Name("j")


def rk4(n: int, a, b, c) -> Scheme:
    """RK4 with the tableau (a, b, c) (:data:`lagrangian.integrate.tableaus.RK4`); M q'' = f
    solved at each stage."""
    matrix, force = Name("matrix"), Name("force")

    def derivative(time: Expr, state: Expr, out: Expr) -> list:
        return [
            Call("mass_force", (time, state, p, matrix, force)),
            Count(0),
            Solve(matrix, force, out, n),
            Loop("i", n, [Assign(out[i], state[n + i])]),
        ]

    return _runge_kutta("rk4", 2 * n, derivative, (a, b, c), (("matrix", (n, n)), ("force", (n,))))


def rk4_tangent(n: int, a, b, c, vectors: int = 1) -> Scheme:
    """RK4 of the state with ``vectors`` displacements, z = [y, w_1, ..., w_k] (2n (k + 1)):
    y' = [q', M^-1 f] and each w' = [w_q', M^-1 D w] (D from the filler ``tangent``,
    :mod:`lagrangian.codegen.schemes`), the numpy backend's
    :class:`~lagrangian.integrate.lyapunov.TangentFlow` (one displacement, the ``lyapunov``
    observable) or :class:`~lagrangian.integrate.indicators.TangentFlows` (k, the chaos
    indicators) stepped by the same tableau."""
    matrix, force, held, slopes, pushed = (
        Name(s) for s in ("matrix", "force", "held", "slopes", "pushed")
    )
    m = 2 * n

    def displaced(state: Expr, out: Expr, base: int, last: bool) -> list:
        # the solve overwrites its matrix: M is kept in ``held`` for the last displacement
        # and copied into ``matrix`` (free after the state's solve) for the others
        solved = held if last else matrix
        copy = [] if last else [Loop("i", n, [Loop("j", n, [Assign(matrix[i, j], held[i, j])])])]
        return [
            *copy,
            Loop("i", n, [
                Assign(pushed[i], Number(0.0)),
                Loop("j", m, [
                    Assign(pushed[i], pushed[i] + slopes[i * m + j] * state[base + j])
                ]),
            ]),
            Solve(solved, pushed, out, base + n),
            Loop("i", n, [Assign(out[base + i], state[base + n + i])]),
        ]  # fmt: skip

    def derivative(time: Expr, state: Expr, out: Expr) -> list:
        body = [
            Call("mass_force", (time, state, p, matrix, force)),
            Count(0),
            Loop("i", n, [Loop("j", n, [Assign(held[i, j], matrix[i, j])])]),
            Solve(matrix, force, out, n),
            Loop("i", n, [Assign(out[i], state[n + i])]),
            Call("tangent", (time, state, p, *(out[n + k] for k in range(n)), slopes)),
            Count(1),
        ]
        for v in range(vectors):
            body += displaced(state, out, m * (v + 1), v == vectors - 1)
        return body

    arrays = (("matrix", (n, n)), ("held", (n, n)), ("force", (n,)), ("pushed", (n,)),
              ("slopes", (2 * n * n,)))  # fmt: skip
    return _runge_kutta("tangent", m * (vectors + 1), derivative, (a, b, c), arrays)


def _runge_kutta(name: str, m: int, derivative, tableau, arrays) -> Scheme:
    """The RK4 step of a state of length m whose slope ``derivative(time, state, out)``
    writes into ``out``; ``arrays``: the scratch arrays ``derivative`` works in."""
    a, b, c = tableau
    k1, k2, k3, k4, stage = (Name(s) for s in ("k1", "k2", "k3", "k4", "stage"))

    def stage_from(k: Expr, coefficient: float) -> Loop:
        return Loop("i", m, [Assign(stage[i], y[i] + (h * float(coefficient)) * k[i])])

    b1, b2, b3, b4 = (float(value) for value in b)

    def weighted(k1: Expr, k2: Expr, k3: Expr, k4: Expr) -> Expr:
        return b1 * k1[i] + b2 * k2[i] + b3 * k3[i] + b4 * k4[i]

    step = [
        *derivative(t, y, k1),
        stage_from(k1, a[1, 0]),
        *derivative(t + float(c[1]) * h, stage, k2),
        stage_from(k2, a[2, 1]),
        *derivative(t + float(c[2]) * h, stage, k3),
        stage_from(k3, a[3, 2]),
        *derivative(t + float(c[3]) * h, stage, k4),
        Loop("i", m, [Assign(y[i], y[i] + h * (weighted(k1, k2, k3, k4)))]),
        Return(0),
    ]
    scratch = (*((s, (m,)) for s in ("k1", "k2", "k3", "k4", "stage")), *arrays)
    return Scheme(name, (), scratch, [], step)


def _raise(target: Name, value: Expr, temporary: str) -> list:
    """target = larger(target, value), value computed once (into ``temporary``)."""
    held = Name(temporary)
    return [Assign(held, value, "real"), Assign(target, larger(target, held))]


def _extent(n: int, state: Expr, kind: str | None = "real") -> list:
    """reach = max(1, max |q|) (variational._extent)."""
    reach = Name("reach")
    return [
        Assign(reach, Number(1.0), kind),
        Loop("i", n, _raise(reach, Abs(state[i]), "entry")),
    ]


def _newton_test(n: int, residual_of, target: Expr, now: Expr, stall: float) -> tuple[list, Expr]:
    """The residual, its size and scale (statements) and variational._converged (expression)."""
    size, scale, previous, reach = Name("size"), Name("scale"), Name("previous"), Name("reach")
    measure = [
        Assign(size, Number(0.0), "real"),
        Assign(scale, Number(0.0), "real"),
        Loop("i", n, [
            Assign(Name("residual")[i], residual_of(i)),
            *_raise(size, Abs(Name("residual")[i]), "entry"),
            Assign(Name("wanted"), Abs(target[i]), "real"),
            *_raise(Name("wanted"), Abs(now[i]), "reached"),
            Assign(scale, larger(scale, Name("wanted"))),
        ]),
    ]  # fmt: skip
    small = either(size <= tol * scale, size.equals(0.0))
    stalled = both(size >= stall * previous, size <= floor * scale * reach)
    return measure, either(small, stalled)


def midpoint(n: int, stall: float) -> Scheme:
    """Variational._midpoint for one state: Newton on the midpoint velocity v (first guess
    2 q'_k - v_{k-1}, or q'_k at the first step), p_{k+1} and q_{k+1}, then the velocity
    from L_q'(q, q') = p_{k+1} by Newton with M, from v."""
    kept, last, started = Name("kept"), Name("last"), Name("started")
    v, z, now, force = Name("v"), Name("z"), Name("momenta_now"), Name("force")
    residual, change, matrix = Name("residual"), Name("change"), Name("matrix")
    tm, previous, iteration = Name("tm"), Name("previous"), Name("iteration")
    first_guess = Choose(started[0].differs(0), 2 * y[n + i] - last[i], y[n + i])
    measure, converged = _newton_test(
        n, lambda k: now[k] - (h / 2) * force[k] - kept[k], kept, now, stall
    )
    velocity_measure, velocity_converged = _newton_test(
        n, lambda k: now[k] - kept[k], kept, now, stall
    )
    step = [
        Assign(tm, t + h / 2, "real"),
        Loop("i", n, [Assign(v[i], first_guess)]),
        Assign(previous, INFINITY, "real"),
        *_extent(n, y),
        Loop("iteration", iterations + 1, [
            Loop("i", n, [Assign(z[i], y[i] + (h / 2) * v[i]), Assign(z[n + i], v[i])]),
            Call("momenta_force", (tm, z, p, now, force)),
            Count(0),
            *measure,
            If(converged, [Break()]),
            If(iteration.equals(iterations), [Return(1)]),
            Assign(previous, Name("size")),
            Call("jacobian", (tm, z, p, h, matrix)),
            Count(1),
            Count(2),
            Solve(matrix, residual, change),
            Loop("i", n, [Assign(v[i], v[i] - change[i])]),
        ]),
        Loop("i", n, [
            Assign(kept[i], kept[i] + h * force[i]),
            Assign(y[i], y[i] + h * v[i]),
            Assign(last[i], v[i]),
            Assign(z[i], y[i]),
            Assign(z[n + i], v[i]),
        ]),
        Assign(started[0], Number(1.0)),
        # the velocity from the momenta: L_q'(q, q') = p_{k+1} by Newton with M, from v
        Assign(previous, INFINITY),
        *_extent(n, y, None),
        Loop("iteration", iterations + 1, [
            Call("momenta", (t + h, z, p, now)),
            Count(0),
            *velocity_measure,
            If(velocity_converged, [Loop("i", n, [Assign(y[n + i], z[n + i])]), Return(0)]),
            If(iteration.equals(iterations), [Return(2)]),
            Assign(previous, Name("size")),
            Call("mass", (t + h, z, p, matrix)),
            Count(1),
            Solve(matrix, residual, change),
            Loop("i", n, [Assign(z[n + i], z[n + i] - change[i])]),
        ]),
        Return(2),
    ]  # fmt: skip
    init = [Call("momenta", (t, y, p, kept)), Count(0), Assign(started[0], Number(0.0))]
    vectors = ("v", "momenta_now", "force", "residual", "change")
    scratch = (("z", (2 * n,)), *((s, (n,)) for s in vectors), ("matrix", (n, n)))
    return Scheme("midpoint", (("kept", (n,)), ("last", (n,)), ("started", (1,))), scratch,
                  init, step)  # fmt: skip


def stormer_verlet(n: int) -> Scheme:
    """Variational's Stormer-Verlet (separable systems: M constant): M^-1 once, then the
    kick-drift-kick of the momenta with the force L_q."""
    kept, force, inverse = Name("kept"), Name("force"), Name("inverse")
    half, z, unit = Name("half"), Name("z"), Name("unit")
    matrix, copy = Name("matrix"), Name("copy")
    total, k = Name("total"), Name("k")

    def apply(left: Expr, x, offset: int, out, out_offset: int) -> Loop:
        """out = left x (left: n x n)."""
        return Loop("i", n, [
            Assign(total, Number(0.0), "real"),
            Loop("j", n, [Assign(total, total + left[i, j] * x[offset + j if offset else j])]),
            Assign(out[out_offset + i if out_offset else i], total),
        ])  # fmt: skip

    init = [
        Call("mass", (t, y, p, matrix)),
        Loop("j", n, [  # the inverse column by column
            Loop("i", n, [
                Assign(unit[i], Choose(i.equals(j), Number(1.0), Number(0.0))),
                Loop("k", n, [Assign(copy[i, k], matrix[i, k])]),
            ]),
            Solve(copy, unit, z),
            Loop("i", n, [Assign(inverse[i, j], z[i])]),
        ]),
        apply(matrix, y, n, kept, 0),
        Call("gradient", (t, y, p, force)),
        Count(0),
    ]  # fmt: skip
    step = [
        Loop("i", n, [Assign(half[i], kept[i] + (h / 2) * force[i])]),
        apply(inverse, half, 0, z, n),
        Loop("i", n, [Assign(z[i], y[i] + h * z[n + i])]),
        Call("gradient", (t + h, z, p, force)),
        Count(0),
        Loop("i", n, [Assign(kept[i], half[i] + (h / 2) * force[i]), Assign(y[i], z[i])]),
        apply(inverse, kept, 0, y, n),
        Return(0),
    ]
    kept_arrays = (("kept", (n,)), ("force", (n,)), ("inverse", (n, n)))
    scratch = (("half", (n,)), ("z", (2 * n,)), ("matrix", (n, n)), ("copy", (n, n)),
               ("unit", (n,)))  # fmt: skip
    return Scheme("verlet", kept_arrays, scratch, init, step)


# -- printers ------------------------------------------------------------------------------


class StepPrinter:
    """What the C and Python printers share: statements walked with indentation."""

    indent = "    "
    end = ""  # of a statement
    prefix = ""  # of the generated fillers' names
    counting = False  # whether Count statements are printed

    def __init__(self, n: int):
        self.n = n

    def block(self, statements: list, depth: int) -> list[str]:
        lines: list[str] = []
        for statement in statements:
            lines += self.statement(statement, depth)
        return lines

    def statement(self, node, depth: int) -> list[str]:
        pad = self.indent * depth
        if isinstance(node, Count):
            return self.count(node, pad) if self.counting else []
        method = getattr(self, f"_{type(node).__name__.lower()}")
        return method(node, depth, pad)

    def number(self, value) -> str:
        raise NotImplementedError

    def expression(self, node: Expr) -> str:
        if isinstance(node, Name):
            return self.name(node.name)
        if isinstance(node, Number):
            return self.number(node.value)
        if isinstance(node, Binary):
            operator = self.operators.get(node.operator, node.operator)
            return f"({self.expression(node.left)} {operator} {self.expression(node.right)})"
        if isinstance(node, Abs):
            return f"{self.absolute}({self.expression(node.operand)})"
        if isinstance(node, Choose):
            return self.choose(*(self.expression(e) for e in (node.condition, node.then,
                                                              node.otherwise)))  # fmt: skip
        if isinstance(node, Index):
            return self.index(node)
        raise TypeError(f"not an expression node: {node!r}")

    def name(self, name: str) -> str:
        return name

    def _break(self, node, depth: int, pad: str) -> list[str]:
        return [f"{pad}break{self.end}"]

    def _return(self, node: Return, depth: int, pad: str) -> list[str]:
        return [f"{pad}return {self.top(self.expression(wrap(node.value)))}{self.end}"]

    def bound(self, value: Expr | int) -> str:
        """A loop's start or stop."""
        return str(value) if isinstance(value, int) else self.top(self.expression(value))

    def _call(self, node: Call, depth: int, pad: str) -> list[str]:
        arguments = ", ".join(self.top(self.expression(e)) for e in node.arguments)
        return [f"{pad}{self.prefix}{node.function}({arguments}){self.end}"]

    def top(self, text: str) -> str:
        """``text`` without the outer parentheses of a binary operation."""
        return text[1:-1] if text.startswith("(") and _balanced(text[1:-1]) else text


def _balanced(text: str) -> bool:
    depth = 0
    for character in text:
        depth += {"(": 1, ")": -1}.get(character, 0)
        if depth < 0:
            return False
    return depth == 0


_C_NAMES = {"floor": "rounding_floor", "tol": "newton_tol"}


class CStepPrinter(StepPrinter):
    """The scheme as CUDA C (see the module): ``lg_state``, ``lg_init``, ``lg_step``."""

    operators: ClassVar[dict[str, str]] = {"and": "&&", "or": "||"}
    end, prefix = ";", "lg_"

    def __init__(self, n: int, printer, real_type: str = "real", *, unroll: bool = True):
        super().__init__(n)
        self.printer = printer  # a lagrangian.codegen.c.CPrinter: literals, fabs
        self.real_type = real_type
        self.unroll = unroll  # loops of a constant length carry #pragma unroll
        self.absolute = printer.fabs
        self.kept: set[str] = set()

    def number(self, value) -> str:
        if isinstance(value, int):
            return str(value)
        if math.isinf(value):
            return self.printer._print_Infinity(None)
        return self.printer.literal(value)

    def name(self, name: str) -> str:
        # floor: the parameter of the Newton test, not C's function
        return f"state->{name}" if name in self.kept else _C_NAMES.get(name, name)

    def choose(self, condition: str, then: str, otherwise: str) -> str:
        return f"({condition} ? {then} : {otherwise})"

    def index(self, node: Index) -> str:
        array = self.expression(node.array)
        if len(node.indices) == 1:
            return f"{array}[{self.top(self.expression(node.indices[0]))}]"
        row, column = (self.expression(e) for e in node.indices)
        return f"{array}[{row} * {self.n} + {column}]"

    def _assign(self, node: Assign, depth: int, pad: str) -> list[str]:
        kind = {"real": f"{self.real_type} ", "int": "int ", None: ""}[node.kind]
        target, value = self.expression(node.target), self.top(self.expression(node.value))
        return [f"{pad}{kind}{target} = {value};"]

    def _loop(self, node: Loop, depth: int, pad: str) -> list[str]:
        start, stop, index = self.bound(node.start), self.bound(node.stop), node.index
        head = [f"{pad}#pragma unroll"] if isinstance(node.stop, int) and self.unroll else []
        head.append(f"{pad}for (int {index} = {start}; {index} < {stop}; ++{index}) {{")
        return [*head, *self.block(node.body, depth + 1), f"{pad}}}"]

    def _if(self, node: If, depth: int, pad: str) -> list[str]:
        head = f"{pad}if ({self.top(self.expression(node.condition))}) {{"
        return [head, *self.block(node.then, depth + 1), f"{pad}}}"]

    def _solve(self, node: Solve, depth: int, pad: str) -> list[str]:
        matrix, rhs, out = (self.expression(e) for e in (node.matrix, node.rhs, node.out))
        return [f"{pad}lg_solve({matrix}, {rhs}, {out}, {node.offset});"]

    def function(self, function: Function, qualifiers: str = "static") -> str:
        """``int name(real *a, ..., int offset)`` with ``function``'s body."""
        types = {"matrix": f"{self.real_type} *", "vector": f"{self.real_type} *", "int": "int "}
        arguments = ", ".join(f"{types[kind]}{name}" for name, kind in function.arguments)
        head = f"{qualifiers} int {function.name}({arguments})".strip()
        return "\n".join([head, "{", *self.block(function.body, 1), "}", ""])

    def scheme(self, scheme: Scheme) -> str:
        """The struct of the kept arrays and the two functions."""
        self.kept = {name for name, _ in scheme.kept}
        members = [f"{self.real_type} {name}[{math.prod(shape)}];" for name, shape in scheme.kept]
        struct = f"typedef struct {{ {' '.join(members) or 'int unused;'} }} lg_state;"
        qualifiers = "__device__ __forceinline__"
        real = self.real_type
        init_body = self.block(scheme.init, 1) or ["    (void)state; (void)t; (void)y; (void)p;"]
        init = [
            f"{qualifiers} void lg_init(lg_state *state, {real} t, const {real} *y, "
            f"const {real} *p)",
            "{",
            *self._scratch(scheme, init_body),
            *init_body,
            "}",
        ]
        step_body = self.block(scheme.step, 1)
        step = [
            f"{qualifiers} int lg_step(lg_state *state, {real} t, {real} h, {real} *y, "
            f"const {real} *p,",
            f"    {real} newton_tol, {real} rounding_floor, int iterations)",
            "{",
            *self._scratch(scheme, step_body),
            *step_body,
            "}",
        ]
        return "\n".join([struct, "", *init, "", *step, ""])

    def _scratch(self, scheme: Scheme, body: list[str]) -> list[str]:
        """The declarations of the scratch arrays ``body`` uses (in registers once unrolled)."""
        text = "\n".join(body)
        return [
            f"    {self.real_type} {name}[{math.prod(shape)}];"
            for name, shape in scheme.scratch
            if re.search(rf"\b{name}\b", text)
        ]


#: numba's decorator of every function of the package's numba modules that allocates
#: nothing: compiled on its own, not inlined, and without numba's reference counting (NRT;
#: ``_nrt=False``, a flag of numba's ``jit`` since 0.19).  Such calls were inlined
#: (``inline="always"``) because a call that passes arrays costs two atomic operations per
#: array; but numba inlines by copying the callee's IR to every call site, recursively, and
#: that took most of the compile time.  First runs (CPU s, benchmarks/README.md): Lyapunov
#: spectrum of Henon-Heiles 29.6 -> 11.7, its ensemble 48.3 -> 13.4, the flip-time ensemble
#: 23.4 -> 10.4; runs: the double pendulum's spectrum 1.11 -> 0.91 s, the ensembles' steps
#: 13-29% slower (one call a step, where the inlined step had none).
LEAN = "@njit(cache=True, _nrt=False)"


@dataclass(frozen=True)
class WorkspaceLayout:
    """Where a scheme's arrays lie in the numba workspace, which has one type for every
    scheme (so the loops that take the steps, :mod:`lagrangian.codegen.numba_stepping`, are
    compiled once): ``(vectors, matrices)``, one buffer of ``size`` entries holding every
    vector one after the other, and a stack of shape ``stack`` holding the matrices.
    ``places``: each array's name -> its slice of ``vectors`` or its index in ``matrices``."""

    size: int
    stack: tuple[int, int, int]
    places: dict[str, slice | int]

    def allocated(self) -> tuple:
        """A workspace ``(vectors, matrices)`` made by NumPy (the numba loops make theirs
        with the same sizes)."""
        return np.empty(self.size), np.empty(self.stack)

    def views(self, work: tuple) -> dict:
        """Name -> the array, in a workspace ``(vectors, matrices)``."""
        vectors, matrices = work
        return {
            name: vectors[place] if isinstance(place, slice) else matrices[place]
            for name, place in self.places.items()
        }

    def unpacked(self, indent: str) -> list[str]:
        """The lines that name the arrays of ``work`` in the printed functions."""
        lines = [f"{indent}vectors, matrices = work"]
        for name, place in self.places.items():
            where = (f"vectors[{place.start}:{place.stop}]" if isinstance(place, slice)
                     else f"matrices[{place}]")  # fmt: skip
            lines.append(f"{indent}{name} = {where}")
        return lines


def workspace_layout(scheme: Scheme) -> WorkspaceLayout:
    """The :class:`WorkspaceLayout` of ``scheme``'s kept and scratch arrays."""
    places: dict[str, slice | int] = {}
    size, shapes = 0, []
    for name, shape in [*scheme.kept, *scheme.scratch]:
        if len(shape) == 1:
            places[name] = slice(size, size + shape[0])
            size += shape[0]
        else:
            places[name] = len(shapes)
            shapes.append(tuple(shape))
    if len(set(shapes)) > 1:
        raise ValueError(f"the {scheme.name} scheme's matrices differ in shape: {set(shapes)}")
    rows, columns = shapes[0] if shapes else (0, 0)
    return WorkspaceLayout(size, (len(shapes), rows, columns), places)


class NumbaStepPrinter(StepPrinter):
    """The scheme as numba Python (see the module): ``<name>_init`` and ``_step``, which
    take a last argument ``counts`` (3 integers: the evaluations of the right-hand side or
    of L_q' and L_q + Q, of the Jacobians, and the Newton updates)."""

    operators: ClassVar[dict[str, str]] = {}
    absolute = "abs"
    counting = True

    def number(self, value) -> str:
        if isinstance(value, int):
            return str(value)
        if math.isinf(value):
            return "math.inf" if value > 0 else "-math.inf"
        return repr(float(value))

    def choose(self, condition: str, then: str, otherwise: str) -> str:
        return f"({then} if {condition} else {otherwise})"

    def index(self, node: Index) -> str:
        indices = ", ".join(self.top(self.expression(e)) for e in node.indices)
        return f"{self.expression(node.array)}[{indices}]"

    def count(self, node: Count, pad: str) -> list[str]:
        return [f"{pad}counts[{node.slot}] += 1"]

    def _assign(self, node: Assign, depth: int, pad: str) -> list[str]:
        target, value = self.expression(node.target), self.top(self.expression(node.value))
        return [f"{pad}{target} = {value}"]

    def _loop(self, node: Loop, depth: int, pad: str) -> list[str]:
        stop = self.bound(node.stop)
        bounds = f"{self.bound(node.start)}, {stop}" if node.start != 0 else stop
        body = self.block(node.body, depth + 1) or [f"{pad}{self.indent}pass"]
        return [f"{pad}for {node.index} in range({bounds}):", *body]

    def _if(self, node: If, depth: int, pad: str) -> list[str]:
        head = f"{pad}if {self.top(self.expression(node.condition))}:"
        return [head, *self.block(node.then, depth + 1)]

    def _solve(self, node: Solve, depth: int, pad: str) -> list[str]:
        matrix, rhs, out = (self.expression(e) for e in (node.matrix, node.rhs, node.out))
        return [f"{pad}eliminate({matrix}, {rhs}, {out}, {node.offset})"]

    def function(self, function: Function) -> str:
        """The module-level numba function (:data:`LEAN`, cached on disk)."""
        arguments = ", ".join(name for name, _ in function.arguments)
        cover = "  # pragma: no cover - compiled by numba"
        return "\n".join([
            LEAN,
            f"def {function.name}({arguments}):{cover}",
            *self.block(function.body, 1),
            "",
        ])  # fmt: skip

    def scheme(self, scheme: Scheme) -> str:
        """The two module-level functions (numba, cached on disk)."""
        name = scheme.name
        layout = workspace_layout(scheme)
        unpack = layout.unpacked("    ")
        cover = "  # pragma: no cover - compiled by numba"
        return "\n".join([
            "@njit(cache=True)",
            f"def {name}_init(t, y, p, work, counts):{cover}",
            *unpack,
            *(self.block(scheme.init, 1) or ["    pass"]),
            "",
            "",
            LEAN,
            f"def {name}_step(t, h, y, p, work, tol, floor, iterations, counts):{cover}",
            *unpack,
            *self.block(scheme.step, 1),
            "",
        ])  # fmt: skip


def scheme_program(
    method: str, n: int, *, tableau=None, stall: float = 0.5, vectors: int = 1
) -> Scheme:
    """The :class:`Scheme` of ``method`` (``rk4``, ``midpoint``, ``stormer-verlet``,
    ``rk4-tangent``) for n coordinates; ``tableau``: the RK4 tableau (a, b, c); ``stall``:
    the Newton test's STALL_RATIO; ``vectors``: the displacements rk4-tangent carries."""
    if method == "rk4":
        return rk4(n, tableau.a, tableau.b, tableau.c)
    if method == "midpoint":
        return midpoint(n, stall)
    if method == "stormer-verlet":
        return stormer_verlet(n)
    if method == "rk4-tangent":
        return rk4_tangent(n, tableau.a, tableau.b, tableau.c, vectors)
    raise ValueError(f"no fixed-step scheme {method!r}")

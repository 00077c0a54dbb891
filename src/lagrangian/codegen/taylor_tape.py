"""y' = F(t, y, p) decomposed into elementary operations, for Taylor's method.

Taylor's method needs the Taylor coefficients of the solution at a point to high order;
automatic differentiation gives them from recurrences, one per elementary operation
(R. Moore, *Interval Analysis*, 1966; A. Jorba and M. Zou, "A software package for the
numerical integration of ODEs by means of high-order Taylor methods", Experimental
Mathematics 14 (2005) 99-117).  This module turns the explicit ODE of a program,

    q' = q',  q'' = M^{-1} f   (M and f of M q'' = f, declared functions in)

into a :class:`Tape`: a list of operations, each producing one *series* (a function of
time whose Taylor coefficients are computed order by order) from earlier ones, and a
list of *constants* (numbers, parameters and every operation on them alone), computed
once per run.  M^{-1} f is written out by the one Gaussian elimination of the
project (:func:`lagrangian.codegen.arrays.eliminated`, without pivoting, as for heyoka:
why that is sound where M is definite is in :mod:`lagrangian.integrate.taylor`),
walked over :class:`Node` values that record each operation as they go.  Equal
operations on equal operands are recorded once (common subexpressions), as are
sin and cos of one argument (one recurrence gives both) and sinh and cosh.

The operations (``Op.kind``): ``add``, ``sub``, ``mul``, ``div`` of two series or a
series and a constant, ``neg``, ``square``, ``sqrt``, ``pow`` (a constant real
exponent), ``exp``, ``log``, ``sincos``, ``sinhcosh``.  Integer powers are products and
quotients; tan and tanh are quotients of the pairs.  Any other function is refused
with a :class:`~lagrangian.errors.ModelError` naming it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy

from ..errors import ModelError
from .arrays import eliminated
from .forms import SymbolicForms

#: The functions the tape differentiates, by SymPy's name (for the refusal's list).
SUPPORTED = ("sin", "cos", "tan", "exp", "log", "sqrt", "sinh", "cosh", "tanh", "powers")


class UnsupportedFunction(ModelError):
    """A function the tape has no Taylor recurrence for: names it and where it is."""

    def __init__(self, function: str, where: str):
        self.function = function
        super().__init__(
            f"method 'taylor' (numba) cannot differentiate {function} (in {where}): its "
            f"Taylor recurrences cover {', '.join(SUPPORTED)}; use backend 'heyoka' or dop853"
        )


@dataclass(frozen=True)
class Op:
    """One series: ``kind`` applied to ``args`` (each ("s", row) a series or ("c", j) a
    constant); ``rows`` the series it writes (two for the sincos and sinhcosh pairs);
    ``exponent`` for ``pow``."""

    kind: str
    args: tuple[tuple[str, int], ...]
    rows: tuple[int, ...]
    exponent: float = 0.0


@dataclass(frozen=True)
class Constant:
    """One constant: a ``number``, parameter ``p[index]``, or ``kind`` of earlier constants
    (``args``, indices into the constants) with ``exponent`` for ``pow``."""

    kind: str
    args: tuple[int, ...] = ()
    number: float = 0.0
    index: int = 0


@dataclass
class Tape:
    """The decomposed ODE: series rows 0..size-1 are the state y (their coefficients are
    the method's unknowns), row ``size`` is time where ``uses_time``, the rest are
    ``ops`` in order; ``rates[i]`` is y_i' (a series row or a constant index)."""

    size: int
    parameters: int
    ops: list[Op] = field(default_factory=list)
    constants: list[Constant] = field(default_factory=list)
    rates: list[tuple[str, int]] = field(default_factory=list)
    uses_time: bool = False
    _seen: dict = field(default_factory=dict, repr=False)
    _made: dict = field(default_factory=dict, repr=False)

    @property
    def rows(self) -> int:
        """Series rows in all: the state, time, and every operation's."""
        return self.size + 1 + sum(len(op.rows) for op in self.ops)

    def constant(self, entry: Constant) -> Node:
        key = ("c", entry)
        if key not in self._seen:
            self.constants.append(entry)
            self._seen[key] = Node(self, "c", len(self.constants) - 1)
        return self._seen[key]

    def number(self, value: float) -> Node:
        return self.constant(Constant("number", number=float(value)))

    @property
    def one(self) -> int:
        """The index of the constant 1."""
        return self.number(1.0).index

    def node(self, arg: tuple[str, int]) -> Node:
        """The node of an operand (``where``, index)."""
        if arg[0] == "c":
            return Node(self, "c", arg[1])
        return Node(self, "s", arg[1])

    def made(self, node: Node) -> Op | None:
        """The operation that made the series ``node`` (None for the state, time and
        constants)."""
        if node.where != "s":
            return None
        return self._made.get(node.index)

    def series(self, kind: str, args: tuple[Node, ...], exponent: float = 0.0) -> Node:
        """The node of ``kind`` of ``args``, recorded unless it was (its first row for a pair;
        :meth:`partner` gives the second)."""
        if all(arg.where == "c" for arg in args):
            return self._folded(kind, args, exponent)
        key = (kind, tuple((a.where, a.index) for a in args), exponent)
        if key not in self._seen:
            width = 2 if kind in ("sincos", "sinhcosh") else 1
            start = self.rows
            rows = tuple(range(start, start + width))
            self.ops.append(Op(kind, key[1], rows, exponent))
            self._made[start] = self.ops[-1]
            self._seen[key] = Node(self, "s", start)
        return self._seen[key]

    def _folded(self, kind: str, args: tuple[Node, ...], exponent: float) -> Node:
        values = [self.constants[a.index] for a in args]
        if all(value.kind == "number" for value in values):
            number = _evaluate(kind, [value.number for value in values], exponent)
            if number is not None:
                return self.number(number)
        return self.constant(Constant(kind, tuple(a.index for a in args), exponent))


def _evaluate(kind: str, values: list[float], exponent: float) -> float | None:
    """The number ``kind`` gives, where it is exact arithmetic on numbers (else None:
    kept as a constant computed at run time, with the run's floating point)."""
    if kind == "add":
        return values[0] + values[1]
    if kind == "sub":
        return values[0] - values[1]
    if kind == "mul":
        return values[0] * values[1]
    if kind == "neg":
        return -values[0]
    return None


@dataclass(frozen=True, eq=False)
class Node:
    """A value of the tape, series (``where`` "s", a row) or constant ("c", an index), with
    the arithmetic the elimination applies to it (numbers become constants)."""

    tape: Tape
    where: str
    index: int

    def _node(self, other) -> Node:
        return other if isinstance(other, Node) else self.tape.number(other)

    def _value(self) -> float | None:
        if self.where != "c":
            return None
        entry = self.tape.constants[self.index]
        return entry.number if entry.kind == "number" else None

    def __add__(self, other) -> Node:
        other = self._node(other)
        if other._value() == 0.0:
            return self
        if self._value() == 0.0:
            return other
        return self.tape.series("add", (self, other))

    __radd__ = __add__

    def __sub__(self, other) -> Node:
        other = self._node(other)
        if other._value() == 0.0:
            return self
        if self._value() == 0.0:
            return -other
        return self.tape.series("sub", (self, other))

    def __rsub__(self, other) -> Node:
        return self._node(other) - self

    def __mul__(self, other) -> Node:
        other = self._node(other)
        for a, b in ((self, other), (other, self)):
            if a._value() == 0.0:
                return a
            if a._value() == 1.0:
                return b
            if a._value() == -1.0:
                return -b
        tape = self.tape
        for a, b in ((self, other), (other, self)):
            made = tape.made(a)
            if made is not None and made.kind == "div" and made.args[0] == ("c", tape.one):
                return tape.series("div", (b, tape.node(made.args[1])))  # b / x, not b * (1/x)
            if b.where == "s" and made is not None and made.kind == "mul":
                scale, factor = sorted(made.args)  # a constant sorts first: ("c", j)
                if scale[0] == "c" and factor == (b.where, b.index):  # (c x) x = c x^2:
                    return tape.node(scale) * tape.series("square", (b,))  # half a product
        if (self.where, self.index) == (other.where, other.index):
            return tape.series("square", (self,))
        return tape.series("mul", (self, other))

    __rmul__ = __mul__

    def __truediv__(self, other) -> Node:
        other = self._node(other)
        if other._value() == 1.0:
            return self
        if self._value() == 0.0:
            return self
        if other.where == "c" and self.where == "s":  # one reciprocal per run, then products
            return self * self.tape.series("div", (self.tape.number(1.0), other))
        return self.tape.series("div", (self, other))

    def __rtruediv__(self, other) -> Node:
        return self._node(other) / self

    def __neg__(self) -> Node:
        return self.tape.series("neg", (self,))


def tape_of(forms: SymbolicForms) -> Tape:
    """The tape of y' = [q', M^{-1} f] of ``forms`` (see the module docstring)."""
    n = forms.n
    tape = Tape(size=2 * n, parameters=len(forms.parameters))
    symbols: dict[sympy.Symbol, Node] = {}
    for i, (q, v) in enumerate(zip(forms.coordinates, forms.velocities, strict=True)):
        symbols[q] = Node(tape, "s", i)
        symbols[v] = Node(tape, "s", n + i)
    symbols[forms.time] = Node(tape, "s", 2 * n)
    for j, symbol in enumerate(forms.parameters):
        symbols[symbol] = tape.constant(Constant("parameter", index=j))
    convert = _Converter(tape, symbols)
    mass = [[convert(forms.mass_matrix[i, j]) for j in range(n)] for i in range(n)]
    force = [convert(forms.forcing[i, 0]) for i in range(n)]
    accelerations = eliminated(mass, force)
    rates = [symbols[v] for v in forms.velocities] + list(accelerations)
    tape.rates = [(node.where, node.index) for node in rates]
    live = _live(tape)
    tape.uses_time = any(("s", 2 * n) in op.args for op in live)
    tape.uses_time |= ("s", 2 * n) in tape.rates
    return _renumbered(tape, live)


def _live(tape: Tape) -> list[Op]:
    """The operations the rates need (a reciprocal folded into a quotient is not)."""
    needed = {row for kind, row in tape.rates if kind == "s"}
    live = []
    for op in reversed(tape.ops):
        if needed.intersection(op.rows):
            live.append(op)
            needed.update(row for kind, row in op.args if kind == "s")
    return live[::-1]


def _renumbered(tape: Tape, live: list[Op]) -> Tape:
    """``tape`` with only the ``live`` operations, their rows numbered anew in order."""
    rows = {row: row for row in range(tape.size + 1)}
    ops = []
    for op in live:
        start = tape.size + 1 + sum(len(kept.rows) for kept in ops)
        rows.update({old: start + i for i, old in enumerate(op.rows)})
        args = tuple((kind, rows[row] if kind == "s" else row) for kind, row in op.args)
        ops.append(Op(op.kind, args, tuple(start + i for i in range(len(op.rows))), op.exponent))
    renamed = [(kind, rows[row] if kind == "s" else row) for kind, row in tape.rates]
    return Tape(tape.size, tape.parameters, ops, tape.constants, renamed, tape.uses_time)


class _Converter:
    """SymPy expression -> :class:`Node`, each subexpression once."""

    def __init__(self, tape: Tape, symbols: dict[sympy.Symbol, Node]):
        self.tape = tape
        self.memo: dict[sympy.Expr, Node] = dict(symbols)

    def __call__(self, expression: sympy.Expr) -> Node:
        found = self.memo.get(expression)
        if found is None:
            found = self.memo[expression] = self._convert(expression)
        return found

    def _convert(self, e: sympy.Expr) -> Node:
        tape = self.tape
        if e.is_Number:
            if not e.is_finite:
                raise ModelError(f"method 'taylor' (numba) cannot use the number {e}")
            return tape.number(float(e))
        if e.is_NumberSymbol:  # pi, E
            return tape.number(float(e))
        if e.is_Symbol:
            raise ModelError(f"method 'taylor' (numba): the symbol {e} has no value")
        if e.is_Add:  # a - b as one subtraction, not a negation and a sum
            signed = [_signed(arg) for arg in e.args]
            signed.sort(key=lambda pair: pair[0])  # a positive term first, where there is one
            total = None
            for negative, term in signed:
                if total is None:  # its sign kept: -c*x is one product with the constant -c
                    total = self(-term) if negative else self(term)
                    continue
                node = self(term)
                total = total - node if negative else total + node
            return total
        if e.is_Mul:
            return self._product(e.args)
        if e.is_Pow:
            return self._power(e.base, e.exp)
        return self._function(e)

    def _product(self, factors) -> Node:
        numerator: list[Node] = []
        denominator: list[Node] = []
        for factor in factors:  # x/y is x*y**-1 in SymPy: divide once, not multiply 1/y
            base, exponent = factor.as_base_exp()
            if exponent.is_Number and exponent.is_negative and not factor.is_Number:
                denominator.append(self._power(base, -exponent))
            else:
                numerator.append(self(factor))
        top = _product_of(numerator) if numerator else self.tape.number(1.0)
        return top / _product_of(denominator) if denominator else top

    def _power(self, base: sympy.Expr, exponent: sympy.Expr) -> Node:
        u = self(base)
        if not exponent.is_Number:  # u**e = exp(e log u)
            return self.tape.series("exp", (self(exponent) * self.tape.series("log", (u,)),))
        if exponent.is_Integer:
            k = int(exponent)
            if k < 0:
                return 1.0 / self._power(base, -exponent)
            if k == 0:
                return self.tape.number(1.0)
            return _integer_power(u, k)
        if exponent == sympy.Rational(1, 2):
            return self.tape.series("sqrt", (u,))
        if exponent == sympy.Rational(-1, 2):
            return 1.0 / self.tape.series("sqrt", (u,))
        return self.tape.series("pow", (u,), float(exponent))

    def _function(self, e: sympy.Expr) -> Node:
        name = type(e).__name__
        if name in ("sin", "cos", "tan", "sinh", "cosh", "tanh", "exp", "log") and len(e.args) == 1:
            u = self(e.args[0])
            if name == "exp":
                return self.tape.series("exp", (u,))
            if name == "log":
                return self.tape.series("log", (u,))
            pair = "sincos" if name in ("sin", "cos", "tan") else "sinhcosh"
            first, second = self._pair(pair, u)
            if name in ("sin", "sinh"):
                return first
            if name in ("cos", "cosh"):
                return second
            return first / second
        raise UnsupportedFunction(name, _short(e))

    def _pair(self, kind: str, u: Node) -> tuple[Node, Node]:
        if u.where == "c":  # a constant argument: two constants
            first = "sin" if kind == "sincos" else "sinh"
            second = "cos" if kind == "sincos" else "cosh"
            tape = self.tape
            return (
                tape.constant(Constant(first, (u.index,))),
                tape.constant(Constant(second, (u.index,))),
            )
        node = self.tape.series(kind, (u,))
        return node, Node(self.tape, "s", node.index + 1)


def _signed(term: sympy.Expr) -> tuple[bool, sympy.Expr]:
    """(whether ``term`` is a negative number times the rest, the term without that sign)."""
    coefficient, _ = term.as_coeff_Mul()
    if coefficient.is_negative:
        return True, -term
    return False, term


def _product_of(nodes: list[Node]) -> Node:
    # constants first: their product is one constant, and then one multiplication of series
    nodes = sorted(nodes, key=lambda node: node.where != "c")
    total = nodes[0]
    for node in nodes[1:]:
        total = total * node
    return total


def _integer_power(u: Node, k: int) -> Node:
    """u**k by squaring (u**2 one square, u**3 a square and a product)."""
    result = None
    square = u
    while k:
        if k & 1:
            result = square if result is None else result * square
        k >>= 1
        if k:
            square = square * square
    return result


def _short(expression: sympy.Expr) -> str:
    text = str(expression)
    return text if len(text) <= 60 else text[:57] + "..."

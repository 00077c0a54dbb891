"""The dimension check of a dimensioned model: every term of every expression, once.

Each expression field is read as the user wrote it (its syntax tree, :mod:`..parsing`),
and each term is held to what the field is: every term of T, V and L an energy, a
particle's position a length, a mass a mass, an inertia mass*length^2, a spring's
stiffness a force per length and its rest length a length, gravity an acceleration, a
generalized force on q an energy per unit of q (a force on a length, a torque on an
angle), the Rayleigh function a power; the terms of a constraint (and of any sum) all
alike; the arguments of sin, cos, exp, log, ... dimensionless.

The names whose units the model does not give (a coordinate, a parameter without a
unit) are unknowns: each requirement is a linear equation on the exponents of their
dimensions (:mod:`.dimension_solver`), and the check solves them as it goes.  A
requirement between known dimensions that fails, or one that contradicts those before
it, is one ModelError naming the field, the term as written, its dimension and the one
expected::

    potential: the term k*x is a force (N), the other terms are energies (J)

and a name still undetermined at the end is one error naming every such name.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction

from ..errors import ModelError, ParseError
from ..parsing import BUILTIN_CONSTANTS, syntax_tree, token_ends
from ..parsing.nodes import Call, Name, Negate, Node, Number, Power, Product, Sum
from ..symbols import ACCELERATION_SUFFIX, TIME_NAME, VELOCITY_SUFFIX
from .dimension_solver import Form, Solver, combine, known, scale, unknown
from .dimensions import (
    ACCELERATION,
    DIMENSIONLESS,
    ENERGY,
    INERTIA,
    LENGTH,
    MASS,
    POWER,
    STIFFNESS,
    TIME,
    Dimension,
    describe,
)
from .spec import ModelSpec, expression_fields

#: What each field is, by its name (the first pattern that matches).
_FIELD_DIMENSIONS = tuple(
    (re.compile(pattern), value)
    for pattern, value in (
        (r"lagrangian|kinetic|potential", ENERGY),
        (r"dissipation", POWER),
        (r"(particles|bodies)\[\d+\]\.mass", MASS),
        (r"particles\[\d+\]\.position\[\d+\]", LENGTH),
        (r"bodies\[\d+\]\.(center|position)\[\d+\]", LENGTH),
        (r"bodies\[\d+\]\.inertia(\[\d+\])*", INERTIA),
        (r"bodies\[\d+\]\.(angle|orientation\..*)", DIMENSIONLESS),
        (r"springs\[\d+\]\.stiffness", STIFFNESS),
        (r"springs\[\d+\]\.(rest_length|ends.*)", LENGTH),
        (r"gravity\.g", ACCELERATION),
        (r"impacts\[\d+\]\.restitution", DIMENSIONLESS),
    )
)
#: A generalized force: the coordinate it acts on is the last part of the field.
_GENERALIZED_FORCE = re.compile(r"(forces|conservative_forces|inputs\.\w+)\.(\w+)")
_DIMENSIONLESS_ARGUMENTS = frozenset(
    {"sin", "cos", "tan", "cot", "sec", "csc", "asin", "acos", "atan", "sinh", "cosh",
     "tanh", "exp", "log"}
)  # fmt: skip
_OPENERS, _CLOSERS = "([{", ")]}"
#: A velocity's dimension is its coordinate's per time, an acceleration's per time squared.
_DERIVATIVES = (
    (ACCELERATION_SUFFIX, known(tuple(-2 * x for x in TIME))),
    (VELOCITY_SUFFIX, known(tuple(-x for x in TIME))),
)


@dataclass(frozen=True)
class Names:
    """The names of a model by kind, and the dimensions its units give (``known``)."""

    coordinates: tuple[str, ...]
    parameters: tuple[str, ...]
    functions: tuple[str, ...]
    known: Mapping[str, Dimension]


@dataclass(frozen=True)
class _Requirement:
    """``term`` must have the dimension of ``expected``: where, and how to say it."""

    term: Form
    expected: Form
    field: str
    text: str
    node: Node
    what: str  # "term", "argument of sin", ...: "the argument x of sin" names it
    others: int  # how many other terms share the expectation (0: a fixed one)
    torque: bool  # the expectation is a generalized force (an energy is a torque there)


def check_dimensions(
    spec: ModelSpec, names: Names, trees: Mapping[str, Node] | None = None
) -> dict[str, Dimension]:
    """The dimension of every coordinate, parameter and function of ``spec``: the known
    ones, and the others as its expressions fix them.  ModelError for a term of the
    wrong dimension (naming it), or for names the model leaves undetermined.  ``trees``:
    the syntax trees of the texts, where the build kept them (not parsed again)."""
    check = _Check(names, trees or {})
    for field, value, _ in expression_fields(spec):
        check.field(field, value)
    for requirement in check.pending:
        if not check.solver.add(combine(requirement.term, requirement.expected, -1)):
            check.refuse(requirement)
    found, undetermined = {}, []
    for name in (*names.coordinates, *names.parameters, *names.functions):
        value = names.known.get(name) or check.solver.value(unknown(name))
        if value is None:
            undetermined.append(name)
        else:
            found[name] = value
    if undetermined:
        shown = ", ".join(undetermined)
        raise ModelError(
            f"the units of {shown} are not determined by the model: give "
            f"{'it' if len(undetermined) == 1 else 'them'} in [units] or with the value",
            field="units",
        )
    return found


class _Check:
    def __init__(self, names: Names, trees: Mapping[str, Node]):
        self.names = names
        self.trees = trees
        self.coordinates = frozenset(names.coordinates)
        self.functions = frozenset(names.functions)
        self.solver = Solver()
        self.pending: list[_Requirement] = []
        self.seen: set[tuple] = set()

    # -- fields --------------------------------------------------------------
    def field(self, field: str, value: object) -> None:
        text = value if isinstance(value, str) else str(value)
        try:
            tree = self.trees.get(text) or syntax_tree(text)
        except ParseError as error:  # parsed when the model was built: only SymPy's str()
            raise ModelError(f"cannot check its units: {error}", field=field) from None
        self.text, self.where = text, field
        terms = _terms(tree)
        expected, torque = self._expected(field)
        if expected is None:
            self.alike(terms, "term")
            return
        for node in terms:
            term = self.form(node)
            if term is not None:
                self.require(_Requirement(term, expected, field, text, node, "term",
                                          len(terms) - 1, torque))  # fmt: skip

    def _expected(self, field: str) -> tuple[Form | None, bool]:
        for pattern, value in _FIELD_DIMENSIONS:
            if pattern.fullmatch(field):
                return known(value), False
        match = _GENERALIZED_FORCE.fullmatch(field)
        if match is not None:
            return combine(known(ENERGY), self.name(match[2]), -1), True
        return None, False

    # -- requirements ----------------------------------------------------------
    def require(self, requirement: _Requirement) -> None:
        """Check at once between known dimensions; otherwise solve with the others, later
        (so that the known ones are refused first, whatever the order of the fields)."""
        if requirement.term[0] or requirement.expected[0]:
            key = (*_key(requirement.term), *_key(requirement.expected))
            if key not in self.seen:  # a chain's sin(theta1) is in every later position
                self.seen.add(key)
                self.pending.append(requirement)
        elif requirement.term[1] != requirement.expected[1]:
            self.refuse(requirement)

    def refuse(self, requirement: _Requirement) -> None:
        term = self.solver.value(requirement.term)
        expected = self.solver.value(requirement.expected)
        written = _written(requirement.node, requirement.text)
        if term is None or expected is None:
            message = (f"the {_named(requirement.what, written)} has no dimension that fits the "
                       f"{'other terms' if requirement.others else 'field'}")  # fmt: skip
            raise ModelError(message, field=requirement.field)
        torque = requirement.torque and expected == ENERGY  # the force on an angle
        one = "a torque (N*m)" if torque else describe(expected)
        kind = requirement.what.partition(" of ")[0]  # term, argument
        if requirement.others > 1:
            many = "torques (N*m)" if torque else describe(expected, plural=True)
            wanted = f"the other {kind}s are {many}"
        elif requirement.others == 1:
            wanted = f"the other {kind} is {one}"
        else:
            wanted = f"expected {one}"
        angular = self._angle_rate(requirement.node)
        raise ModelError(
            f"the {_named(requirement.what, written)} is {describe(term, angular=angular)}, "
            f"{wanted}",
            field=requirement.field,
        )

    def _angle_rate(self, node: Node) -> bool:
        """Whether ``node`` is (minus) the velocity of an angle, a coordinate without
        dimension: its 1/s is said as rad/s."""
        while isinstance(node, Negate):
            node = node.operand
        if not isinstance(node, Name):
            return False
        base = node.name.removesuffix(VELOCITY_SUFFIX)
        return (
            base != node.name
            and base in self.coordinates
            and self.solver.value(self.name(base)) == DIMENSIONLESS
        )

    def alike(self, nodes: list[Node], what: str) -> Form | None:
        """Every node of ``nodes`` (the terms of a sum) of one dimension: that of the first
        term whose dimension the most terms share, so that the odd one out is named."""
        forms = [(node, self.form(node)) for node in nodes]
        forms = [(node, form) for node, form in forms if form is not None]
        if not forms:
            return None
        counts: dict[Dimension, int] = {}
        for _, form in forms:
            if not form[0]:
                counts[form[1]] = counts.get(form[1], 0) + 1
        majority = max(counts, key=counts.get) if counts else None
        anchor = next((f for _, f in forms if not f[0] and f[1] == majority), forms[0][1])
        for node, form in forms:
            if form is not anchor:
                self.require(_Requirement(form, anchor, self.where, self.text, node, what,
                                          len(forms) - 1, False))  # fmt: skip
        return anchor

    def dimensionless(self, node: Node, what: str) -> None:
        form = self.form(node)
        if form is not None:
            requirement = _Requirement(form, known(DIMENSIONLESS), self.where, self.text,
                                       node, what, 0, False)  # fmt: skip
            self.require(requirement)

    # -- the walk --------------------------------------------------------------
    def name(self, name: str) -> Form:
        """The form of a name: t, a constant, a coordinate or its derivatives, a
        parameter, a function written bare."""
        if name == TIME_NAME:
            return known(TIME)
        if name in BUILTIN_CONSTANTS:
            return known(DIMENSIONLESS)
        for suffix, per_time in _DERIVATIVES:
            base = name.removesuffix(suffix)
            if base != name and base in self.coordinates:
                return combine(self.name(base), per_time)
        if name in self.names.known:
            return known(self.names.known[name])
        return unknown(name)

    def form(self, node: Node) -> Form | None:
        """The dimension of ``node`` as a :data:`Form`; None for 0 (of any dimension)."""
        match node:
            case Number(value=value):
                return None if value == 0 else known(DIMENSIONLESS)
            case Name(name=name):
                return self.name(name)
            case Negate(operand=operand):
                return self.form(operand)
            case Sum(terms=operands):
                return self.alike([operand.node for operand in operands], "term")
            case Product(factors=operands):
                result: Form | None = known(DIMENSIONLESS)
                for operand in operands:
                    factor = self.form(operand.node)
                    if factor is None or result is None:
                        result = None
                        continue  # the other factors are still checked inside
                    result = combine(result, factor, -1 if operand.inverted else 1)
                return result
            case Power(base=base, exponent=exponent):
                return self.power(base, exponent)
            case Call(name=name, args=args, juxtaposed=juxtaposed):
                return self.call(name, args, juxtaposed)
        raise TypeError(f"unexpected syntax node {node!r}")

    def power(self, base: Node, exponent: Node) -> Form | None:
        value = _constant(exponent)
        if value is None:  # x**n with n a symbol: both sides must be pure numbers
            self.dimensionless(exponent, "exponent")
            self.dimensionless(base, "base of a power with a symbolic exponent")
            return known(DIMENSIONLESS)
        form = self.form(base)
        return None if form is None else scale(form, value)

    def call(self, name: str, args: tuple[Node, ...], juxtaposed: bool) -> Form | None:
        if juxtaposed and name not in self.functions:  # LaTeX m(a + b): a product
            first, second = self.name(name), self.form(args[0])
            return None if second is None else combine(first, second)
        if name in _DIMENSIONLESS_ARGUMENTS:
            self.dimensionless(args[0], f"argument of {name}")
            return known(DIMENSIONLESS)
        if name == "sqrt":
            form = self.form(args[0])
            return None if form is None else scale(form, Fraction(1, 2))
        if name == "Abs":
            return self.form(args[0])
        if name == "sign":  # the sign of a quantity of any dimension (Coulomb friction's)
            self.form(args[0])
            return known(DIMENSIONLESS)
        if name == "atan2":
            self.alike(list(args), "argument of atan2")
            return known(DIMENSIONLESS)
        for argument in args:  # a declared function: its arguments are free
            self.form(argument)
        return unknown(name)


def _named(what: str, written: str) -> str:
    """``argument x of sin`` (``what`` is ``argument of sin``), ``term k*x``."""
    kind, of, rest = what.partition(" of ")
    return f"{kind} {written} of {rest}" if of else f"{what} {written}"


def _key(form: Form) -> tuple:
    return tuple(sorted(form[0].items())), form[1]


def _terms(node: Node) -> list[Node]:
    """The terms of the sum ``node`` is (sums inside sums and signs opened), or [node]."""
    match node:
        case Sum(terms=operands):
            return [term for operand in operands for term in _terms(operand.node)]
        case Negate(operand=operand) if isinstance(operand, Sum | Negate):
            return _terms(operand)
    return [node]


def _constant(node: Node) -> Fraction | None:
    """The rational number ``node`` is, or None (it has a name, or is irrational)."""
    match node:
        case Number(value=value):
            return int(value.p) if value.q == 1 else Fraction(int(value.p), int(value.q))
        case Negate(operand=operand):
            value = _constant(operand)
            return None if value is None else -value
        case Sum(terms=operands):
            values = [_constant(o.node) for o in operands]
            if None in values:
                return None
            signed = (-v if o.inverted else v for o, v in zip(operands, values, strict=True))
            return sum(signed, Fraction(0))
        case Product(factors=operands):
            result = Fraction(1)
            for operand in operands:
                value = _constant(operand.node)
                if value is None or (operand.inverted and value == 0):
                    return None
                result = result / value if operand.inverted else result * value
            return result
    return None


def _written(node: Node, text: str) -> str:
    """The text ``node`` was written with: from its first token to its last, with the
    brackets it opens or closes."""
    ends = token_ends(text)
    positions = list(_positions(node))
    start = min(positions)
    end = max(ends.get(p, p + 1) for p in positions)
    span = text[start:end]
    depth = sum(span.count(c) for c in _OPENERS) - sum(span.count(c) for c in _CLOSERS)
    while depth > 0 and end < len(text):  # f(x: take the closing bracket
        if text[end] in _CLOSERS:
            depth -= 1
        end += 1
    while depth < 0 and start > 0:  # x + 1)*y: take the opening one
        start -= 1
        if text[start] in _OPENERS:
            depth += 1
    return " ".join(text[start:end].split())


def _positions(node: Node):
    stack = [node]
    while stack:
        node = stack.pop()
        yield node.position
        match node:
            case Negate(operand=operand):
                stack.append(operand)
            case Sum(terms=operands) | Product(factors=operands):
                stack.extend(o.node for o in operands)
                yield from (o.position for o in operands[1:])
            case Power(base=base, exponent=exponent):
                stack.extend((base, exponent))
            case Call(args=args):
                stack.extend(args)

"""What generated code computes, language-neutral: symbols renamed, expressions CSE'd.

A :class:`Program` holds, for M(q, t) q'' = f(q, q', t, u) (see
:class:`~lagrangian.derive.EquationsOfMotion`), three routines of (t, y, params, u)
with y = [q, q']:

* ``mass_matrix``: M (n x n),
* ``forcing``: f (n),
* ``dynamics``: M, f and, with constraints, A and the stabilised bias b of
  A q'' = b, together, for the right-hand side, which solves

      M q'' = f                                  (no constraints), or
      [[M, -A^T], [A, 0]] [q''; lambda] = [f; b]  (constraints, Baumgarte's
      b = beta - 2 alpha (A q' + a0) - alpha^2 c, as :mod:`lagrangian.numeric.dynamics`)

  and returns y' = [q', q''].

The expressions are those our own compiled right-hand side evaluates
(:func:`lagrangian.codegen.forms.symbolic_forms`), with the model's names
renamed so that no name of a model can clash with a target language's keywords
or with the generated code's own names: a coordinate ``x`` is ``q_x``, its
velocity ``v_x``, a parameter ``g`` is ``p_g``, an input ``F`` is ``u_F``,
time stays ``t`` and common subexpressions (:func:`sympy.cse`) are ``w_0, w_1, ...``.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property

import sympy

from ..derive import EquationsOfMotion
from ..distributions import without_distributions
from ..errors import ModelError
from .definitions import Definition, function_definitions
from .forms import DEFAULT_BAUMGARTE, SymbolicForms, checked_baumgarte, symbolic_forms
from .literals import machine_numbers


@dataclass(frozen=True)
class Routine:
    """One generated function: the temporaries (symbol, expression) in order, then the
    named outputs (each a matrix of expressions over the renamed symbols and temporaries)."""

    name: str
    temporaries: tuple[tuple[sympy.Symbol, sympy.Expr], ...]
    outputs: tuple[tuple[str, sympy.ImmutableMatrix], ...]

    def output(self, name: str) -> sympy.ImmutableMatrix:
        return dict(self.outputs)[name]


@dataclass(frozen=True)
class Quantity:
    """A name of the model and the symbol that stands for it in the generated code."""

    name: str
    symbol: sympy.Symbol
    default: float | None = None


@dataclass(frozen=True)
class Program:
    """Everything a target needs (see the module docstring).

    Cheap to make: the renamed blocks and the CSE'd routines are made on first use (the
    CSE of a 10-link chain takes over a second), and targets that generate code of their
    own from the symbolic forms (numba, llvm, heyoka) read :attr:`forms` and pay nothing.
    """

    title: str
    description: str
    time: sympy.Symbol
    coordinates: tuple[Quantity, ...]
    velocities: tuple[Quantity, ...]
    parameters: tuple[Quantity, ...]
    inputs: tuple[Quantity, ...]
    constraints: int
    baumgarte: float
    forms: SymbolicForms = field(repr=False, compare=False)

    @property
    def n(self) -> int:
        return len(self.coordinates)

    @property
    def size(self) -> int:
        """Unknowns of the linear solve of the right-hand side: n + constraints."""
        return self.n + self.constraints

    @property
    def fingerprint(self) -> str:
        """The sha256 of the expressions it is made from (:func:`forms_fingerprint`)."""
        return self.forms.fingerprint

    @property
    def time_dependent(self) -> bool:
        routines = (self.mass_matrix, self.forcing, self.dynamics)
        return any(_uses(routine, self.time) for routine in routines)

    @cached_property
    def _renaming(self) -> dict[sympy.Symbol, sympy.Symbol]:
        forms = self.forms
        by_name = {p.name: p.symbol for p in forms.equations.system.parameters}
        renamed = {forms.time: self.time}
        renamed |= {q: c.symbol for q, c in zip(forms.coordinates, self.coordinates, strict=True)}
        renamed |= {v: c.symbol for v, c in zip(forms.velocities, self.velocities, strict=True)}
        renamed |= {by_name[x.name]: x.symbol for x in (*self.parameters, *self.inputs)}
        return renamed

    def renamed(self, matrix) -> sympy.ImmutableMatrix:
        """``matrix`` (over the model's symbols) over the program's, with what no language
        has: the delta functions (0 but where a force is not differentiable, as our own
        compiled functions take them) and exact numbers beyond a double (see
        :mod:`lagrangian.codegen.literals`) taken out."""
        matrix = without_distributions(sympy.Matrix(matrix).xreplace(self._renaming))
        return sympy.ImmutableMatrix(matrix.applyfunc(machine_numbers))

    def routine(self, name: str, blocks: Sequence[tuple[str, sympy.MatrixBase]]) -> Routine:
        """A routine of (t, y, params, u) beyond the equations (the positions a page draws,
        the energy it reads out): the ``blocks`` (label, matrix over the model's symbols)
        renamed and CSE'd like the program's own routines."""
        return _routine(name, [(label, self.renamed(matrix)) for label, matrix in blocks])

    @cached_property
    def blocks(self) -> tuple[tuple[str, sympy.ImmutableMatrix], ...]:
        """("M", M), ("f", f) and, with constraints, ("A", A), ("b", b), :meth:`renamed`."""
        forms = self.forms
        blocks = [("M", self.renamed(forms.mass_matrix)), ("f", self.renamed(forms.forcing))]
        if self.constraints:
            blocks += [
                ("A", self.renamed(forms.constraints.matrix)),
                ("b", self.renamed(forms.constraints.stabilised_bias(self.baumgarte))),
            ]
        return tuple(blocks)

    @cached_property
    def mass_matrix(self) -> Routine:
        return _routine("mass_matrix", list(self.blocks[:1]))

    @cached_property
    def forcing(self) -> Routine:
        return _routine("forcing", list(self.blocks[1:2]))

    @cached_property
    def dynamics(self) -> Routine:
        return _routine("dynamics", list(self.blocks))


def program(
    eom: EquationsOfMotion,
    *,
    definitions: Mapping[str, Definition] | None = None,
    baumgarte: float = DEFAULT_BAUMGARTE,
) -> Program:
    """The :class:`Program` of ``eom``; unspecified functions must be given in
    ``definitions`` (as for :func:`~lagrangian.numeric.compile_equations`)."""
    baumgarte = checked_baumgarte(baumgarte)
    return program_of(symbolic_forms(eom, function_definitions(eom.system, definitions)), baumgarte)


def program_of(forms: SymbolicForms, baumgarte: float = DEFAULT_BAUMGARTE) -> Program:
    """The :class:`Program` of symbolic forms already made (a compiled system keeps its own)."""
    baumgarte = checked_baumgarte(baumgarte)
    system = forms.equations.system
    inputs = set(system.input_names)
    coordinates = tuple(
        Quantity(c.name, sympy.Symbol(f"q_{c.name}", real=True)) for c in system.coordinates
    )
    velocities = tuple(
        Quantity(c.q_dot.name, sympy.Symbol(f"v_{c.name}", real=True)) for c in system.coordinates
    )
    parameters = tuple(
        Quantity(p.name, sympy.Symbol(f"p_{p.name}", real=True), p.default)
        for p in system.parameters
        if p.name not in inputs
    )
    controls = tuple(
        Quantity(p.name, sympy.Symbol(f"u_{p.name}", real=True))
        for p in system.parameters
        if p.name in inputs
    )
    count = forms.constraints.count if forms.constraints is not None else 0
    return Program(
        title=system.name,
        description=system.description,
        time=sympy.Symbol("t", real=True),
        coordinates=coordinates,
        velocities=velocities,
        parameters=parameters,
        inputs=controls,
        constraints=count,
        baumgarte=float(baumgarte) if count else 0.0,
        forms=forms,
    )


def _routine(name: str, blocks: list[tuple[str, sympy.ImmutableMatrix]]) -> Routine:
    """The blocks with their common subexpressions taken out once (sympy.cse)."""
    flat = [entry for _, matrix in blocks for entry in matrix]
    temporaries, reduced = sympy.cse(flat, symbols=sympy.numbered_symbols("w_", real=True))
    outputs, start = [], 0
    for label, matrix in blocks:
        size = matrix.rows * matrix.cols
        entries = reduced[start : start + size]
        outputs.append((label, sympy.ImmutableMatrix(matrix.rows, matrix.cols, entries)))
        start += size
    return Routine(name, tuple(temporaries), tuple(outputs))


def indexed_renaming(forms: SymbolicForms, backend: str, scalars=(), *, constants: bool = False):
    """Expression -> the same over ``_t``, ``_y<i>`` and ``_p<j>``: the flat names of the
    generated loops (numba, CUDA) that read t, the state y and the parameters p.

    Exact numbers become doubles (:func:`~.literals.machine_numbers`); with ``constants``
    pi and E become 20-digit floats too (C has no exact ones).  The ``scalars`` (a step h)
    are kept; any other symbol left is an error naming ``backend``.
    """
    n = forms.n
    replace = {forms.time: sympy.Symbol("_t")}
    replace.update({q: sympy.Symbol(f"_y{i}") for i, q in enumerate(forms.coordinates)})
    replace.update({v: sympy.Symbol(f"_y{n + i}") for i, v in enumerate(forms.velocities)})
    replace.update({s: sympy.Symbol(f"_p{j}") for j, s in enumerate(forms.parameters)})
    known = {*replace.values(), *scalars}

    def rename(expression: sympy.Expr) -> sympy.Expr:
        result = machine_numbers(without_distributions(expression).xreplace(replace))
        if constants:
            numbers = result.atoms(sympy.NumberSymbol)
            result = result.xreplace({c: sympy.Float(c.evalf(20), 20) for c in numbers})
        unknown = result.free_symbols - known
        if unknown:
            names = ", ".join(sorted(str(s) for s in unknown))
            raise ModelError(
                f"backend '{backend}': the equations depend on unknown symbols {names}"
            )
        return result

    return rename


def _uses(routine: Routine, symbol: sympy.Symbol) -> bool:
    return any(e.has(symbol) for _, e in routine.temporaries) or any(
        m.has(symbol) for _, m in routine.outputs
    )


def fingerprint(expression: sympy.Basic, digest: hashlib._Hash) -> None:
    """Feed an unambiguous prefix form of ``expression`` to ``digest``.

    Each node gives its class and arity, each atom its exact value (a Float its
    mantissa and exponent), so different trees never give the same bytes; much
    faster than printing (``srepr``).  The one fingerprint of generated code: the
    disk cache's file names and the in-memory cache's keys (:mod:`.cache`) come from it.
    """
    parts = []
    for node in sympy.preorder_traversal(expression):
        if isinstance(node, sympy.Float):
            parts.append(f"F{node._mpf_}")
        elif node.is_Atom:
            parts.append(f"{type(node).__name__}:{node}")
        else:
            parts.append(f"{type(node).__name__}/{len(node.args)}")
    parts.append(";")
    digest.update("\0".join(parts).encode())


def forms_fingerprint(forms: SymbolicForms) -> str:
    """sha256 over every expression code is generated from (the arguments in order, M, f,
    L, p, Q, h and the constraints): equal fingerprints, equal generated code."""
    digest = hashlib.sha256(sympy.__version__.encode() + b"\0")
    arguments = (forms.time, *forms.coordinates, *forms.velocities, *forms.parameters)
    parts = [sympy.Tuple(*arguments), forms.mass_matrix, forms.forcing, forms.lagrangian]
    parts += [forms.momenta, forms.nonconservative_forces, forms.energy]
    if forms.constraints is not None:
        constraints = forms.constraints
        parts += [constraints.matrix, constraints.bias, constraints.velocity]
        positions = (sympy.Integer(0) if c is None else c for c in constraints.position)
        parts += [sympy.Tuple(*positions), sympy.Tuple(*constraints.holonomic)]
    for part in parts:
        fingerprint(part, digest)
    return digest.hexdigest()

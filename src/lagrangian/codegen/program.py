"""What an exported file computes, language-neutral: symbols renamed, expressions CSE'd.

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

from collections.abc import Mapping
from dataclasses import dataclass

import sympy

from ..derive import EquationsOfMotion
from ..distributions import without_distributions
from .definitions import Definition, function_definitions
from .forms import DEFAULT_BAUMGARTE, checked_baumgarte, symbolic_forms
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
    """Everything a language writer needs (see the module docstring)."""

    title: str
    description: str
    time: sympy.Symbol
    coordinates: tuple[Quantity, ...]
    velocities: tuple[Quantity, ...]
    parameters: tuple[Quantity, ...]
    inputs: tuple[Quantity, ...]
    constraints: int
    baumgarte: float
    mass_matrix: Routine
    forcing: Routine
    dynamics: Routine

    @property
    def n(self) -> int:
        return len(self.coordinates)

    @property
    def size(self) -> int:
        """Unknowns of the linear solve of the right-hand side: n + constraints."""
        return self.n + self.constraints

    @property
    def time_dependent(self) -> bool:
        routines = (self.mass_matrix, self.forcing, self.dynamics)
        return any(_uses(routine, self.time) for routine in routines)


def program(
    eom: EquationsOfMotion,
    *,
    definitions: Mapping[str, Definition] | None = None,
    baumgarte: float = DEFAULT_BAUMGARTE,
) -> Program:
    """The :class:`Program` of ``eom``; unspecified functions must be given in
    ``definitions`` (as for :func:`~lagrangian.numeric.compile_equations`)."""
    baumgarte = checked_baumgarte(baumgarte)
    system = eom.system
    forms = symbolic_forms(eom, function_definitions(system, definitions))
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
    renamed = dict(zip(forms.coordinates, (c.symbol for c in coordinates), strict=True))
    renamed |= dict(zip(forms.velocities, (v.symbol for v in velocities), strict=True))
    by_name = {p.name: p for p in system.parameters}
    renamed |= {by_name[x.name].symbol: x.symbol for x in (*parameters, *controls)}
    time = sympy.Symbol("t", real=True)
    renamed[forms.time] = time

    def rename(matrix) -> sympy.ImmutableMatrix:
        """Renamed, with what no language has taken out: the delta functions (0 but where
        a force is not differentiable, as our own compiled functions take them) and exact
        numbers beyond a double (see :mod:`lagrangian.codegen.literals`)."""
        matrix = without_distributions(sympy.Matrix(matrix).xreplace(renamed))
        return sympy.ImmutableMatrix(matrix.applyfunc(machine_numbers))

    mass, forcing = rename(forms.mass_matrix), rename(forms.forcing)
    blocks = [("M", mass), ("f", forcing)]
    count = 0
    if forms.constraints is not None:
        count = forms.constraints.count
        blocks += [
            ("A", rename(forms.constraints.matrix)),
            ("b", rename(forms.constraints.stabilised_bias(baumgarte))),
        ]
    return Program(
        title=system.name,
        description=system.description,
        time=time,
        coordinates=coordinates,
        velocities=velocities,
        parameters=parameters,
        inputs=controls,
        constraints=count,
        baumgarte=float(baumgarte) if count else 0.0,
        mass_matrix=_routine("mass_matrix", [("M", mass)]),
        forcing=_routine("forcing", [("f", forcing)]),
        dynamics=_routine("dynamics", blocks),
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


def _uses(routine: Routine, symbol: sympy.Symbol) -> bool:
    return any(e.has(symbol) for _, e in routine.temporaries) or any(
        m.has(symbol) for _, m in routine.outputs
    )

"""RK4 on a fixed step grid with the terms that depend on time alone read from a table.

In a fixed-step ensemble whose members share the parameters (a basin map's grid of
starts, an ensemble of initial states), every member takes its steps at the same times
t_s + c_k h (stage k of step s), so a subexpression of M q'' = f whose free symbols lie in
{t} and the shared parameters (a drive A cos(ω t), a product of parameters) has the same
value for every member: :func:`split_time_terms` finds those subexpressions (the largest
such subtrees, and the factors or terms of a product or sum that are such), and the
generated step reads them from a row of a table made once for the grid
(:meth:`TabulatedLoop.table`), instead of evaluating a cosine per member and stage.
When M itself is such (free of the state: M = m l^2 for a pendulum), the table carries
M^-1 at each stage time as well, and the step multiplies by it instead of solving
M q'' = f (no division per stage).  The arithmetic is the plain rk4 step's
(:func:`lagrangian.codegen.steps.rk4`) at the same times, up to rounding: sums and
products are regrouped, and M^-1 f replaces the elimination.

The generated module (:mod:`.numba_tabulated`, filled per system and set of shared
parameters) has ``tabulate(grid, c, p, table)`` and the step
``rk4_table_step(t, h, y, p, rows, work, counts)`` (``rows``: the table's rows of the
step, one per stage); the parallel loop over members that calls it through a pointer is
:mod:`.numba_table_stepping`, compiled once for every system.
"""

from __future__ import annotations

import hashlib
from collections.abc import Collection, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import numpy as np
import sympy

from .cache import built, filled_template, load_text, package_text
from .forms import SymbolicForms
from .program import indexed_renaming
from .steps import LEAN
from .subtrees import hoisted

_SCHEME_BEGIN, _SCHEME_END = "# -- scheme: begin", "# -- scheme: end"


@dataclass(frozen=True)
class TimeTerms:
    """M and f of one system with their time-only terms taken out (see the module).

    ``terms``: the subexpressions tabulated, over ``_t`` and ``_p<j>``; ``symbols``: the
    ``_d<k>`` that stand for them in ``forcing`` and ``mass`` (M row by row, over ``_t``,
    ``_y<i>``, ``_p<j>`` and the ``_d<k>``); ``inverse``: M is free of the state, so the
    table carries M^-1 (row by row, after the terms) and ``mass`` is M itself, to invert."""

    n: int
    terms: tuple[sympy.Expr, ...]
    symbols: tuple[sympy.Symbol, ...]
    forcing: tuple[sympy.Expr, ...]
    mass: tuple[sympy.Expr, ...]
    inverse: bool

    @property
    def width(self) -> int:
        """Entries of a table row: the terms, then M^-1 where ``inverse``."""
        return len(self.terms) + (self.n * self.n if self.inverse else 0)


def split_time_terms(forms: SymbolicForms, shared: Collection[int]) -> TimeTerms:
    """M and f of ``forms`` with the subexpressions over t and the parameters numbered
    ``shared`` (those every member has the same value of) replaced by table entries."""
    n = forms.n
    rename = indexed_renaming(forms, "numba")
    mass = [rename(forms.mass_matrix[i, j]) for i in range(n) for j in range(n)]
    forcing = [rename(forms.forcing[i, 0]) for i in range(n)]
    allowed = {sympy.Symbol("_t"), *(sympy.Symbol(f"_p{j}") for j in shared)}
    found: dict[sympy.Expr, sympy.Symbol] = {}

    def fixed(expression: sympy.Basic) -> bool:  # a number (not a condition) every member has
        return isinstance(expression, sympy.Expr) and expression.free_symbols <= allowed

    def entry(expression: sympy.Expr) -> sympy.Symbol:
        if expression not in found:
            found[expression] = sympy.Symbol(f"_d{len(found)}")
        return found[expression]

    inverse = all(fixed(entry_) for entry_ in mass)
    forcing = [hoisted(e, fixed, entry) for e in forcing]
    if not inverse:
        mass = [hoisted(e, fixed, entry) for e in mass]
    return TimeTerms(n, tuple(found), tuple(found.values()), tuple(forcing), tuple(mass), inverse)


def shared_parameters(params: np.ndarray) -> tuple[int, ...]:
    """The parameters (columns of ``params``, members x parameters, or one vector) that
    every member has the same value of."""
    values = np.atleast_2d(np.asarray(params, dtype=float))
    return tuple(int(j) for j in range(values.shape[1]) if np.all(values[:, j] == values[0, j]))


def tabulated_step(split: TimeTerms, tableau) -> str:
    """The text of ``rk4_table_step(t, h, y, p, rows, work, counts)``: rk4 (``tableau``:
    a, b, c, the classic one's pattern, as :func:`~.steps.rk4`) whose stage k reads its
    table row ``rows[k]``, written out over scalars (the stages' slopes and states are
    local numbers, not arrays: a third of the plain step's time for a pendulum).  The
    operations of the plain step's program, in its order: the stages
    y + (h a_k) k_k, the times t + c_k h, y + h (((b1 k1 + b2 k2) + b3 k3) + b4 k4).
    Where M depends on the state it is filled and solved (``eliminate``) in the
    workspace's ``matrix`` and ``force``."""
    from .numba import _Printer

    a, b, c = tableau
    n, offset, m = split.n, len(split.terms), 2 * split.n
    printer = _Printer({"fully_qualified_modules": True, "strict": True})
    outputs = [*split.forcing, *(() if split.inverse else split.mass)]
    replacements, reduced = sympy.cse(outputs, symbols=sympy.numbered_symbols("_c"))
    used = set().union(*(e.free_symbols for e in outputs))
    number = lambda value: repr(float(value))  # noqa: E731

    lines = ["vectors, matrices = work", "force = vectors[0:N]", "solved = vectors[N:2 * N]",
             "matrix = matrices[0]"]  # fmt: skip
    lines += [f"{s.name} = p[{s.name[2:]}]" for s in sorted(used, key=str) if s.name[:2] == "_p"]
    lines += [f"y_{i} = y[{i}]" for i in range(m)]
    state = [f"y_{i}" for i in range(m)]
    for k in range(4):
        time = "t" if k == 0 else f"t + ({number(c[k])} * h)"
        if k > 0:  # the stage's state from the slopes before it
            state = [f"s{k}_{i}" for i in range(m)]
            factor = number(a[k, k - 1])
            lines += [f"s{k}_{i} = y_{i} + ((h * {factor}) * k{k}_{i})" for i in range(m)]
        lines += [f"row = rows[{k}]", f"_t = {time}"]
        lines += [f"_y{i} = {state[i]}" for i in range(m)]
        lines += [f"{s.name} = row[{s.name[2:]}]" for s in split.symbols if s in used]
        lines += [f"{s} = {printer.doprint(v)}" for s, v in replacements]
        lines += [f"f_{i} = {printer.doprint(e)}" for i, e in enumerate(reduced[:n])]
        if split.inverse:
            for i in range(n):
                total = " + ".join(f"(row[{offset + i * n + j}] * f_{j})" for j in range(n))
                lines.append(f"a_{i} = {total}")
        else:
            for index, entry in enumerate(reduced[n:]):
                lines.append(f"matrix[{index // n}, {index % n}] = {printer.doprint(entry)}")
            lines += [f"force[{i}] = f_{i}" for i in range(n)]
            lines.append("eliminate(matrix, force, solved, 0)")
            lines += [f"a_{i} = solved[{i}]" for i in range(n)]
        lines += [f"k{k + 1}_{i} = {state[n + i]}" for i in range(n)]
        lines += [f"k{k + 1}_{n + i} = a_{i}" for i in range(n)]
    b1, b2, b3, b4 = (number(value) for value in b)
    for i in range(m):
        weighted = f"((({b1} * k1_{i}) + ({b2} * k2_{i})) + ({b3} * k3_{i})) + ({b4} * k4_{i})"
        lines.append(f"y[{i}] = y_{i} + (h * ({weighted}))")
    lines.append("return 0")
    cover = "  # pragma: no cover - compiled by numba"
    head = [LEAN, f"def rk4_table_step(t, h, y, p, rows, work, counts):{cover}"]
    return "\n".join([*head, *("    " + line for line in lines), ""])


class TabulatedLoop:
    """One system's tabulated rk4 (see the module) with the shared loop over members:
    ``table(grid, p)`` once, then ``run(...)`` as often as the grid is stepped."""

    def __init__(self, loops: ModuleType, system: ModuleType, n: int, width: int, tableau):
        self.loops, self.system, self.width = loops, system, width
        self._sizes = (2 * n, 1, n, n)  # the step's force and solved, and its matrix
        self._stages = np.ascontiguousarray(np.asarray(tableau.c, dtype=float))
        self._steppers = loops.steppers(system.rk4_table_step)

    def table(self, grid: np.ndarray, params: np.ndarray) -> np.ndarray:
        """(steps, stages, width): each stage's row at t = grid[s] + c_k (grid[s+1] - grid[s]),
        with ``params`` (one vector: the shared ones are read)."""
        grid = np.ascontiguousarray(grid, dtype=float)
        table = np.zeros((grid.size - 1, self._stages.size, max(self.width, 1)))
        self.system.tabulate(grid, self._stages, np.ascontiguousarray(params, dtype=float), table)
        return table

    def run(self, y0, params, grid, table, every: int, final, paths) -> None:
        """Every member of ``y0`` (B, 2n) stepped over ``grid`` with its row of ``params``
        (B, parameters; C order), the state after every ``every`` steps into ``paths``
        (B, 2n, saved) when ``every``, the last into ``final``."""
        self.loops.run(*self._sizes, self._steppers, y0, params, grid, table, every, final, paths)


def tabulated_loop(forms: SymbolicForms, shared: Sequence[int], *, tableau) -> TabulatedLoop:
    """The :class:`TabulatedLoop` of ``forms`` (unconstrained) with the parameters
    ``shared`` taken as the same for every member, built once per process."""
    shared = tuple(sorted(int(j) for j in shared))
    build = lambda: _build(forms, shared, tableau)  # noqa: E731
    return built(forms.fingerprint, "numba-tabulated", build, shared)


def _build(forms: SymbolicForms, shared: tuple[int, ...], tableau) -> TabulatedLoop:
    from .numba import linear_import, load_functions

    split = split_time_terms(forms, shared)
    n = forms.n
    unused = [sympy.Float(0.0)] * (n * n)  # tabulate inverts M only where it is state-free
    functions = [
        ("terms", [("out", list(split.terms))]),
        ("mass", [("M", list(split.mass) if split.inverse else unused)]),
    ]
    fillers = load_functions(forms, "tabulated", functions, matrices=("M",))
    generated = [
        f"from {fillers.__name__} import terms, mass",
        linear_import(n),
        f"N, TERMS, INVERSE = {n}, {len(split.terms)}, {split.inverse}",
    ]
    text = filled_template(Path(__file__).with_name("numba_tabulated.py"), generated)[1]
    before, rest = text.split(_SCHEME_BEGIN, 1)
    after = rest.split(_SCHEME_END, 1)[1].split("\n", 1)[1]
    step = tabulated_step(split, (tableau.a, tableau.b, tableau.c))
    text = "\n".join([before.rstrip("\n"), "", "", step, "", after.lstrip("\n")])
    system = load_text(hashlib.sha256(text.encode()).hexdigest(), text)
    loops = load_text(*package_text(Path(__file__).with_name("numba_table_stepping.py")))
    return TabulatedLoop(loops, system, n, split.width, tableau)

"""Term tables of the large route: SymEngine expressions as {state monomial: coefficient}.

A monomial depends on the state symbols (q, q', t) and its coefficient only on
parameters.  Differentiating a table touches only the monomials that hold the symbol
(an index finds them); products of sums are expanded after counting the terms that
makes (``MAX_EXPANDED_TERMS``).
"""

from __future__ import annotations

from collections import defaultdict

from ..algebra import factor_common
from ..budget import MAX_EXPANDED_TERMS, expanded_terms
from ..errors import ModelError


class TermTables:
    """Splitting SymEngine expressions into {monomial: coefficient} over the state symbols."""

    def __init__(self, state, *, nonsmooth: bool = False, field=lambda: None):
        import symengine as se

        self.se = se
        self.one = se.Integer(1)
        self.state = frozenset(state)
        self.symbols: dict = {}  # monomial -> its state symbols
        self.nonsmooth = nonsmooth  # whether an |u| or sign(u) may be differentiated
        self.absolute: set = set()  # the monomials that hold an |u|
        self._depends: dict = {}  # factor -> whether it holds a state symbol
        self.made = 0  # terms split so far: all the tables' terms are bounded together
        self.field = field  # () -> the model's field a refusal names (found only then)

    def depends(self, factor) -> bool:
        """Whether ``factor`` holds a state symbol (cached: the same factors recur)."""
        found = self._depends.get(factor)
        if found is None:
            found = self._depends[factor] = bool(factor.free_symbols & self.state)
        return found

    def split(self, expr, into=None, scale=None) -> dict:
        """Add ``scale * expr`` term by term to ``into`` ({monomial: [coefficients]})."""
        se = self.se
        Add, Mul, Pow = se.Add, se.Mul, se.Pow
        into = defaultdict(list) if into is None else into
        added = 0
        one = self.one if scale is None else scale
        known = self._depends
        for term in expr.args if type(expr) is Add else (expr,):
            coefficient, dependent = [one], []
            for factor in term.args if type(term) is Mul else (term,):
                found = known.get(factor)
                if found is None:
                    found = self.depends(factor)
                (dependent if found else coefficient).append(factor)
            added += 1
            if not dependent:
                into[self.one].append(one * term)
                continue
            # (a product of one factor is that factor: the keys and coefficients of Mul)
            outer = one if len(coefficient) == 1 else Mul(*coefficient)
            for factor in dependent:
                kind = type(factor)
                if kind is Add or (kind is Pow and type(factor.args[0]) is Add):
                    break  # a sum, or a power of one, that expansion distributes
            else:
                into[dependent[0] if len(dependent) == 1 else Mul(*dependent)].append(outer)
                continue
            # SymEngine's expand runs in C++, out of reach of the deadline and of memory's
            # limits: the terms it would make are counted first, all tables' together
            product = Mul(*dependent)
            left = MAX_EXPANDED_TERMS - self.made - added
            if expanded_terms(product, left) > left:
                raise too_many_terms(self.field())
            for part in _args(se.expand(product), Add):
                added += 1
                inner, monomial = [outer], []
                for factor in _args(part, Mul):
                    (monomial if self.depends(factor) else inner).append(factor)
                into[Mul(*monomial)].append(Mul(*inner))
        self.made += added
        if self.made > MAX_EXPANDED_TERMS:
            raise too_many_terms(self.field())
        return into

    def table(self, lists: dict, *, differentiated: bool = False) -> dict:
        """{monomial: coefficient} from {monomial: [coefficients]}, zeros dropped; where the
        table is to be ``differentiated``, its monomials' state symbols are recorded."""
        Add = self.se.Add
        result = {}
        for monomial, coefficients in lists.items():
            coefficient = coefficients[0]
            if len(coefficients) > 1 or type(coefficient) is Add:
                coefficient = factor_common(coefficients)
            if not coefficient.is_zero:
                result[monomial] = coefficient
        if differentiated:
            for monomial in result:
                if monomial not in self.symbols:
                    self.symbols[monomial] = monomial.free_symbols & self.state
                    if self.nonsmooth and monomial.atoms(self.se.Abs):
                        self.absolute.add(monomial)
        return result

    def derivative(self, monomial, symbol):
        """d monomial / d symbol; d|u|/dx = sign(u) du/dx, as SymPy has it for real u
        (every symbol of a model is real), where SymEngine leaves Derivative(|u|, x)."""
        se = self.se
        result = se.diff(monomial, symbol)
        if self.absolute and monomial in self.absolute:
            undone = [d for d in result.atoms(se.Derivative) if type(d.args[0]) is se.Abs]
            inner = [d.args[0].args[0] for d in undone]
            result = result.subs(
                {d: se.sign(u) * se.diff(u, symbol) for d, u in zip(undone, inner, strict=True)}
            )
        return result

    def index(self, table: dict) -> dict:
        """{state symbol: the monomials of ``table`` that hold it}."""
        found = defaultdict(list)
        for monomial in table:
            for symbol in self.symbols[monomial]:
                found[symbol].append(monomial)
        return found

    def diff(self, table: dict, symbol, index: dict | None = None) -> dict:
        """``d table / d symbol`` as {monomial: [coefficients]} (``index``: of ``table``)."""
        into = defaultdict(list)
        if index is None:
            index = {symbol: [m for m in table if symbol in self.symbols[m]]}
        for monomial in index.get(symbol, ()):
            self.split(self.derivative(monomial, symbol), into, table[monomial])
        return into

    def expr(self, table: dict):
        return self.se.Add(*(c * m for m, c in table.items()))


def too_many_terms(field: str | None = None) -> ModelError:
    """The one-line refusal of a model whose expansion is too large to derive."""
    return ModelError(
        f"expanded, it makes more than {MAX_EXPANDED_TERMS:,} terms (a power of a sum of "
        "n terms to the k makes C(n + k - 1, k)): the model is too large to derive",
        field=field,
    )


def _args(expr, kind) -> tuple:
    return expr.args if type(expr) is kind else (expr,)

"""Term tables of the large route: SymEngine expressions as {state monomial: coefficient}.

A monomial depends on the state symbols (q, q', t) and its coefficient only on
parameters.  A monomial is held as a tuple of small integers, ((atom, exponent), ...)
sorted by atom, where an atom is a distinct base of the state factors (a state symbol,
cos(theta_1 - theta_2), ...) numbered as first met; its SymEngine form is made once per
distinct monomial, when a table becomes an expression.  Differentiating a monomial by a
symbol held by one of its atoms is then the product rule in integers: the exponent
lowered and the atom's own derivative (split once per atom and symbol) multiplied in.
Products of sums are expanded after counting the terms that makes (``MAX_EXPANDED_TERMS``).
"""

from __future__ import annotations

from collections import defaultdict

from ..algebra import args_of, factor_common
from ..errors import ModelError
from ..sizes import MAX_EXPANDED_TERMS, expanded_terms


class TermTables:
    """Splitting SymEngine expressions into {monomial: coefficient} over the state symbols.

    ``state`` gives the symbols' numbers: atom k < len(state) is ``state[k]``.
    """

    def __init__(self, state, *, nonsmooth: bool = False, field=lambda: None):
        import symengine as se

        self.se = se
        self.one = se.Integer(1)
        self._minus = (se.Integer(-1),)  # the factors of a coefficient -1
        self.state = frozenset(state)
        self.nonsmooth = nonsmooth  # whether an |u| or sign(u) may be differentiated
        self.field = field  # () -> the model's field a refusal names (found only then)
        self.made = 0  # terms split so far: all the tables' terms are bounded together
        self.symbols: dict = {}  # monomial -> {symbol's number: (atom, exponent) or None}
        self.atoms: list = list(state)  # atom number -> its SymEngine base
        self._numbers: dict = {s: k for k, s in enumerate(state)}  # base -> atom number
        self._holds: list = [(k,) for k in range(len(state))]  # atom -> its symbols' numbers
        self._plain: list = [True] * len(state)  # atom -> product rule on it is SymEngine's
        self._factors: dict = {}  # factor -> False, (atom, exponent) or (atom, exponent, SUM)
        self._exprs: dict = {(): self.one}  # monomial -> its SymEngine form
        self._powers: dict = {}  # (atom, exponent) -> its SymEngine form
        self._atom_derivatives: dict = {}  # (atom, symbol) -> ([(monomial, factors)], cost)
        self._integers: dict = {}
        self._circular = (se.sin, se.cos)
        self._partners: dict = {}  # atom sin(u) or cos(u) -> (u, the other's (atom, 1))

    def _factor(self, factor):
        """What ``factor`` of a term is (cached: the same factors recur): False where it
        holds no state symbol, else (atom, exponent): b^k with an integer or rational k is
        atom b to k, anything else an atom to the power 1; SUM is appended where the
        factor is a sum or a power of one, which expansion distributes."""
        se = self.se
        kind = type(factor)
        if kind is se.Symbol:  # a parameter or a state symbol (no set of its symbols made)
            held = (factor,) if factor in self.state else ()
        else:
            held = factor.free_symbols & self.state
        if not held:
            found = False
        elif kind is se.Add or (kind is se.Pow and type(factor.args[0]) is se.Add):
            found = (*self._power(factor, held), SUM)
        else:
            found = self._power(factor, held)
        self._factors[factor] = found
        return found

    def _power(self, factor, held: set) -> tuple:
        """(atom, exponent) of a state factor holding the state symbols ``held``."""
        se = self.se
        base, exponent = factor, 1
        if type(factor) is se.Pow:
            base, exponent = factor.args
            if exponent.is_Integer:
                exponent = int(exponent)
            elif not exponent.is_Rational:
                base, exponent = factor, 1
        number = self._numbers.get(base)
        if number is None:  # b^k with a number k holds b's symbols
            holds = tuple(sorted(self._numbers[s] for s in held))
            # the product rule over atoms gives SymEngine's terms where the atom is a
            # symbol or a function of the state that SymEngine differentiates itself
            plain = (
                type(base) not in (se.Add, se.Mul, se.Pow)
                and not base.is_Number
                and not (self.nonsmooth and base.atoms(se.Abs, se.sign))
            )
            number = self._atom(base, holds, plain)
        return (number, exponent)

    def _atom(self, base, holds: tuple, plain: bool) -> int:
        """The number of a new atom ``base`` holding the symbols numbered ``holds``."""
        number = self._numbers[base] = len(self.atoms)
        self.atoms.append(base)
        self._holds.append(holds)
        self._plain.append(plain)
        return number

    def expr_of(self, monomial: tuple):
        """The SymEngine form of ``monomial`` (made once)."""
        found = self._exprs.get(monomial)
        if found is None:
            factors = self._forms(monomial)
            found = factors[0] if len(factors) == 1 else self.se.Mul(*factors)
            self._exprs[monomial] = found
        return found

    def _forms(self, monomial: tuple) -> list:
        """The SymEngine forms of ``monomial``'s powers."""
        powers, power_of = self._powers, self._power_of
        return [powers[p] if p in powers else power_of(p) for p in monomial]

    def split(self, expr, into=None, scale=None, *, bound: int | None = None) -> dict:
        """Add ``scale * expr`` term by term to ``into`` ({monomial: [coefficients]});
        ``bound``: the terms the expansion of ``expr`` makes at most, where counted."""
        Mul = self.se.Mul
        into = defaultdict(list) if into is None else into
        one = self.one if scale is None else scale
        terms, added = self._terms(expr, bound)
        for monomial, factors in terms:
            into[monomial].append(Mul(one, *factors) if factors else one)
        self._count(added)
        return into

    def _terms(self, expr, bound: int | None = None) -> tuple[list, int]:
        """[(monomial, coefficient's factors)] of ``expr``, and the terms counted."""
        se = self.se
        Add, Mul = se.Add, se.Mul
        made = []
        added = 0
        known = self._factors
        classify = self._factor
        for term in expr.args if type(expr) is Add else (expr,):
            coefficient, dependent, powers = [], [], []
            sums = False
            for factor in term.args if type(term) is Mul else (term,):
                found = known.get(factor)
                if found is None:
                    found = classify(factor)
                if found is False:
                    coefficient.append(factor)
                else:
                    dependent.append(factor)
                    powers.append(found)
                    if len(found) == 3:
                        sums = True
            added += 1
            if not dependent:
                made.append(((), (term,)))
            elif not sums:
                monomial = tuple(sorted(powers)) if len(powers) > 1 else tuple(powers)
                made.append((monomial, tuple(coefficient)))
            else:
                parts = self._expanded(dependent, coefficient, added, bound)
                made += parts
                added += len(parts)
        return made, added

    def _expanded(self, dependent: list, coefficient: list, added: int, bound) -> list:
        """The terms of the expansion of a product of state factors, some of them sums
        (times ``coefficient``'s factors), as ``_terms`` gives them."""
        se = self.se
        # SymEngine's expand runs in C++, out of reach of the deadline and of memory's
        # limits: the terms it would make are counted first, all tables' together (no
        # count where the whole expression's bound leaves room: its products make fewer)
        product = se.Mul(*dependent)
        left = MAX_EXPANDED_TERMS - self.made - added
        if (bound is None or bound > left) and expanded_terms(product, left) > left:
            raise too_many_terms(self.field())
        parts = []
        known, classify = self._factors, self._factor
        for part in args_of(se.expand(product), se.Add):
            inner, powers = list(coefficient), []
            for factor in args_of(part, se.Mul):
                found = known.get(factor)
                if found is None:
                    found = classify(factor)
                if found is False:
                    inner.append(factor)
                else:
                    powers.append(found[:2])
            parts.append((tuple(sorted(powers)), tuple(inner)))
        return parts

    def _count(self, added: int) -> None:
        self.made += added
        if self.made > MAX_EXPANDED_TERMS:
            raise too_many_terms(self.field())

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
            holds, symbols = self._holds, self.symbols
            for monomial in result:
                if monomial not in symbols:
                    held: dict = {}
                    for power in monomial:
                        for s in holds[power[0]]:
                            held[s] = power if s not in held else None  # None: two atoms
                    symbols[monomial] = held
        return result

    def derivative(self, expr, symbol):
        """d expr / d symbol; d|u|/dx = sign(u) du/dx, as SymPy has it for real u (every
        symbol of a model is real), where SymEngine leaves Derivative(|u|, x)."""
        se = self.se
        result = se.diff(expr, symbol)
        if self.nonsmooth and result.atoms(se.Derivative):
            undone = [d for d in result.atoms(se.Derivative) if type(d.args[0]) is se.Abs]
            inner = [d.args[0].args[0] for d in undone]
            result = result.subs(
                {d: se.sign(u) * se.diff(u, symbol) for d, u in zip(undone, inner, strict=True)}
            )
        return result

    def differentiate(self, table: dict, routes: list, monomials=None) -> None:
        """For each state symbol s with ``routes[s] = (into, times)``, add ``c * dm/ds``
        of each term c m of ``table`` (of ``monomials`` of it, where given) to ``into``,
        times the state symbol numbered ``times`` where that is not None: the terms
        SymEngine's derivative would give, split."""
        Mul = self.se.Mul
        symbols, plain, derivatives = self.symbols, self._plain, self._atom_derivatives
        made = 0  # terms counted, added to self.made table by table
        for monomial in table if monomials is None else monomials:
            scale = table[monomial]
            for symbol, held in symbols[monomial].items():
                route = routes[symbol]
                if route is None:
                    continue
                into, times = route
                found = None
                if held is not None and type(held[1]) is int and plain[held[0]]:
                    found = derivatives.get((held[0], symbol), _UNKNOWN)
                    if found is _UNKNOWN:
                        found = self._atom_derivative(held[0], symbol)
                if found is None:  # SymEngine's derivative of the whole monomial
                    self._count(made)
                    made = 0
                    derivative = self.derivative(self.expr_of(monomial), self.atoms[symbol])
                    if times is not None:
                        derivative = derivative * self.atoms[times]
                    self.split(derivative, into, scale)
                    continue
                # k a^(k-1) (da/ds) (the rest) for the monomial's a^k, da/ds split once
                atom, exponent = held
                terms, cost = found
                rest = dict(monomial)
                if exponent == 1:
                    del rest[atom]
                    lowered: tuple = ()
                else:
                    rest[atom] = exponent - 1
                    lowered = (self._integer(exponent),)
                if times is not None:
                    rest[times] = rest.get(times, 0) + 1
                single = len(terms) == 1
                for powers, factors, negated in terms:
                    product = rest if single else rest.copy()
                    for a, k in powers:
                        k += product.get(a, 0)
                        if type(k) is not int and k.is_Integer:  # a sum of rationals
                            k = int(k)
                        if k == 0:
                            del product[a]
                        else:
                            product[a] = k
                    key = tuple(sorted(product.items()))
                    if lowered:
                        into[key].append(Mul(scale, *lowered, *factors))
                    elif negated:  # the product Mul(scale, -1) makes, made faster
                        into[key].append(-scale)
                    else:
                        into[key].append(Mul(scale, *factors) if factors else scale)
                made += cost
        self._count(made)

    def _atom_derivative(self, atom: int, symbol: int):
        """([(monomial, factors)], terms counted) of d atom / d symbol; None where the
        derivative is a sum (SymEngine's derivative of the product then stays one term
        with that sum as a factor, which the split expands otherwise)."""
        base = self.atoms[atom]
        found = _UNKNOWN
        if type(base) in self._circular:
            found = self._circular_derivative(atom, base, symbol)
        if found is _UNKNOWN:
            derivative = self.derivative(base, self.atoms[symbol])
            found = None if type(derivative) is self.se.Add else self._terms(derivative)
        if found is not None:  # each term marked where its coefficient is -1 alone
            minus = self._minus
            found = [(m, f, f == minus) for m, f in found[0]], found[1]
        self._atom_derivatives[(atom, symbol)] = found
        return found

    def _circular_derivative(self, atom: int, base, symbol: int):
        """d sin(u)/ds = cos(u) du/ds and d cos(u)/ds = -sin(u) du/ds where du/ds holds no
        state symbol, as ``_atom_derivative`` gives them (the factors of SymEngine's
        derivative, without making and splitting it); _UNKNOWN otherwise."""
        se = self.se
        partner = self._partners.get(atom)
        if partner is None:
            (inside,) = base.args
            made = se.cos(inside) if type(base) is se.sin else se.sin(inside)
            power = None
            if type(made) in self._circular:  # not -sin(u) for an odd sin of a negation
                power = self._factors.get(made)
                if power is None:  # an atom holding the symbols that its partner holds
                    number = self._atom(made, self._holds[atom], self._plain[atom])
                    power = self._factors[made] = (number, 1)
            partner = self._partners[atom] = (inside, power)
        inside, power = partner
        if power is None:
            return _UNKNOWN
        rate = se.diff(inside, self.atoms[symbol])
        if not rate.is_Number and rate.free_symbols & self.state:
            return _UNKNOWN
        if type(base) is se.cos:
            rate = -rate
        return [((power,), () if rate == self.one else (rate,))], 1

    def _power_of(self, power: tuple):
        """The SymEngine form of an (atom, exponent) pair (made once: the same powers recur
        in many terms, and ``base ** k`` of a Python int converts k on each use)."""
        atom, k = power
        base = self.atoms[atom]
        if type(k) is not int:  # a rational exponent
            found = base**k
        elif k == 1:
            found = base
        else:
            found = base ** self._integer(k)
        self._powers[power] = found
        return found

    def _integer(self, k: int):
        found = self._integers.get(k)
        if found is None:
            found = self._integers[k] = self.se.Integer(k)
        return found

    def index(self, table: dict) -> dict:
        """{state symbol's number: the monomials of ``table`` that hold it}."""
        found = defaultdict(list)
        for monomial in table:
            for symbol in self.symbols[monomial]:
                found[symbol].append(monomial)
        return found

    def diff(self, table: dict, symbol: int, index: dict | None = None) -> dict:
        """``d table / d symbol`` as {monomial: [coefficients]} (``index``: of ``table``)."""
        into = defaultdict(list)
        if index is None:
            index = {symbol: [m for m in table if symbol in self.symbols[m]]}
        routes = [None] * len(self.state)
        routes[symbol] = (into, None)
        self.differentiate(table, routes, index.get(symbol, ()))
        return into

    def expr(self, table: dict):
        """The sum of ``table``'s terms, each one product of its coefficient and powers."""
        Mul, forms = self.se.Mul, self._forms
        terms = [Mul(c, *forms(m)) if m else c for m, c in table.items()]
        # most of M's entries have one term: the term itself, as the sum of one is
        return terms[0] if len(terms) == 1 else self.se.Add(*terms)


_UNKNOWN = object()
SUM = "sum"  # marks a factor that is a sum or a power of one


def too_many_terms(field: str | None = None) -> ModelError:
    """The one-line refusal of a model whose expansion is too large to derive."""
    return ModelError(
        f"expanded, it makes more than {MAX_EXPANDED_TERMS:,} terms (a power of a sum of "
        "n terms to the k makes C(n + k - 1, k)): the model is too large to derive",
        field=field,
    )

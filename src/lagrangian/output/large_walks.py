"""The walks of :mod:`lagrangian.output.large`: Unicode and LaTeX text of a SymEngine tree,
in the notation of :mod:`lagrangian.output.notation` (dots over velocities, sin²θ,
juxtaposed products, accelerations first in a sum) without SymPy's ordering of the rest.
Only ``derive``'s text and LaTeX (and the pages) need them; its JSON does not import them.
"""

from __future__ import annotations

from .notation import SUPERSCRIPT, _split_dots, latex_name, unicode_name

ADD, MUL, POW, ATOM = 1, 2, 3, 4  # binding strength of what a walk returns
NUMBER, SYMBOLIC, OTHER = 0, 1, 2  # a factor's place in a product (see Walk.ordered)


class Walk:
    """Text of a SymEngine tree: one visit per distinct node, whose record is kept.

    A record is the tuple (text, binding strength, rank, factor kind, negative, below):
    the rank is 2 for an expression with an acceleration, 1 with a velocity, 0 otherwise;
    the factor kind orders a product's factors (numbers, then symbols and their powers,
    then the rest); negative is whether the text is a minus sign and the magnitude's text
    (a negative number, or a product with a negative coefficient); below is, for a power
    with a negative number as exponent, the record of what it puts in a denominator, and
    for a number the (numerator, denominator) of its magnitude (a product's coefficient).
    Parents read their children's records, so each node's args are read once and each
    child is looked up once per parent: symbols by name (SymEngine's equality of two
    nodes costs 0.4 us, a name's lookup 0.07 us, and the equations of a 100-link chain
    hold 190,000 edges, most of them to symbols).
    """

    def __init__(self):
        import symengine as se

        self.se = se
        self._done: dict = {}  # node -> record, for all but the symbols below the root
        self._symbols: dict = {}  # a symbol's name -> its record
        self._names: dict = {}

    def text(self, node) -> str:
        return self.visit(node)[0]

    def visit(self, node) -> tuple:
        found = self._done.get(node)
        if found is None:
            found = self._done[node] = self._visit(node)
        return found

    def enclosed(self, record: tuple, strength: int) -> str:
        """The text of ``record``, parenthesized where it binds less than ``strength``."""
        return self.parenthesized(record[0]) if record[1] < strength else record[0]

    def _visit(self, node) -> tuple:
        se = self.se
        kind = type(node)
        if kind is se.Symbol:
            name = node.name
            return self.symbol(name), ATOM, _split_dots(name)[1], SYMBOLIC, False, None
        if node.is_Number:
            text = str(node)
            negative = bool(node < 0)
            if kind is se.Rational or "/" in text:
                text, strength = self.rational(node), ADD if negative else MUL
            else:
                strength = ADD if negative else ATOM
            magnitude = -node if negative else node
            fraction = (1, 1) if magnitude == 1 else _fraction(magnitude)
            return text, strength, 0, NUMBER, negative, fraction
        args = node.args
        done, symbols, symbol = self._done, self._symbols, se.Symbol
        records = []
        rank = 0
        for arg in args:
            if type(arg) is symbol:
                name = arg.name
                record = symbols.get(name)
                if record is None:
                    record = symbols[name] = self._visit(arg)
            else:
                record = done.get(arg)
                if record is None:
                    record = done[arg] = self._visit(arg)
            if record[2] > rank:
                rank = record[2]
            records.append(record)
        if kind is se.Add:
            return self.add(records), ADD, rank, OTHER, False, None
        if kind is se.Mul:
            text, negative = self.mul(args, records)
            return text, ADD if negative else MUL, rank, OTHER, negative, None
        if kind is se.Pow:
            base, exponent = args
            factor_kind = SYMBOLIC if type(base) is se.Symbol else OTHER
            if records[1][3] == NUMBER and records[1][4]:  # 1/x: a product with a denominator
                below = records[0] if exponent == -1 else self.visit(base ** (-exponent))
                text = self.product([], [below])
                return text, MUL, rank, factor_kind, False, below
            text, strength = self.power(base, exponent, records)
            return text, strength, rank, factor_kind, False, None
        if not args:
            return self.constant(node), ATOM, rank, OTHER, False, None
        return self.function(type(node).__name__, records), ATOM, rank, OTHER, False, None

    def add(self, records: list) -> str:
        """Accelerations first, then velocities, then the rest; alphabetical within each."""
        terms = []
        for text, strength, rank, _, negative, _ in records:
            if negative:
                text = text[1:]  # the magnitude: what the minus sign is put before
            elif strength < MUL:
                text = self.parenthesized(text)
            terms.append((-rank, text, negative))
        terms.sort()
        parts = []
        for _, text, negative in terms:
            if parts:
                parts.append((" - " if negative else " + ") + text)
            else:
                parts.append(("-" if negative else "") + text)
        return "".join(parts)

    def ordered(self, factors: list) -> list[str]:
        """Numbers, parameters, then the rest; velocities and accelerations last
        (``factors`` holds records and Python ints)."""
        keyed = []
        for factor in factors:
            if isinstance(factor, int):
                keyed.append((0, 0, str(factor)))
            else:
                text = factor[0] if factor[1] >= MUL else self.parenthesized(factor[0])
                keyed.append((factor[2], factor[3], text))
        keyed.sort()
        return [key[2] for key in keyed]

    def factors(self, factors: list) -> str:
        return " ".join(self.ordered(factors))

    def mul(self, args, records: list) -> tuple[str, bool]:
        """The text of a product (its minus sign in front) and whether it is negative."""
        first = records[0]
        if first[3] == NUMBER:  # the coefficient
            negative, (numerator, denominator) = first[4], first[5]
        else:
            negative, numerator, denominator = False, 1, 1
        top, bottom = [], []
        if numerator != 1:  # an int, or a number that is no fraction (a float)
            top.append(numerator if isinstance(numerator, int) else self.visit(numerator))
        if denominator != 1:
            bottom.append(denominator)
        for record in records:
            if record[3] == NUMBER:
                continue
            if record[5] is not None:
                bottom.append(record[5])
            else:
                top.append(record)
        text = self.product(top, bottom)
        return ("-" + text if negative else text), negative

    def function_name(self, name: str) -> str:
        return {"Abs": "abs"}.get(name, name)


class UnicodeWalk(Walk):
    """Unicode as :class:`~lagrangian.output.notation.UnicodePrinter` writes it."""

    def symbol(self, name: str) -> str:
        found = self._names.get(name)
        if found is None:
            found = self._names[name] = unicode_name(name)
        return found

    def parenthesized(self, text: str) -> str:
        return f"({text})"

    def rational(self, number) -> str:
        return str(number)

    def constant(self, node) -> str:
        return {"pi": "π", "E": "e"}.get(str(node), str(node))

    def product(self, top: list, bottom: list) -> str:
        numerator = self.factors(top) if top else "1"
        if not bottom:
            return numerator
        if len(bottom) == 1 and not isinstance(bottom[0], int):
            denominator = self.enclosed(bottom[0], POW)
        else:
            denominator = self.factors(bottom)
            denominator = denominator if len(bottom) == 1 else f"({denominator})"
        return f"{numerator}/{denominator}"

    def power(self, base, exponent, records: list) -> tuple[str, int]:
        se = self.se
        shown_base, shown_exponent = records
        if base == se.E:
            return f"exp({shown_exponent[0]})", ATOM
        if exponent == se.Rational(1, 2):
            return f"√{self.enclosed(shown_base, ATOM)}", POW
        if exponent.is_Integer and exponent > 1:
            sup = str(exponent).translate(SUPERSCRIPT)
            if base.args and type(base) not in (se.Add, se.Mul, se.Pow) and len(base.args) == 1:
                name = type(base).__name__
                if name != "Abs":
                    return f"{name}{sup}({self.text(base.args[0])})", ATOM  # sin²(θ)
            return f"{self.enclosed(shown_base, ATOM)}{sup}", POW
        base_text = self.enclosed(shown_base, ATOM)
        return f"{base_text}^{self.enclosed(shown_exponent, ATOM)}", POW

    def function(self, name: str, records: list) -> str:
        if name == "Abs":
            return f"|{records[0][0]}|"
        return f"{name}({', '.join(record[0] for record in records)})"


class LatexWalk(Walk):
    """LaTeX as :class:`~lagrangian.output.notation.DotLatexPrinter` writes it."""

    FUNCTIONS = frozenset(("sin", "cos", "tan", "exp", "log", "sinh", "cosh", "tanh"))

    def symbol(self, name: str) -> str:
        found = self._names.get(name)
        if found is None:
            found = self._names[name] = latex_name(name)
        return found

    def parenthesized(self, text: str) -> str:
        return rf"\left({text}\right)"

    def rational(self, number) -> str:
        numerator, denominator = _fraction(abs(number))
        sign = "-" if number < 0 else ""
        return rf"{sign}\frac{{{numerator}}}{{{denominator}}}"

    def constant(self, node) -> str:
        return {"pi": r"\pi", "E": "e"}.get(str(node), str(node))

    def product(self, top: list, bottom: list) -> str:
        numerator = self.factors(top) if top else "1"
        if not bottom:
            return numerator
        return rf"\frac{{{numerator}}}{{{self.factors(bottom)}}}"

    def power(self, base, exponent, records: list) -> tuple[str, int]:
        se = self.se
        shown_base, shown_exponent = records
        shown = shown_exponent[0]
        if base == se.E:
            return f"e^{{{shown}}}", POW
        if exponent == se.Rational(1, 2):
            return rf"\sqrt{{{shown_base[0]}}}", ATOM
        if exponent.is_Integer and len(base.args) == 1 and type(base).__name__ in self.FUNCTIONS:
            name = type(base).__name__
            return rf"\{name}^{{{shown}}}{{\left({self.text(base.args[0])} \right)}}", ATOM
        return f"{self.enclosed(shown_base, ATOM)}^{{{shown}}}", POW

    def function(self, name: str, records: list) -> str:
        inner = ", ".join(record[0] for record in records)
        if name == "Abs":
            return rf"\left|{{{inner}}}\right|"
        command = rf"\{name}" if name in self.FUNCTIONS else rf"\operatorname{{{name}}}"
        return rf"{command}{{\left({inner} \right)}}"


def _fraction(number) -> tuple:
    """(numerator, denominator) of a positive SymEngine number as Python ints, or (x, 1)."""
    text = str(number)
    if "/" in text:
        top, bottom = text.split("/")
        return int(top), int(bottom)
    return (int(text) if text.isdigit() else number), 1

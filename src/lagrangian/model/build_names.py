"""The names and expressions of a model being built: its coordinates' symbols, declared
functions and parameters, the namespace the safe parser reads, and each expression parsed
(or a user's SymPy expression adopted) and checked: what it may depend on, and that its
numbers are doubles.  :class:`ModelNames` is the first half of :mod:`.build`'s builder,
which assembles the energies and the :class:`~.system.System` from what it resolves.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping, Sequence

import sympy
from sympy.core.function import AppliedUndef

from ..errors import ModelError, ParseError
from ..parsing import (
    DeclaredFunction,
    Namespace,
    Terms,
    parse_expression,
    referenced_names,
)
from ..parsing.constants import NotRealError, RealConstants
from ..symbols import (
    TIME_NAME,
    is_identifier,
    parameter_symbol,
    time_symbol,
)
from .inputs import input_entries, input_parameters
from .naming import RESERVED, coordinates_named, parameter_entry, warn_of_likely_typos
from .spec import (
    COORDINATES,
    PARAMETERS,
    TIME,
    VELOCITIES,
    ModelSpec,
    expression_fields,
)
from .system import FunctionDeclaration, Parameter

#: log10 of the largest double and of the smallest (subnormal) one.
_LARGEST_DIGITS = math.log10(sys.float_info.max)
_SMALLEST_DIGITS = math.log10(math.ulp(0.0))


class ModelNames:
    """The names, namespace and expressions of ``spec`` (``trees``: the syntax trees of
    the parsed expressions, kept for the dimension check of a model with units)."""

    def __init__(self, spec: ModelSpec, trees: dict | None = None):
        self.spec = spec
        self.trees = trees  # the syntax trees, kept for the dimension check (with units)
        self.terms = Terms()  # terms of the texts' sums, each built once (a chain repeats them)
        self.coordinates = coordinates_named(spec.coordinates)
        self.names = self._base_names()
        self.functions = self._functions()
        self.parameters = self._parameters()
        self.parameters += input_parameters(
            spec.inputs, self._check_new_name, {p.name for p in self.parameters}
        )
        self.namespace = self._namespace()

    # -- names ---------------------------------------------------------------
    def _base_names(self) -> dict[str, tuple[sympy.Expr, str]]:
        names: dict[str, tuple[sympy.Expr, str]] = {TIME_NAME: (time_symbol(), TIME)}
        for c in self.coordinates:
            names[c.name] = (c.q, COORDINATES)
            names[c.q_dot.name] = (c.q_dot, VELOCITIES)
            names[c.q_ddot.name] = (c.q_ddot, "accelerations")
        return names

    def _functions(self) -> dict[str, FunctionDeclaration]:
        declared = {}
        if not isinstance(self.spec.functions, Mapping):
            raise ModelError("expected a table of name = [arguments]", field="functions")
        for name, arguments in self.spec.functions.items():
            where = f"functions.{name}"
            self._check_new_name(name, where)
            if isinstance(arguments, str) or not isinstance(arguments, Sequence):
                raise ModelError("expected a list of argument names", field=where)
            symbols = []
            for argument in arguments:
                if argument not in self.names or self.names[argument][1] == "accelerations":
                    raise ModelError(
                        f"argument '{argument}' is not a coordinate, velocity or t", field=where
                    )
                symbols.append(self.names[argument][0])
            declared[name] = FunctionDeclaration(
                name, sympy.Function(name, real=True), tuple(symbols)
            )
        return declared

    def _parameters(self) -> tuple[Parameter, ...]:
        given = self.spec.parameters
        if given is None:
            entries: dict[str, object] = dict.fromkeys(sorted(self._undeclared_names()))
        elif isinstance(given, Mapping):
            entries = dict(given)
        elif isinstance(given, Sequence) and not isinstance(given, str):
            entries = dict.fromkeys(given)
        else:
            raise ModelError("expected a table of name = value", field="parameters")
        parameters = []
        for name, entry in entries.items():
            where = f"parameters.{name}"
            self._check_new_name(name, where)
            value, sign = parameter_entry(entry, where)
            symbol = parameter_symbol(name, positive=(sign == "positive"))
            if sign == "nonnegative":
                symbol = sympy.Symbol(name, nonnegative=True)
            elif sign == "negative":
                symbol = sympy.Symbol(name, negative=True)
            parameters.append(Parameter(name, symbol, value, sign))
        warn_of_likely_typos(
            entries, self.coordinates, declared=given is not None, source=self.spec.source
        )
        return tuple(parameters)

    def _check_new_name(self, name: object, where: str) -> None:
        if not isinstance(name, str) or not is_identifier(name):
            raise ModelError(f"invalid name {name!r}", field=where)
        if name in RESERVED:
            raise ModelError(f"'{name}' is reserved and cannot be declared", field=where)
        if name in self.names or name in getattr(self, "functions", {}):
            raise ModelError(f"'{name}' is declared twice", field=where)

    def _undeclared_names(self) -> set[str]:
        found: set[str] = set()
        for where, value, _ in expression_fields(self.spec):
            if isinstance(value, str):
                try:
                    referenced = referenced_names(value)
                except ParseError as error:
                    raise ModelError(str(error), field=where, text=value) from None
                found |= referenced.symbols
            elif isinstance(value, sympy.Basic):
                found |= {s.name for s in value.free_symbols if isinstance(s, sympy.Symbol)}
        inputs = {name for name, _, _ in input_entries(self.spec.inputs)}
        return found - set(self.names) - set(self.functions) - inputs - RESERVED

    def _namespace(self) -> Namespace:
        symbols = {name: symbol for name, (symbol, _) in self.names.items()}
        symbols.update({p.name: p.symbol for p in self.parameters})
        symbols.update({f.name: f.applied for f in self.functions.values()})
        functions = {
            f.name: DeclaredFunction(f.function, f.arguments) for f in self.functions.values()
        }
        return Namespace(symbols=symbols, functions=functions)

    def _category(self, symbol: sympy.Symbol) -> str:
        entry = self.names.get(symbol.name)
        return entry[1] if entry else PARAMETERS

    # -- expressions -----------------------------------------------------------
    def expr(self, value: object, where: str, allowed: frozenset[str]) -> sympy.Expr:
        """Parse or adopt one expression and check what it depends on."""
        if isinstance(value, bool) or value is None:
            raise ModelError(f"expected an expression, got {value!r}", field=where)
        if isinstance(value, str):
            try:
                result = parse_expression(value, self.namespace, trees=self.trees, terms=self.terms)
            except ParseError as error:
                raise ModelError(str(error), field=where, text=value) from None
        elif isinstance(value, int):
            result = sympy.Integer(value)
        elif isinstance(value, float):
            if not math.isfinite(value):
                raise ModelError(f"expected a finite number, got {value!r}", field=where)
            result = sympy.Rational(repr(value))
        elif isinstance(value, sympy.Expr):
            result = self._adopt(value, where)
        else:
            raise ModelError(
                f"expected an expression, got {type(value).__name__}", field=where, text=str(value)
            )
        beyond = _beyond_double(self.terms.union(result, _numbers))
        if beyond is not None:
            raise ModelError(
                f"the number {beyond} is beyond double precision",
                field=where,
                text=value if isinstance(value, str) else str(value),
            )
        for symbol in self.free_symbols(result):
            category = self._category(symbol)
            if category not in allowed:
                raise ModelError(
                    f"'{symbol}' ({category}) is not allowed here; this field may depend on "
                    + ", ".join(sorted(allowed)),
                    field=where,
                    text=value if isinstance(value, str) else str(value),
                )
        return result

    def free_symbols(self, expr: sympy.Basic) -> set:
        """``expr.free_symbols``, each term of a sum looked at once per model (they recur)."""
        return self.terms.union(expr, _free_symbols)

    def _adopt(self, value: sympy.Expr, where: str) -> sympy.Expr:
        """Rebind the symbols of a user's SymPy expression to the model's, by name."""
        table = self.namespace.symbols
        mapping = {}
        for symbol in value.free_symbols:
            if symbol.name not in table:
                raise ModelError(f"unknown symbol '{symbol.name}'", field=where, text=str(value))
            mapping[symbol] = table[symbol.name]
        adopted = value.xreplace(mapping)
        for applied in adopted.atoms(AppliedUndef):
            declared = self.functions.get(applied.func.__name__)
            if declared is None:
                raise ModelError(
                    f"undeclared function '{applied.func.__name__}'", field=where, text=str(value)
                )
            adopted = adopted.xreplace({applied: declared.function(*applied.args)})
        try:  # the parser checks this as it builds; a SymPy expression is checked whole
            RealConstants().check(adopted)
        except NotRealError as error:
            raise ModelError(
                f"{error.subexpression} {error.reason}", field=where, text=str(value)
            ) from None
        return adopted


def _numbers(expr: sympy.Basic) -> set:
    return expr.atoms(sympy.Number)


def _free_symbols(expr: sympy.Basic) -> set:
    return expr.free_symbols


def _beyond_double(numbers: set) -> str | None:
    """A number of ``numbers`` (an expression's) outside the range of doubles (shown
    short), or None."""
    for number in numbers:
        if number == 0 or not number.is_finite:
            continue
        if number.is_Rational:
            digits = math.log10(abs(number.p)) - math.log10(number.q)
        else:
            digits = float(sympy.log(abs(number), 10).evalf(15))
        if digits > _LARGEST_DIGITS or digits < _SMALLEST_DIGITS:
            shown = str(number)
            return shown if len(shown) <= 24 else f"{shown[:12]}... (about 10^{digits:.4g})"
    return None

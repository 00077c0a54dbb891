"""Bounded simplification: cheap, predictable steps that make equations readable.

SymPy's ``simplify`` can run for hours on a mid-sized mechanical expression, so
nothing here calls it.  :func:`tidy` expands products (never powers of sums,
which could explode), optionally tries ``trigsimp`` on small expressions and
keeps its result only when it is shorter, and writes the result the way a
textbook does: terms with the same dependence on the state grouped, with the
parameter coefficient factored ((m1 + m2) g sin(theta1)).  Every step is
skipped above a fixed operation count, so the cost is bounded; sizes are
measured by :func:`lagrangian.sizes.ops_exceed`, which stops counting at the
limit (SymPy's ``count_ops`` alone walks a huge tree for minutes).
"""

from __future__ import annotations

import functools
import hashlib
from collections.abc import Iterable

import sympy
from sympy.core.function import AppliedUndef

from .sizes import MAX_EXPANDED_TERMS, exceeds, expanded_terms, ops_exceed

#: Largest operation count handed to ``trigsimp`` (tens of milliseconds at this size).
TRIGSIMP_MAX_OPS = 120
#: Longest number (digits) handed to ``trigsimp``: it factors polynomials by Wang's
#: algorithm, which looks for a prime above the coefficients (``nextprime`` of a
#: 600-digit bound took minutes for an inertia of 10**300).
TRIGSIMP_MAX_DIGITS = 30
#: Largest operation count for which ``expand`` and grouping are attempted at all.
EXPAND_MAX_OPS = 4_000
#: Largest coefficient (operation count) that is factored.
FACTOR_MAX_OPS = 40
#: Largest tree (nodes) that ``tidy`` looks at: above, nothing it tries pays for its cost.
TIDY_MAX_NODES = 20_000


def expand_products(expr: sympy.Expr) -> sympy.Expr:
    """Distribute products over sums, but never expand ``(a + b)**n``."""
    if ops_exceed(expr, EXPAND_MAX_OPS):
        return expr
    if expanded_terms(expr, TIDY_MAX_NODES, powers=False) > TIDY_MAX_NODES:
        return expr  # a product of many sums: past readable long before it is made
    return sympy.expand(
        expr, deep=True, mul=True, multinomial=False, power_exp=False, power_base=False, log=False
    )


def as_expression(value: sympy.Basic | int | float) -> sympy.Expr:
    """A SymPy number for a Python number; SymPy objects pass through (never parses text)."""
    if isinstance(value, sympy.Basic):
        return value
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise TypeError(f"expected a SymPy expression or a number, got {type(value).__name__}")
    return sympy.Integer(value) if isinstance(value, int) else sympy.Float(value)


def tidy(expr: sympy.Expr, state: Iterable[sympy.Symbol] = (), *, trig: bool = False) -> sympy.Expr:
    """A readable, equal form of ``expr`` computed in bounded time.

    ``state``: the symbols (q, q', q'', t) whose terms are grouped; with
    ``trig``, trigonometric identities (sin^2 + cos^2 = 1, angle sums) are
    applied when they make the expression shorter.
    """
    if expr.is_Number or exceeds(expr, TIDY_MAX_NODES):
        return expr
    expanded = expand_products(expr)
    if trig and expanded.has(sympy.sin, sympy.cos) and not _expands_far(expanded):
        expanded = _angle_sums_combined(squares_combined(expanded))
        ops = sympy.count_ops(expanded)
        short = not _has_long_numbers(expanded, TRIGSIMP_MAX_DIGITS)
        if ops <= TRIGSIMP_MAX_OPS and short and _has_trig_products(expanded):
            candidate = sympy.trigsimp(expanded)
            if sympy.count_ops(candidate) < ops:
                expanded = expand_products(candidate)
    state = tuple(state)
    if state and isinstance(expanded, sympy.Add):
        return group_by_state(expanded, state)
    return sympy.factor_terms(expanded)


def _has_long_numbers(expr: sympy.Expr, digits: int) -> bool:
    """Some rational of ``expr`` has a numerator or denominator longer than ``digits``."""
    bound = 10**digits
    return any(abs(r.p) >= bound or r.q >= bound for r in expr.atoms(sympy.Rational))


def _angle_sums_combined(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` with cos a cos b + sin a sin b -> cos(a - b) and cos^2 + sin^2 -> 1 applied.

    The one rule behind most of what ``trigsimp`` finds in mechanics (a chain's
    mass matrix), linear in the number of terms; kept only when it is shorter.
    """
    if expanded_terms(expr, TIDY_MAX_NODES) > TIDY_MAX_NODES:
        return expr  # the rule needs the full expansion: too long to read, let alone make
    converted = to_symengine(expr)
    if converted is None:
        return expr
    symbols = {s.name: s for s in expr.free_symbols}
    # doit: SymPy's own evaluation, so cos(-a + b) is written cos(a - b) as SymPy prints it
    combined = expand_products(to_sympy(combine_angles(converted), symbols).doit())
    return combined if sympy.count_ops(combined) < sympy.count_ops(expr) else expr


def squares_combined(expr: sympy.Expr) -> sympy.Expr:
    """``expr`` with each sum that holds both sin(a)^2 and cos(a)^2 rewritten by
    cos^2 = 1 - sin^2 (or sin^2 = 1 - cos^2) where that makes the sum shorter.

    I1 sin^2 - I3 sin^2 - I3 cos^2 + I3 + M l^2 sin^2 becomes (I1 + M l^2) sin^2: the
    determinant of a top's mass matrix, and every fraction over it.  Linear in the size
    of the sums (one substitution and expansion each), unlike ``trigsimp``.
    """
    return expr.replace(_has_both_squares, _shortest_in_squares)


def _squares(add: sympy.Expr, kind) -> set[sympy.Expr]:
    return {p for p in add.atoms(sympy.Pow) if p.exp == 2 and isinstance(p.base, kind)}


def _has_both_squares(expr: sympy.Expr) -> bool:
    if not expr.is_Add:
        return False
    sines = {p.base.args[0] for p in _squares(expr, sympy.sin)}
    return any(p.base.args[0] in sines for p in _squares(expr, sympy.cos))


def _shortest_in_squares(add: sympy.Expr) -> sympy.Expr:
    best, ops = add, sympy.count_ops(add)
    for kind, other in ((sympy.cos, sympy.sin), (sympy.sin, sympy.cos)):
        rewritten = {p: 1 - other(p.base.args[0]) ** 2 for p in _squares(add, kind)}
        candidate = sympy.expand_mul(add.xreplace(rewritten))
        if sympy.count_ops(candidate) < ops:
            best, ops = sympy.factor_terms(candidate), sympy.count_ops(candidate)
    return best


#: Highest power of a sum that the full expansion behind the angle rule may multiply out:
#: (sin x + x')^1000 would become a thousand terms with 300-digit coefficients.
EXPAND_MAX_POWER = 6


def _expands_far(expr: sympy.Expr) -> bool:
    return any(
        p.base.is_Add and p.exp.is_Integer and abs(p.exp) > EXPAND_MAX_POWER
        for p in expr.atoms(sympy.Pow)
    )


_TRIG = (sympy.sin, sympy.cos, sympy.tan, sympy.cot, sympy.sec, sympy.csc)


def _has_trig_products(expr: sympy.Expr) -> bool:
    """Some term holds two trigonometric factors (or a power of one): what trigsimp works on.

    With at most one simple trigonometric factor per term, no identity shortens the
    sum, and ``trigsimp`` (tens of milliseconds per call) is skipped.
    """
    for term in sympy.Add.make_args(expr):
        count = 0
        for factor in sympy.Mul.make_args(term):
            base, exponent = factor.as_base_exp()
            if isinstance(base, _TRIG):
                count += 1 if exponent == 1 else 2
            elif factor.has(*_TRIG):
                count += 2  # inside a sum or a function: let trigsimp look
        if count >= 2:
            return True
    return False


def group_by_state(expr: sympy.Expr, state: tuple[sympy.Symbol, ...]) -> sympy.Expr:
    """Collect the terms of a sum by their state-dependent part, factoring each coefficient.

    g*m1*sin(theta1) + g*m2*sin(theta1) -> g*(m1 + m2)*sin(theta1).
    """
    if ops_exceed(expr, EXPAND_MAX_OPS):
        return expr
    state_set = set(state)
    groups: dict[sympy.Expr, list[sympy.Expr]] = {}
    for term in sympy.Add.make_args(expr):
        coefficient, dependent = [], []
        for factor in sympy.Mul.make_args(term):
            (dependent if factor.free_symbols & state_set else coefficient).append(factor)
        key = sympy.Mul(*dependent)
        groups.setdefault(key, []).append(sympy.Mul(*coefficient))
    terms = []
    for key, coefficients in groups.items():
        coefficient = sympy.Add(*coefficients)
        if len(coefficients) > 1 and sympy.count_ops(coefficient) <= FACTOR_MAX_OPS:
            coefficient = _factored(coefficient)
        terms.append(coefficient * key)
    return sympy.Add(*terms)


def _factored(coefficient: sympy.Expr) -> sympy.Expr:
    """``factor`` of a parameter coefficient; only the common factors when no symbol is squared.

    g l1 m1 + g l1 m2 -> g l1 (m1 + m2) needs no polynomial factorisation (which costs
    milliseconds a call); squares may hide (m1 + m2)^2 and get the full ``factor``.
    """
    for term in sympy.Add.make_args(coefficient):
        if any(not (e == 1 or b.is_Number) for b, e in term.as_powers_dict().items()):
            return sympy.factor(coefficient)
    return sympy.factor_terms(coefficient)


def positive_content(expr: sympy.Expr, state: Iterable[sympy.Symbol]) -> sympy.Expr:
    """The state-free common factor of ``expr`` when it is positive (else 1).

    For m l^2 theta'' + m g l sin(theta) it is m l: dividing an equation
    ``expr = 0`` by it changes nothing but makes it read like the textbook.
    """
    content = sympy.factor_terms(expr).as_independent(*state, as_Add=False)[0]
    coefficient, rest = content.as_coeff_Mul()
    content = abs(coefficient) * rest
    return content if content.is_positive else sympy.Integer(1)


def with_positive_content_outside(expr: sympy.Expr, state: Iterable[sympy.Symbol]) -> sympy.Expr:
    """l1 (m1 + m2 - m2 cos^2(...)) rather than l1 m1 + l1 m2 - l1 m2 cos^2(...)."""
    state = tuple(state)
    content = positive_content(expr, state)
    return content * tidy(expr / content, state)


def tidy_in_velocities(
    expr: sympy.Expr, velocities: Iterable[sympy.Symbol], state: Iterable[sympy.Symbol]
) -> sympy.Expr:
    """``tidy`` of each coefficient of ``expr`` as a polynomial in the velocities.

    After a change of coordinates L is a long sum; simplifying the coefficient of
    each velocity monomial on its own (with trigonometric identities) is cheap
    and recovers m (r'^2 + r^2 theta'^2)/2.  Non-polynomial dependence on the
    velocities falls back to :func:`tidy`.
    """
    velocities, state = tuple(velocities), tuple(state)
    try:
        polynomial = sympy.Poly(expand_products(expr), *velocities)
    except sympy.PolynomialError:
        return tidy(expr, state, trig=True)
    terms = []
    for powers, coefficient in polynomial.terms():
        monomial = sympy.Mul(*(v**k for v, k in zip(velocities, powers, strict=True)))
        terms.append(tidy(coefficient, state, trig=True) * monomial)
    return sympy.Add(*terms)


def tidy_fraction(
    expr: sympy.Expr, state: Iterable[sympy.Symbol] = (), *, trig: bool = False
) -> sympy.Expr:
    """``tidy`` for a quotient: one numerator over one denominator, common factors cancelled.

    (g x y - x (x'^2 + y'^2)) / (x^2 + y^2) rather than a sum of fractions.
    """
    state = tuple(state)
    if ops_exceed(expr, EXPAND_MAX_OPS):
        return expr
    numerator, denominator = sympy.fraction(sympy.together(expr))
    if not any(_is_polynomial_factor(f) for f in sympy.Mul.make_args(denominator)):
        # a monomial denominator, or a root like (x^2 + y^2)^(3/2): keep a sum of terms
        return tidy(expr, state, trig=trig)
    common = sympy.gcd(positive_content(numerator, state), positive_content(denominator, state))
    numerator = tidy(numerator / common, state, trig=trig)
    denominator = with_positive_content_outside(tidy(denominator / common, state, trig=trig), state)
    return numerator / _shorter_trig_factors(denominator)


def _squares_swapped(expr: sympy.Expr) -> list[sympy.Expr]:
    """``expr`` with every cos(u)^2 written 1 - sin(u)^2, and with every sin(u)^2 written
    1 - cos(u)^2, each expanded (cheap where trigsimp is not, and deterministic)."""
    u = sympy.Wild("u")
    forms = []
    for square, other in ((sympy.cos, sympy.sin), (sympy.sin, sympy.cos)):
        swapped = expr.replace(square(u) ** 2, lambda u, other=other: 1 - other(u) ** 2)
        forms.append(sympy.expand(swapped))
    return forms


#: Largest factor of a denominator (operations) that :func:`_shorter_trig_factors` tries.
TRIG_FACTOR_MAX_OPS = 24


def _shorter_trig_factors(denominator: sympy.Expr) -> sympy.Expr:
    """Each small sum of the denominator with a sine or cosine squared, in its shortest
    form by sin^2 + cos^2 = 1: M - m cos^2(theta) + m is M + m sin^2(theta), the
    denominator a textbook writes (the determinant of the cart-pole's mass matrix)."""
    factors = []
    for factor in sympy.Mul.make_args(denominator):
        base, exponent = factor.as_base_exp()
        if (
            base.is_Add
            and base.has(sympy.sin, sympy.cos)
            and not ops_exceed(base, TRIG_FACTOR_MAX_OPS)
        ):
            shorter = min(_squares_swapped(base), key=sympy.count_ops)
            if sympy.count_ops(shorter) < sympy.count_ops(base):
                factor = shorter**exponent
        factors.append(factor)
    return sympy.Mul(*factors)


def _is_polynomial_factor(factor: sympy.Expr) -> bool:
    base, exponent = factor.as_base_exp()
    return base.is_Add and exponent.is_Integer


def is_zero(expr: sympy.Expr) -> bool:
    """True when ``expr`` is identically zero after bounded simplification.

    An expression that is not zero at a point of its symbols' domains is not identically
    zero: :func:`nonzero_at_a_point` says so in milliseconds, where simplifying it (a
    sum of products of sines and cosines) takes seconds to reach the same answer."""
    if nonzero_at_a_point(expr):
        return False
    simplified = tidy(expr, trig=True)
    # a float zero (a parameter set to 0.0) is not == 0 in SymPy
    return simplified == 0 or (simplified.is_Number and bool(simplified.is_zero))


def nonzero_at_a_point(expr: sympy.Expr) -> bool:
    """True when ``expr`` has a nonzero value at a point of its symbols' domains (each
    symbol at a value of its sign, fixed by its name), evaluated with 30 and with 50
    significant digits that agree: so it is not identically zero.  False where that is not
    shown (a zero, a point where it is undefined, an unspecified function): the caller
    then decides by simplifying."""
    if not isinstance(expr, sympy.Expr) or expr.has(sympy.Derivative, AppliedUndef):
        return False
    if exceeds(expr, TIDY_MAX_NODES):  # linear in the size, but not unbounded
        return False
    point = {symbol: _probe_value(symbol) for symbol in expr.free_symbols}
    try:  # Floats substituted: each node evaluated once at that precision
        coarse, fine = (
            expr.xreplace({s: sympy.Float(v, digits) for s, v in point.items()}).evalf(digits)
            for digits in (30, 50)
        )
    except (TypeError, ValueError, ZeroDivisionError, ArithmeticError):
        return False
    if not (fine.is_Float and coarse.is_Float) or fine == 0 or not fine.is_finite:
        return False
    return abs(coarse - fine) <= abs(fine) * sympy.Float("1e-20", 50)


def _probe_value(symbol: sympy.Symbol) -> sympy.Rational:
    """A value of ``symbol``'s sign, between 1/2 and 3/2 in size, the same in every run."""
    spread = int(hashlib.sha256(symbol.name.encode()).hexdigest()[:6], 16) % 1000
    size = sympy.Integer(2) if symbol.is_integer else sympy.Rational(500 + spread, 1000)
    return -size if symbol.is_negative or symbol.is_nonpositive else size


# -- large systems: SymEngine arithmetic, converted to and from SymPy exactly --------------

#: Systems with more coordinates than this are assembled and derived with SymEngine
#: (:mod:`lagrangian.derive.fast`); smaller ones keep the readable route above.
FAST_MIN_COORDINATES = 7

_FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sinh", "cosh", "tanh", "asin", "acos", "atan")
#: Converted back with SymPy's evaluation, which knows the signs of the model's symbols
#: (Abs(l) is l for a length); SymEngine leaves their derivatives unevaluated, so
#: results that hold such a derivative are refused (:func:`holds_derivative`).
_EVALUATED = {"Abs": 1, "sign": 1, "atan2": 2}


def to_symengine(expr: sympy.Expr, cache: dict | None = None):
    """``expr`` as a SymEngine expression, or None when it holds something SymEngine lacks.

    Built node by node (symbols by name, exact numbers, the elementary functions),
    so nothing is parsed; ``cache`` shares the work between calls.
    """
    import symengine as se

    cache = {} if cache is None else cache

    def convert(node):
        found = cache.get(node)  # one lookup: a large model's sums meet each term often
        if found is not None:
            return found
        if node.is_Symbol:
            result = se.Symbol(node.name)
        elif node.is_Integer:
            result = se.Integer(int(node))
        elif node.is_Rational:
            result = se.Rational(int(node.p), int(node.q))
        elif node.is_Add:
            result = se.Add(*[convert(a) for a in node.args])
        elif node.is_Mul:
            result = se.Mul(*[convert(a) for a in node.args])
        elif node.is_Pow:
            result = se.Pow(convert(node.base), convert(node.exp))
        elif node is sympy.pi:
            result = se.pi
        elif node is sympy.E:
            result = se.E
        elif node.is_Function and _argument_count(node.func.__name__) == len(node.args):
            result = getattr(se, node.func.__name__)(*(convert(a) for a in node.args))
        else:
            raise _Unsupported
        cache[node] = result
        return result

    try:
        return convert(expr)
    except _Unsupported:
        return None


class _Unsupported(Exception):
    pass


def _argument_count(name: str) -> int | None:
    return 1 if name in _FUNCTIONS else _EVALUATED.get(name)


def holds_derivative(expr) -> bool:
    """Whether a SymEngine expression holds an unevaluated derivative (d|u|/dx, say)."""
    import symengine as se

    return bool(expr.atoms(se.Derivative))


@functools.cache
def _sympy_functions() -> tuple[dict, dict]:
    """SymEngine's function classes -> SymPy's: the elementary ones, the evaluated ones."""
    import symengine as se

    def classes(names):
        return {getattr(se, name): getattr(sympy, name) for name in names}

    return classes(_FUNCTIONS), classes(_EVALUATED)


def applied_unevaluated(function: sympy.FunctionClass, argument: sympy.Expr) -> sympy.Expr:
    """``function(argument, evaluate=False)``, made as SymPy's ``Application.__new__`` does.

    SymEngine's form is already canonical, so SymPy's eval would only redo it slowly;
    and the unevaluated call still builds a new arity set ``FiniteSet(1)`` each time
    (about 18 us, 40x the object itself), which is shared here instead.
    """
    result = sympy.Basic.__new__(function, argument)
    result.nargs = _shared_nargs(function)
    return result


@functools.cache
def _shared_nargs(function: sympy.FunctionClass):
    """The arity set SymPy gives every call of ``function`` (made once)."""
    return function(sympy.Dummy(), evaluate=False).nargs


def to_sympy(expr, symbols: dict[str, sympy.Symbol], cache: dict | None = None) -> sympy.Expr:
    """The SymPy form of a SymEngine expression, with the model's own symbols (by name).

    Shared subexpressions (the sum of the masses below a link) convert once per ``cache``.
    SymEngine's sums and products are already flat, combined and coefficient-first, so
    they are built without SymPy's re-evaluation (the costly part of the conversion).
    """
    import symengine as se

    cache = {} if cache is None else cache
    functions, evaluated = _sympy_functions()

    def convert(node):
        found = cache.get(node)
        if found is not None:
            return found
        kind = type(node)
        if kind is se.Symbol:
            result = symbols.get(node.name) or sympy.Symbol(node.name)
        elif kind is se.Add:  # scalars commute: skip the assumption queries that would say so
            result = sympy.Add._from_args([convert(a) for a in node.args], is_commutative=True)
        elif kind is se.Mul:
            result = sympy.Mul._from_args([convert(a) for a in node.args], is_commutative=True)
        elif kind is se.Pow:
            base, exponent = node.args
            if base == se.E:  # SymEngine's exp(x) is E**x; SymPy's is exp(x)
                result = applied_unevaluated(sympy.exp, convert(exponent))
            else:
                result = sympy.Pow(convert(base), convert(exponent), evaluate=False)
        elif kind in functions:
            result = applied_unevaluated(functions[kind], convert(node.args[0]))
        elif kind in evaluated:
            result = evaluated[kind](*(convert(a) for a in node.args))
        else:
            result = node._sympy_()  # numbers and constants: no symbols inside
        cache[node] = result
        return result

    return convert(expr)


def combine_angles(expr):
    """c cos a cos b + c sin a sin b -> c cos(a - b) and c cos^2 a + c sin^2 a -> c (SymEngine).

    The targeted rule behind the mass matrix of a chain (M_ij ~ l_i l_j cos(theta_i -
    theta_j)), linear in the number of terms where ``trigsimp`` searches; terms it does
    not pair are kept as they are, so the result is always equal to ``expr``.
    """
    import symengine as se

    if expanded_terms(expr) > MAX_EXPANDED_TERMS:
        return expr  # SymEngine's expand, in C++, is out of reach of deadlines and memory limits
    return combine_expanded_angles(se.expand(expr))


def combine_expanded_angles(expanded):
    """:func:`combine_angles` of an expression already expanded (SymEngine)."""
    import symengine as se

    # names bound once: T calls this for each product of two columns (5,050 at n = 100)
    add, mul, pow_, sin, cos, two = se.Add, se.Mul, se.Pow, se.sin, se.cos, se.Integer(2)
    pairs: dict[tuple, dict[type, object]] = {}
    kept = []
    for term in expanded.args if type(expanded) is add else (expanded,):
        rest, trig = [], []
        for factor in term.args if type(term) is mul else (term,):
            kind = type(factor)
            if kind is sin or kind is cos:
                trig.append(factor)
                continue
            if kind is pow_:
                base, exponent = factor.args
                if (type(base) is sin or type(base) is cos) and exponent == two:
                    trig += (base, base)
                    continue
            rest.append(factor)
        if len(trig) != 2 or type(trig[0]) is not type(trig[1]):
            kept.append(term)
            continue
        kind = type(trig[0])
        found = pairs.setdefault((mul(*rest), frozenset(f.args[0] for f in trig)), {})
        if kind in found:
            kept.append(term)
        else:
            found[kind] = term
    for (coefficient, angles), found in pairs.items():
        if len(found) == 2:
            a, b = (*angles, *angles)[:2]
            kept.append(coefficient * cos(a - b))
        else:
            kept += found.values()
    return add(*kept)


def factor_common(terms):
    """The sum of ``terms`` (SymEngine) with the factors common to every term pulled out.

    g l1 m1 + g l1 m2 -> g l1 (m1 + m2): grouping a chain's masses keeps its equations
    O(n^2) in size rather than O(n^3).
    """
    import symengine as se

    total = terms[0] if len(terms) == 1 else se.Add(*terms)
    if type(total) is not se.Add:
        return total
    Mul, Pow = se.Mul, se.Pow
    addends = total.args
    one = se.Integer(1)
    common = {}  # base -> the least positive integer exponent of the terms so far
    for factor in args_of(addends[0], Mul):
        base, exponent = factor.args if type(factor) is Pow else (factor, one)
        if not factor.is_Number and exponent.is_Integer and int(exponent) > 0:
            common[base] = exponent
    for term in addends[1:]:
        if not common:
            return total
        found = {}  # only the bases still common are looked at
        for factor in term.args if type(term) is Mul else (term,):
            if type(factor) is Pow:
                base, exponent = factor.args
                if base in common and exponent.is_Integer and int(exponent) > 0:
                    found[base] = exponent
            elif factor in common:
                found[factor] = one
        common = {b: min(e, found[b]) for b, e in common.items() if b in found}
    if not common:
        return total
    factor = se.Mul(*(b**e for b, e in common.items()))
    return factor * se.Add(*(term / factor for term in addends))


def args_of(expr, kind) -> tuple:
    """The args of ``expr`` where it is of ``kind`` (SymPy's or SymEngine's Add, Mul), else
    ``(expr,)``: the terms of a sum, the factors of a product, without SymPy's make_args."""
    return expr.args if type(expr) is kind else (expr,)

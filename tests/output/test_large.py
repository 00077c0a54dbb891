"""Printing of large systems from their SymEngine form (lagrangian.output.large).

The JSON text must read back with ``sympy.parse_expr`` (DESIGN section 5) and equal
what was derived; checked numerically at random points, entry by entry.
"""

from __future__ import annotations

import json
import random

import pytest
import sympy

import lagrangian as lg
from lagrangian import output
from lagrangian.algebra import FAST_MIN_COORDINATES
from lagrangian.output.large import (
    is_large,
    latex_printer,
    plain_printer,
    symengine_text,
    unicode_printer,
)
from lagrangian.output.large_walks import LatexWalk, UnicodeWalk


def chain(n: int) -> lg.System:
    particles, x, y = [], "0", "0"
    for i in range(1, n + 1):
        x += f" + l{i}*sin(theta{i})"
        y += f" - l{i}*cos(theta{i})"
        particles.append(lg.Particle(f"bob{i}", mass=f"m{i}", position=[x, y]))
    parameters = {f"m{i}": 1.0 + i / 10 for i in range(1, n + 1)}
    parameters |= {f"l{i}": 1.0 for i in range(1, n + 1)} | {"g": 9.81}
    return lg.System.from_particles(
        coordinates=[f"theta{i}" for i in range(1, n + 1)],
        particles=particles,
        gravity=lg.Gravity(g="g", direction=(0, -1)),
        parameters=parameters,
    )


def unusual(n: int = FAST_MIN_COORDINATES) -> lg.System:
    """Large, with the functions and numbers a printer can get wrong."""
    terms = [f"m*x{i}_dot**2/2 - k*x{i}**2/3" for i in range(1, n + 1)]
    terms += [
        "exp(-x1*x2)/7",
        "sqrt(1 + x3**2)*x3_dot",
        "atan2(x4, 1 + x5**2)",
        "Abs(x6 - 2)*x6_dot**2/5",
        "x7_dot*x1/(k + x2**2)**3",
        "pi*cosh(x1)*x2_dot*x1_dot",
    ]
    return lg.System.from_lagrangian(
        " + ".join(terms),
        coordinates=[f"x{i}" for i in range(1, n + 1)],
        parameters={"m": 1.5, "k": 0.7},
    )


def read_back(text: str, system: lg.System) -> sympy.Expr:
    names = {s.name: s for s in system.state_symbols}
    names |= {c.q_ddot.name: c.q_ddot for c in system.coordinates}
    names |= {name: sympy.Symbol(name) for name in system.parameter_names}
    for name, symbol in dict(system.symbols).items():
        names.setdefault(name, symbol)
    return sympy.parse_expr(text, local_dict=names)  # trusted: our own output


def same_value(a: sympy.Expr, b: sympy.Expr, rng: random.Random) -> bool:
    symbols = sorted(a.free_symbols | b.free_symbols, key=str)
    by_name: dict[str, list] = {}
    for s in symbols:
        by_name.setdefault(s.name, []).append(s)
    for _ in range(2):
        point = {}
        for same in by_name.values():
            value = sympy.Float(rng.uniform(0.3, 1.7), 30)
            point |= {s: value for s in same}  # a name means one value, whatever its assumptions
        # numbers in place of the symbols, at 30 digits: SymPy folds them as it rebuilds the
        # tree, 30 times faster than evalf(subs=...) on chain(4)'s q'' (0.8 s, not 29 s)
        x, y = complex(a.xreplace(point)), complex(b.xreplace(point))
        if abs(x - y) > 1e-9 * (1 + abs(y)):
            return False
    return True


@pytest.mark.parametrize("make", [lambda: chain(8), unusual], ids=["chain8", "unusual"])
def test_json_of_a_large_system_reads_back_equal(make):
    system = make()
    assert is_large(system)
    eom = system.equations_of_motion()
    document = json.loads(json.dumps(output.derive_document(eom)))
    rng = random.Random(12)
    n = len(eom.coordinates)
    pairs = [(document["lagrangian"], system.lagrangian)]
    pairs += list(zip(document["equations"], eom.equations, strict=True))
    matrix = document["mass_matrix"]
    pairs += [(matrix[i][j], eom.mass_matrix[i, j]) for i in range(n) for j in range(n)]
    pairs += [(document["forcing"][i], eom.forcing[i, 0]) for i in range(n)]
    for text, derived in pairs:
        assert same_value(read_back(text, system), derived, rng), text


def test_json_text_is_symengine_form_only_for_large_systems():
    small = lg.load("double_pendulum")
    show = plain_printer(small)
    for expr in small.equations_of_motion().forcing:
        assert show(expr) == str(expr)  # SymPy's own str, unchanged
    large = chain(FAST_MIN_COORDINATES)
    assert is_large(large) and not is_large(small)


@pytest.mark.slow
def test_huge_acceleration_of_a_small_system_reads_back():
    system = chain(4)
    eom = system.equations_of_motion()
    document = output.derive_document(eom)
    rng = random.Random(3)
    for c in eom.coordinates:
        derived = eom.accelerations[c.name]
        assert same_value(read_back(document["accelerations"][c.name], system), derived, rng)


OSCILLATORS = lg.System.from_lagrangian(
    " + ".join(f"m*x{i}_dot**2/2 - k*x{i}**2/2" for i in range(1, 8))
    + " + sqrt(k)*sin(x1)**2*x2_dot - x3_dot*x4_dot/(m*k)",
    coordinates=[f"x{i}" for i in range(1, 8)],
    parameters={"m": 1.0, "k": 2.0},
)


def test_unicode_of_a_large_system_in_textbook_notation():
    x1, x5 = sympy.symbols("x1 x5", real=True)
    show = unicode_printer(OSCILLATORS)
    eom = OSCILLATORS.equations_of_motion()
    assert show(eom.equations[4]) == "m ẍ₅ + k x₅"
    lagrangian = show(OSCILLATORS.lagrangian)
    assert "√k sin²(x₁) ẋ₂" in lagrangian
    assert " - ẋ₃ ẋ₄/(k m)" in lagrangian
    assert lagrangian.startswith("m ẋ")  # velocities before positions
    assert show(sympy.Rational(-3, 4) * x1**3 / x5) == "-3 x₁³/(4 x₅)"


def test_latex_of_a_large_system_with_dots_and_fractions():
    x1, x5 = sympy.symbols("x1 x5", real=True)
    show = latex_printer(OSCILLATORS)
    eom = OSCILLATORS.equations_of_motion()
    assert show(eom.equations[4]) == r"m \ddot{x}_{5} + k x_{5}"
    assert show(sympy.Rational(-3, 4) * x1**3 / x5) == r"-\frac{3 x_{1}^{3}}{4 x_{5}}"
    assert show(sympy.sin(x1) ** 2) == r"\sin^{2}{\left(x_{1} \right)}"
    assert show(sympy.sqrt(x1 + x5)) == r"\sqrt{x_{1} + x_{5}}"


def test_text_and_latex_documents_of_a_large_chain():
    eom = chain(FAST_MIN_COORDINATES + 1).equations_of_motion()
    text = output.format_equations(eom)
    assert "θ̈₁" in text and "**" not in text and "theta" not in text
    latex = output.latex_equations(eom)
    assert r"\ddot{\theta}_{1}" in latex and "**" not in latex
    assert latex.count(r"0 &= ") == FAST_MIN_COORDINATES + 1


def test_each_distinct_entry_of_a_large_mass_matrix_is_written_once():
    """M is symmetric: the JSON's lower triangle is the upper's text, written once (the
    same string), and the same text SymEngine writes for each entry."""
    system = chain(FAST_MIN_COORDINATES)
    eom = system.equations_of_motion()
    rows = eom.symengine.mass_matrix
    show = plain_printer(system)
    for i in range(len(rows)):
        for j in range(i):
            assert show(rows[i][j]) is show(rows[j][i])
            assert show(rows[i][j]) == str(rows[j][i])
    document = output.derive_document(eom)
    assert document["mass_matrix"][2][1] == str(rows[1][2])


class _CountedLookups(dict):
    """A walk's records, counting the lookups made in them."""

    lookups = 0

    def get(self, key, default=None):
        self.lookups += 1
        return super().get(key, default)


@pytest.mark.parametrize("walk", [UnicodeWalk, LatexWalk])
def test_a_walk_reads_each_distinct_node_once(walk):
    """Text and LaTeX make one record per distinct node of an equation and look each
    child up once per parent that holds it (no negated copy of a term, no second lookup
    for its rank): the lookups are the edges of the expression's graph, counted here by
    an independent traversal, plus the root."""
    equation = chain(FAST_MIN_COORDINATES).equations_of_motion().symengine.equations[3]
    distinct, edges, pending = set(), 0, [equation]
    while pending:
        node = pending.pop()
        if node not in distinct:
            distinct.add(node)
            edges += len(node.args)
            pending.extend(node.args)
    printer = walk()
    printer._done, printer._symbols = _CountedLookups(), _CountedLookups()
    text = printer.text(equation)
    assert printer._done.lookups + printer._symbols.lookups == edges + 1
    assert len(printer._done) + len(printer._symbols) == len(distinct)
    assert text == walk().text(equation)


@pytest.mark.parametrize(
    ("walk", "expected"),
    [(UnicodeWalk, "-1.875 x θ₁ + exp(1.0 x)"), (LatexWalk, r"-1.875 \theta_{1} x + e^{1.0 x}")],
)
def test_a_walk_writes_a_float_coefficient(walk, expected):
    """A float is no fraction: it stands in a product as itself (SymPy writes 1.875 too)."""
    import symengine as se

    x, theta1 = se.symbols("x theta1")
    assert (
        walk().text(se.RealDouble(-1.875) * x * theta1 + se.exp(se.RealDouble(1.0) * x)) == expected
    )


@pytest.mark.parametrize("make", [chain, unusual])
def test_an_equation_holds_its_forcing_as_written(make):
    """An equation M q'' - f is SymEngine's own text with f's text put in, not printed
    again: the same string as ``str``, and a marker written for f lands in f's place."""
    forms = make(FAST_MIN_COORDINATES).equations_of_motion().symengine
    reused = 0
    for equation, forcing in zip(forms.equations, forms.forcing, strict=True):
        assert symengine_text(equation, {forcing: str(forcing)}) == str(equation)
        marked = symengine_text(equation, {forcing: "FORCING"})
        reused += marked == str(equation).replace(f"({forcing})", "(FORCING)")
    assert reused >= FAST_MIN_COORDINATES - 1


def test_sums_holding_a_written_sum_print_as_symengine_does():
    """Random sums with a multiple of an inner sum among their terms (and other sums,
    numbers, powers and functions beside it): the text with the inner sum's written text
    put in is SymEngine's ``str`` of the whole, character for character."""
    import symengine as se

    names = [se.Symbol(n) for n in ("x", "theta1", "theta1_dot", "theta2_ddot", "m", "l2")]
    numbers = [se.Integer(-2), se.Integer(3), se.Rational(1, 2), se.Rational(-3, 4)]
    rng = random.Random(5)

    def node(depth: int):
        pick = rng.random()
        if depth == 0 or pick < 0.3:
            return rng.choice(names) if rng.random() < 0.85 else rng.choice(numbers)
        parts = [node(depth - 1) for _ in range(rng.randint(2, 3))]
        if pick < 0.5:
            return se.Add(*parts)
        if pick < 0.8:
            return se.Mul(*parts)
        return se.cos(parts[0]) if pick < 0.9 else parts[0] ** rng.choice([2, -1])

    reused = 0
    for _ in range(400):
        inner = se.Add(*(node(2) for _ in range(rng.randint(2, 5))))
        if type(inner) is not se.Add:
            continue
        scale = rng.choice([se.Integer(-1), se.Integer(2), se.Rational(-1, 3), se.Integer(1)])
        whole = se.Add(*(node(3) for _ in range(rng.randint(0, 6))), scale * inner)
        assert symengine_text(whole, {inner: str(inner)}) == str(whole)
        reused += "MARK" in symengine_text(whole, {inner: "MARK"})
    assert reused > 100


@pytest.mark.parametrize(
    ("write", "walk"), [(output.format_equations, UnicodeWalk), (output.latex_equations, LatexWalk)]
)
def test_the_collector_rests_while_a_large_system_is_walked(write, walk, monkeypatch):
    """A large system's walk keeps its records (tuples, without a cycle among them) alive by
    the hundred thousand, which set off full collections of the whole heap: the collector
    is off at every node the text or LaTeX walk visits, and on again after."""
    import gc

    eom = chain(FAST_MIN_COORDINATES).equations_of_motion()
    visit, collecting = walk._visit, []

    def watched(self, node):
        collecting.append(gc.isenabled())
        return visit(self, node)

    monkeypatch.setattr(walk, "_visit", watched)
    assert gc.isenabled()
    text = write(eom)
    assert len(collecting) > 100 and not any(collecting)
    assert gc.isenabled()
    assert text.count("= ") > FAST_MIN_COORDINATES

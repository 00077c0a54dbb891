"""Long sums split into their terms without a parse (``parsing.split``): the same outcome.

With ``terms=Terms()`` (a model's texts), a plain text's top-level sum is split by one scan
of its signs and parentheses, and only the terms not built before are tokenized and
parsed.  Every text, valid or not, must come out as a fresh parse gives it: the same
value, or the same message at the same position.
"""

from __future__ import annotations

import random

import pytest
import sympy

from lagrangian.errors import ParseError
from lagrangian.parsing import Namespace, ParseLimits, Terms, parse_expression
from lagrangian.parsing import expression as expression_module
from lagrangian.parsing.split import top_level_terms

NAMES = ["x", "y", "a1e", "theta1", "theta2", "l1", "l2"]
NAMESPACE = Namespace(symbols={name: sympy.Symbol(name) for name in NAMES})

# pieces of terms, some of them broken on purpose (an error inside a term, at a sign
# that is not a split, across the split)
ATOMS = ["x", "y", "2", "0.5", "1e-3", "2.5E+2", "1.e-2", ".5e-1", "a1e", "theta1", "l2"]
BROKEN = ["z", "1e-x", "x__y", "(", ")", "*", "sin(", "_x", "−x", "x[1]", "2x", "1e-", ""]


def _term(rng: random.Random, depth: int = 0) -> str:
    roll = rng.random()
    if roll < 0.008:
        return rng.choice(BROKEN)
    if depth > 2 or roll < 0.35:
        return rng.choice(ATOMS)
    if roll < 0.5:
        return f"{_term(rng, depth + 1)}*{_term(rng, depth + 1)}"
    if roll < 0.6:
        return f"{_term(rng, depth + 1)}{rng.choice(['**', '^', '/', '*'])}-{_term(rng, depth + 1)}"
    if roll < 0.75:
        return f"{rng.choice(['sin', 'cos', 'sqrt', 'exp'])}({_sum(rng, depth + 1)})"
    if roll < 0.85:
        return f"({_sum(rng, depth + 1)})"
    return f"{rng.choice(['-', '+', ' - '])}{_term(rng, depth + 1)}"


def _sum(rng: random.Random, depth: int = 0) -> str:
    text = _term(rng, depth)
    for _ in range(rng.randint(0, 6 if depth else 12)):
        text += rng.choice([" + ", " - ", "+", "-", " -  ", "\t+ ", " - -", "+-"]) + _term(
            rng, depth
        )
    return rng.choice(["", " ", "\n"]) + text + rng.choice(["", " "])


def _outcome(text: str, terms: Terms | None = None, limits: ParseLimits | None = None):
    try:
        return parse_expression(text, NAMESPACE, limits or ParseLimits(), terms=terms)
    except ParseError as error:
        return (type(error).__name__, error.message, error.position)


def test_random_texts_come_out_as_a_fresh_parse_gives_them():
    rng = random.Random(36)
    texts = [_sum(rng) for _ in range(100)]
    terms = Terms()  # shared, as a model's texts share it: terms are met again and again
    split = 0
    for text in texts:
        fresh = _outcome(text)
        assert _outcome(text, terms) == fresh, text
        split += top_level_terms(text) is not None
    assert split > 60  # most texts took the split


@pytest.mark.parametrize(
    "text",
    [
        "x + y",
        "  -x + 2*y - 1e-3",
        "x*-y + 2^-x - x/-y",
        "x - -y + +x",
        "sin(x - y) + (x - y)*2",
        "1e-3 + 2.5e+2*x - .5e-1",
        "a1e-3 + x",  # a name ending in e: the sign is an operator
        "x + y)",
        "(x + y",
        "x + ",
        "x +* y",
        "x + z",  # an unknown name in a later term
        "x + y − x",  # a Unicode minus: not split
        "x + 1e-x",
    ],
)
def test_written_cases_come_out_as_a_fresh_parse_gives_them(text):
    terms = Terms()
    _outcome("x + y + 2*y + sin(x - y)", terms)
    assert _outcome(text, terms) == _outcome(text)


def test_the_split_is_the_parsers():
    # each term without the spaces around it
    assert top_level_terms(" -x + 2*y - 1e-3*x") == [(1, 3, False), (6, 9, False), (12, 18, True)]
    assert top_level_terms("x*-y - 2^-x") == [(0, 4, False), (7, 11, True)]
    assert top_level_terms("sin(x - y) + x") == [(0, 10, False), (13, 14, False)]
    assert top_level_terms("x +\t y \n") == [(0, 1, False), (5, 6, False)]
    assert top_level_terms("x") is None  # one term: the parse as before
    assert top_level_terms("x + y)") is None
    assert top_level_terms("x − y + x") is None  # not ASCII


@pytest.fixture
def tokenized(monkeypatch) -> list[str]:
    """The texts handed to the tokenizer, in order."""
    seen: list[str] = []
    tokenize = expression_module.tokenize

    def counting(text, limits):
        seen.append(text)
        return tokenize(text, limits)

    monkeypatch.setattr(expression_module, "tokenize", counting)
    return seen


def test_a_term_is_the_same_term_whatever_the_spaces_around_it(tokenized):
    """A chain's term is the last of one sum (no space after it) and inside the next:
    it is built once, so every sum holds the same object (before: two equal objects,
    which every dict of the checks then compared node by node)."""
    seen = tokenized
    terms = Terms()
    first = _outcome("0 + l1*sin(theta1)", terms)
    second = _outcome("0 + l1*sin(theta1)\t+ l2*sin(theta2) ", terms)
    unicode = _outcome("x − y +  l1*sin(theta1)  + l2*sin(theta2)", terms)  # the full parse
    assert seen[:3] == ["0", "l1*sin(theta1)", "l2*sin(theta2)"]  # then the full parse's
    product = sympy.Symbol("l1") * sympy.sin(sympy.Symbol("theta1"))
    made = {term for term in (*first.args, *second.args, *unicode.args) if term == product}
    assert len(made) == 1 and len({id(term) for term in made}) == 1
    assert [first, second, unicode] == [
        _outcome("0 + l1*sin(theta1)"),
        _outcome("0 + l1*sin(theta1)\t+ l2*sin(theta2) "),
        _outcome("x − y +  l1*sin(theta1)  + l2*sin(theta2)"),
    ]
    assert any(term is next(iter(made)) for term in unicode.args)
    assert any(term is next(iter(made)) for term in second.args)


def test_too_many_tokens_are_refused_where_a_fresh_parse_refuses_them():
    limits = ParseLimits(max_nodes=40)
    terms = Terms()
    assert isinstance(_outcome(" + ".join(["x*y"] * 10), terms, limits), sympy.Expr)  # 39 tokens
    longer = " + ".join(["x*y"] * 11)  # 43 tokens
    assert _outcome(longer, terms, limits) == _outcome(longer, limits=limits)
    assert "more than 40 tokens" in _outcome(longer, terms, limits)[1]


def test_only_the_terms_not_met_before_are_tokenized(tokenized):
    seen = tokenized
    chains = ["0"]
    for i in range(1, 31):
        chains.append(chains[-1] + f" + l{1 + i % 2}*sin(theta{1 + i % 2})")
    terms = Terms()
    split = [_outcome(chain, terms) for chain in chains]
    with_terms = sum(map(len, seen))
    seen.clear()
    assert split == [_outcome(chain) for chain in chains]
    assert with_terms < sum(map(len, seen)) / 20


def test_the_checks_of_a_sum_look_at_each_distinct_term_once(monkeypatch):
    """A model's long sums are checked term by term (numbers, names, infinities), each
    distinct term once, not walked whole for every text (before: atoms of every sum)."""
    walked: list[int] = []
    atoms = sympy.Basic.atoms

    def counted(self, *types):
        walked.append(len(self.args) if isinstance(self, sympy.Add) else 0)
        return atoms(self, *types)

    monkeypatch.setattr(sympy.Basic, "atoms", counted)
    terms = Terms()
    chains = ["0"]
    for i in range(1, 31):
        chains.append(chains[-1] + f" + l{1 + i % 2}*sin(theta{1 + i % 2})*{i}")
    for chain in chains:
        parse_expression(chain, NAMESPACE, terms=terms)
    assert max(walked) == 0  # no sum walked whole


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("x + 10**299*y + 10**299*y", sympy.Symbol("x") + 2 * 10**299 * sympy.Symbol("y")),
        ("x + 10**999*y - 10**999*y", sympy.Symbol("x")),
    ],
)
def test_numbers_made_by_the_sum_are_checked_as_a_fresh_parse_checks_them(text, expected):
    terms = Terms()
    _outcome("x + 10**299*y + y", terms)
    outcome = _outcome(text, terms)
    assert outcome == _outcome(text)
    if isinstance(expected, str):
        assert expected in outcome[1]
    else:
        assert outcome == expected

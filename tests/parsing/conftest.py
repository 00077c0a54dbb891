"""Fixtures of the parser tests."""

from __future__ import annotations

import pytest
import sympy
from parsing_fixtures import NAMESPACE, S

from lagrangian.errors import ParseError
from lagrangian.parsing import Namespace, parse_expression


@pytest.fixture
def ns() -> Namespace:
    return NAMESPACE


@pytest.fixture
def s() -> dict[str, sympy.Symbol]:
    return S


@pytest.fixture
def parse():
    """``parse(text)``: the expression in the test namespace."""
    return lambda text, **kwargs: parse_expression(text, NAMESPACE, **kwargs)


@pytest.fixture
def parse_error():
    """``parse_error(text)``: the ParseError that parsing ``text`` raises."""

    def run(text: str, **kwargs) -> ParseError:
        with pytest.raises(ParseError) as caught:
            parse_expression(text, NAMESPACE, **kwargs)
        return caught.value

    return run

"""The one owner of naming: time ``t``, coordinates ``q``, ``q_dot``, ``q_ddot``, momenta ``p_q``.

Coordinates, velocities and accelerations are plain real SymPy symbols (not
functions of time): the total time derivative is taken by the chain rule,

    d/dt f(q, q', t) = sum_j (df/dq_j q'_j + df/dq'_j q''_j) + df/dt,

which is what the Euler-Lagrange operator needs and is far cheaper than
``dynamicsymbols``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import sympy

TIME_NAME = "t"
VELOCITY_SUFFIX = "_dot"
ACCELERATION_SUFFIX = "_ddot"
MOMENTUM_PREFIX = "p_"

IDENTIFIER = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def time_symbol() -> sympy.Symbol:
    """The symbol of time, ``t`` (real). SymPy symbols are values: every call gives an equal one."""
    return sympy.Symbol(TIME_NAME, real=True)


def velocity_name(coordinate: str) -> str:
    return coordinate + VELOCITY_SUFFIX


def acceleration_name(coordinate: str) -> str:
    return coordinate + ACCELERATION_SUFFIX


def momentum_name(coordinate: str) -> str:
    return MOMENTUM_PREFIX + coordinate


def parameter_symbol(name: str, *, positive: bool) -> sympy.Symbol:
    """A parameter: positive when its default value is positive, otherwise only real."""
    if positive:
        return sympy.Symbol(name, positive=True)
    return sympy.Symbol(name, real=True)


@dataclass(frozen=True)
class Coordinate:
    """A generalized coordinate with its velocity and acceleration symbols."""

    name: str
    q: sympy.Symbol
    q_dot: sympy.Symbol
    q_ddot: sympy.Symbol

    @classmethod
    def named(cls, name: str) -> Coordinate:
        return cls(
            name=name,
            q=sympy.Symbol(name, real=True),
            q_dot=sympy.Symbol(velocity_name(name), real=True),
            q_ddot=sympy.Symbol(acceleration_name(name), real=True),
        )

    @property
    def momentum_name(self) -> str:
        return momentum_name(self.name)

    @property
    def p(self) -> sympy.Symbol:
        """The conjugate momentum symbol p_q (real)."""
        return sympy.Symbol(self.momentum_name, real=True)


def is_identifier(name: str) -> bool:
    return bool(IDENTIFIER.match(name))

"""The namespace the parser tests use: the symbols of a pendulum and a few more."""

from __future__ import annotations

import sympy

from lagrangian.parsing import DeclaredFunction, Namespace

NAMES = [
    "x",
    "y",
    "z",
    "t",
    "m",
    "g",
    "l",
    "k",
    "a",
    "b",
    "theta",
    "phi",
    "omega",
    "mu",
    "lambda",
    "varphi",
    "theta_dot",
    "theta_ddot",
    "phi_dot",
    "x_dot",
    "x_ddot",
    "theta1",
    "theta2",
    "theta1_dot",
    "theta2_dot",
    "m1",
    "m2",
    "l1",
    "l2",
    "l_ab",
    "Theta",
]

S = {name: sympy.Symbol(name, real=True) for name in NAMES}
A = sympy.Function("A", real=True)
V = sympy.Function("V", real=True)
NAMESPACE = Namespace(
    S,
    {
        "A": DeclaredFunction(A, (S["x"], S["y"], S["z"])),
        "V": DeclaredFunction(V, (S["x"],)),
    },
)

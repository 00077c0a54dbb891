"""The namespace the parser tests use: the symbols of a pendulum and a few more."""

from __future__ import annotations

import contextlib
import signal
from collections.abc import Iterator

import sympy

from helpers import timer_handler
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


class ParseDeadline(BaseException):
    """The parser ran past its deadline.

    A BaseException, not an Exception: raised from a signal handler anywhere in
    the parser or SymPy, it cannot be caught by an ``except Exception`` there
    (the builder turns SymPy's own exceptions into ParseErrors).
    """


@contextlib.contextmanager
def hard_deadline(seconds: float, text: str) -> Iterator[None]:
    """Raise :class:`ParseDeadline` naming ``text`` if the block runs longer than ``seconds``."""

    def expired(signum, frame):
        raise ParseDeadline(f"still parsing after {seconds} s: {text[:300]!r}")

    with timer_handler(signal.ITIMER_REAL, signal.SIGALRM, expired, seconds):
        yield

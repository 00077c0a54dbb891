"""The known name that a misspelt one most likely means: ``xdot`` -> ``x_dot``.

Two kinds of slips are recognised.  Other spellings of a velocity or an
acceleration (``xdot``, ``x_d``, ``dx``, ``x_dott``, ``thetadot``, ``xddot``,
``ddx``), whatever the case of the letters; and a name one edit away (a letter
inserted, deleted, replaced or two swapped) from a known name of at least
:data:`MIN_EDIT_LENGTH` characters.  Edits of digits and of the case of a letter
do not count: ``theta0`` or ``l2`` beside ``theta1`` and ``l1``, or ``Theta``
beside ``theta``, are usually other quantities on purpose.
"""

from __future__ import annotations

from collections.abc import Iterable

from lagrangian.symbols import ACCELERATION_SUFFIX, VELOCITY_SUFFIX

MIN_EDIT_LENGTH = 4
"""Shortest known name that a one-edit slip is matched against (``k`` is not a slip of ``x``)."""

_VELOCITY_FORMS = ("{q}dot", "{q}_d", "{q}d", "{q}dott", "{q}_dott", "d{q}", "d_{q}", "{q}dt",
                   "{q}_dt", "d{q}dt", "{q}prime", "{q}_prime")  # fmt: skip
_ACCELERATION_FORMS = ("{q}ddot", "{q}_dd", "{q}dd", "{q}ddott", "{q}_ddott", "dd{q}",
                       "dd_{q}", "d2{q}", "{q}_dddot", "{q}dddot")  # fmt: skip


def likely_meant(name: str, known: Iterable[str]) -> str | None:
    """The name of ``known`` that ``name`` is most likely a slip for, or None.

    >>> likely_meant("xdot", ["x", "x_dot", "x_ddot", "m"])
    'x_dot'
    >>> likely_meant("thetta", ["theta", "theta_dot", "l"])
    'theta'
    >>> likely_meant("k", ["x", "x_dot"]) is None
    True
    """
    return Slips(known).meant(name)


class Slips:
    """:func:`likely_meant` against one list of ``known`` names, for many names: the other
    spellings of each velocity and acceleration are listed once (a model of n coordinates
    checks each of its parameters against 3n names, 12 spellings each)."""

    def __init__(self, known: Iterable[str]):
        self.known = sorted(set(known))
        self.spellings: dict[str, list[str]] = {}  # folded spelling -> candidates, in order
        self.by_length: dict[int, list[str]] = {}  # see _near
        for candidate in self.known:
            for suffix, forms in ((VELOCITY_SUFFIX, _VELOCITY_FORMS),
                                  (ACCELERATION_SUFFIX, _ACCELERATION_FORMS)):  # fmt: skip
                base = candidate.removesuffix(suffix)
                if base == candidate:
                    continue
                if suffix == VELOCITY_SUFFIX and base.endswith("_d"):
                    continue  # x_ddot ends in "_dot" too; it is matched as an acceleration
                for spelling in dict.fromkeys(f.format(q=base).lower() for f in forms):
                    self.spellings.setdefault(spelling, []).append(candidate)

    def meant(self, name: str) -> str | None:
        """The known name (other than ``name``) that ``name`` is most likely a slip for."""
        for candidate in self.spellings.get(name.lower(), ()):
            if candidate != name:
                return candidate
        for candidate in self._near(len(name)):
            if len(candidate) >= MIN_EDIT_LENGTH and _one_slip_apart(name, candidate):
                return candidate
        return None

    def _near(self, length: int) -> list[str]:
        """The known names one character longer or shorter than ``length`` or as long, in
        order: only these can be one slip apart (a model of n coordinates checks its
        parameters against 3n names)."""
        found = self.by_length.get(length)
        if found is None:
            found = [c for c in self.known if abs(len(c) - length) <= 1]
            self.by_length[length] = found
        return found


def _one_slip_apart(a: str, b: str) -> bool:
    """True when ``a`` and ``b`` differ by one edit that is not of a digit or a letter's case."""
    if abs(len(a) - len(b)) > 1 or a == b:
        return False
    start = 0
    while start < min(len(a), len(b)) and a[start] == b[start]:
        start += 1
    if len(a) == len(b):
        if a[start + 1 :] == b[start + 1 :]:  # one replaced character
            return not _digit_or_case(a[start], b[start])
        swapped = a[start : start + 2] == b[start : start + 2][::-1]
        return swapped and a[start + 2 :] == b[start + 2 :]
    longer, shorter = (a, b) if len(a) > len(b) else (b, a)
    if longer[start + 1 :] != shorter[start:]:
        return False
    return not longer[start].isdigit()  # one inserted character


def _digit_or_case(x: str, y: str) -> bool:
    return (x.isdigit() and y.isdigit()) or x.lower() == y.lower()

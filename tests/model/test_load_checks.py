"""The checks a model file passes before it is built cost what the file needs, not more.

A dotted key of more than ``MAX_KEY_PARTS`` parts has that many dots on one line, so a
file without such a line is not scanned for one; a parameter's likely misspelling of a
coordinate's name is looked for among the names one character longer, shorter or as
long (the others cannot be one slip apart).  The outcomes stay as before.
"""

from __future__ import annotations

import random

import pytest

from lagrangian.errors import ModelError
from lagrangian.model import limits
from lagrangian.parsing.suggest import MIN_EDIT_LENGTH, Slips, _one_slip_apart


class _Counted:
    def __init__(self, pattern):
        self.pattern = pattern
        self.calls = 0

    def search(self, text):
        self.calls += 1
        return self.pattern.search(text)


def test_a_file_without_a_line_of_many_dots_is_not_scanned_for_deep_keys(monkeypatch):
    counted = _Counted(limits._DEEP_KEY)
    monkeypatch.setattr(limits, "_DEEP_KEY", counted)
    lines = [f"p{i} = 1.{i}  # a.b.c" for i in range(2_000)] + ["a." * 30 + "b = 1"]
    limits.check_toml_keys("\n".join(lines))
    assert counted.calls == 0  # before: one scan of every position of the text
    deep = "\n".join([*lines, ".".join(["a"] * 40) + " = 1"])
    with pytest.raises(ModelError, match=r"more than 32 parts \(line 2002\)"):
        limits.check_toml_keys(deep)
    assert counted.calls == 1


def test_likely_slips_are_the_ones_every_known_name_gives():
    rng = random.Random(11)
    letters = "abcdeθ_12"
    known = {"".join(rng.choice(letters) for _ in range(rng.randint(1, 9))) for _ in range(300)}
    known |= {"theta1", "theta1_dot", "theta1_ddot", "x_dot"}
    slips = Slips(known)

    def first_of_all(name):  # the search over every known name, in order
        for candidate in sorted(known):
            if len(candidate) >= MIN_EDIT_LENGTH and _one_slip_apart(name, candidate):
                return candidate
        return None

    names = ["".join(rng.choice(letters) for _ in range(rng.randint(1, 10))) for _ in range(2_000)]
    names += [name[:-1] for name in known] + [name + "a" for name in known] + ["thetal"]
    found = 0
    for name in names:
        if name.lower() in slips.spellings:
            continue  # a velocity's other spelling: found before any slip
        expected = first_of_all(name)
        assert slips.meant(name) == expected, name
        found += expected is not None
    assert found > 100

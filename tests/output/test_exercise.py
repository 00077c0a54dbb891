"""The exercise of a page, Python's side: the steps a teacher names, the right answers as
trees the page evaluates (checked against SymPy's values), the command line's option."""

from __future__ import annotations

import json
import math
import random
import re

import pytest
import sympy

import lagrangian as lg
from helpers import slow_where
from lagrangian.cli import ExitStatus, main
from lagrangian.errors import ModelError
from lagrangian.examples import example_path
from lagrangian.output.exercise import (
    NO_CONSTRAINTS,
    NO_FUNCTIONS,
    STEPS,
    exercise_document,
    exercise_steps,
)
from lagrangian.output.page import page_html

CALLS = {"sin": math.sin, "cos": math.cos, "tan": math.tan, "exp": math.exp, "log": math.log,
         "Abs": abs, "cosh": math.cosh, "sinh": math.sinh, "atan": math.atan}  # fmt: skip


def value(tree, env):
    """A tree evaluated as the page does (exercise.js: exerciseValue), written again here."""
    kind, *rest = tree
    if kind == "n":
        return rest[0]
    if kind == "s":
        return env[rest[0]]
    if kind == "+":
        return sum(value(t, env) for t in rest)
    if kind == "*":
        return math.prod(value(t, env) for t in rest)
    if kind == "^":
        return value(rest[0], env) ** value(rest[1], env)
    return CALLS[rest[0]](*(value(t, env) for t in rest[1:]))


def test_steps_named_by_a_teacher():
    assert exercise_steps("all") == STEPS
    assert exercise_steps("equations, kinetic") == ("kinetic", "equations")
    with pytest.raises(ModelError) as caught:
        exercise_steps("kinetic,hamiltonian")
    assert str(caught.value) == (
        "exercise: unknown exercise step 'hamiltonian' (steps: all or kinetic, potential, "
        "lagrangian, equations, separated by commas)"
    )


@pytest.mark.parametrize(
    "name",
    slow_where(["double_pendulum", "rotating_wire_bead", "cart_pole"], lambda n: n.startswith("d")),
)
def test_the_trees_are_the_right_answers(name):
    system = lg.load(name)
    eom = system.equations_of_motion()
    document = exercise_document(eom, STEPS)
    rng = random.Random(7)
    env = {s: rng.uniform(0.3, 1.3) for s in document["names"]["state"]}
    env |= {p["name"]: rng.uniform(0.5, 2.0) for p in document["names"]["parameters"]}
    symbols = dict(system.symbols)
    at = {symbols[n]: v for n, v in env.items()}

    def same(tree, expr):
        assert value(tree, env) == pytest.approx(float(expr.xreplace(at)), rel=1e-9, abs=1e-12)

    same(document["lagrangian"]["tree"], system.lagrangian)
    steps = eom.steps
    for answer, step in zip(document["equations"], steps, strict=True):
        same(answer["shown"], step.equation)
        # the groups add up to the answer, each group its key times a parameter factor
        total = sum(value(g["value"], env) for g in answer["groups"])
        assert total == pytest.approx(value(answer["tree"], env), rel=1e-9, abs=1e-12)
    json.dumps(document, allow_nan=False)  # JSON as it is


MODEL = re.compile(r'<script type="application/json" id="lagrangian-model">(.*?)</script>')


def steps_asked(html: str) -> list[str] | None:
    exercise = json.loads(MODEL.search(html).group(1)).get("exercise")
    return None if exercise is None else exercise["steps"]


@pytest.mark.slow
def test_page_with_exercise_and_without():
    system = lg.load("harmonic_oscillator")
    plain, asked = page_html(system), page_html(system, exercise=("kinetic", "potential"))
    assert steps_asked(plain) is None
    exercise = json.loads(MODEL.search(asked).group(1))["exercise"]
    assert exercise["steps"] == ["kinetic", "potential"]
    assert set(exercise) == {"names", "steps", "notes", "kinetic", "potential"}


def test_command_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("LAGRANGIAN_NO_CACHE", raising=False)
    model = tmp_path / "oscillator.toml"
    model.write_text(example_path("harmonic_oscillator").read_text("utf-8"), "utf-8")
    pages = {}
    for argv in ([], ["--exercise"], ["--exercise", "kinetic"]):
        out = tmp_path / f"page{len(argv)}.html"
        assert main(["page", str(model), *argv, "--out", str(out)]) == ExitStatus.SUCCESS
        pages[tuple(argv)] = out.read_text("utf-8")
    # the cache keeps each apart: a page with an exercise is not the page without
    assert len(set(pages.values())) == 3
    assert steps_asked(pages[("--exercise",)]) == list(STEPS)
    assert steps_asked(pages[("--exercise", "kinetic")]) == ["kinetic"]
    assert steps_asked(pages[()]) is None
    capsys.readouterr()
    status = main(["page", str(model), "--exercise", "kinetik", "--out", str(tmp_path / "x.html")])
    assert status == ExitStatus.BAD_INPUT
    assert capsys.readouterr().err == (
        "lagrangian: error: --exercise: unknown exercise step 'kinetik' (steps: all or kinetic,"
        " potential, lagrangian, equations, separated by commas)\n"
    )
    assert not (tmp_path / "x.html").exists()


def test_what_cannot_be_asked_is_said_and_the_rest_asked():
    functions = lg.loads(
        'name = "f"\ncoordinates = ["x"]\nlagrangian = "x_dot^2/2 - V"\n'
        '[parameters]\n[functions]\nV = ["x"]\n'
    )
    assert exercise_document(functions.equations_of_motion(), ("kinetic",)) == {
        "steps": [],
        "notes": [NO_FUNCTIONS],
    }
    constrained = exercise_document(lg.load("cartesian_pendulum").equations_of_motion(), STEPS)
    assert constrained["steps"] == ["kinetic", "potential", "lagrangian"]
    assert constrained["notes"] == [NO_CONSTRAINTS]
    assert "equations" not in constrained


def test_sympy_constants_become_numbers():
    from lagrangian.output.exercise import tree

    assert tree(sympy.pi * sympy.Symbol("x")) == ["*", ["n", math.pi], ["s", "x"]]

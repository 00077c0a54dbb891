"""The target registry: every target is registered under its own name, the export languages
are the targets that render a file, every target renders the double pendulum and the loaded
ones load it where their package is installed; one cache entry per (fingerprint, target)."""

from __future__ import annotations

import pytest

import lagrangian as lg
from lagrangian.codegen import TARGETS, AbstractLoadedTarget, AbstractTarget, cache
from lagrangian.errors import MissingDependencyError
from lagrangian.export import LANGUAGES
from lagrangian.numeric import compile_equations
from lagrangian.numeric.compile import JIT_BACKENDS


@pytest.fixture(scope="module")
def compiled():
    return compile_equations(lg.load("double_pendulum").equations_of_motion())


def test_every_target_is_registered_under_its_name():
    for name, target in TARGETS.items():
        assert issubclass(target, AbstractTarget)
        assert target.name == name
        assert target.suffix.startswith(".") and target.base in (0, 1)


def test_languages_are_the_targets_that_render_a_file():
    standalone = {name for name, target in TARGETS.items() if target.standalone}
    assert standalone <= set(LANGUAGES)
    assert not {name for name, t in TARGETS.items() if issubclass(t, AbstractLoadedTarget)} & (
        set(LANGUAGES)
    )


def test_jit_backends_are_targets():
    for name, (target, _, _) in JIT_BACKENDS.items():
        assert TARGETS[name] is target


@pytest.mark.parametrize("name", sorted(TARGETS))
def test_every_target_renders_the_double_pendulum(name, compiled):
    target = TARGETS[name]()
    try:
        target.check()
    except MissingDependencyError:
        pytest.skip(f"target {name}: its package is not installed")
    text = target.render(compiled.program, "double_pendulum")
    assert isinstance(text, str) and text


def test_a_compiled_system_keeps_its_program(compiled):
    assert compiled.program.forms is compiled.forms
    again = compile_equations(compiled.equations)
    assert again.program.fingerprint == compiled.program.fingerprint


def test_built_once_per_fingerprint_and_target():
    calls = []
    for _ in range(3):
        value = cache.built("f" * 64, "test-target", lambda: calls.append(1) or len(calls), 1)
    assert value == 1 and calls == [1]
    assert cache.built("f" * 64, "test-target", lambda: 2, 2) == 2  # other options

"""What reaches generated files from the model (issue 21): free text stays inside comments
in every language, constants and large integers are valid literals that give our numbers,
file names that a language would misread are refused, the Baumgarte rate is bounded."""

from __future__ import annotations

import copy
import functools
import math
import re

import numpy as np
import pytest
import sympy

import lagrangian as lg
from lagrangian.codegen.comments import (
    C_COMMENT,
    JULIA_COMMENT,
    MATLAB_COMMENT,
    PYTHON_COMMENT,
    comment_safe,
    commented,
)
from lagrangian.errors import ModelError
from lagrangian.export import export_code, write_code
from lagrangian.numeric import compile_equations

from .test_export import c_library, call_c, close, load_module

HOSTILE_TEXT = [
    "*/ int pwned(void) { return 3; } /*",
    '"""; import sys; sys.exit(3); """',
    "a\nPWNED = 3",
    "a\rPWNED = 3",
    "a\r\nPWNED = 3",
    "a\x00b",
    "a =# PWNED = 3 #= b",
    "%}\nPWNED = 3\n%{",
    "a\u2028PWNED = 3\u2029PWNED = 4",
    "a\x0bPWNED = 3\x0cPWNED = 4\x1cPWNED = 5\x85PWNED = 6",
    "\u202eevil\u202c ??/",
    "coding: utf-7 +AAo-PWNED = 3",
    "\\",
]
STYLES = {"c": C_COMMENT, "numpy": PYTHON_COMMENT, "julia": JULIA_COMMENT, "matlab": MATLAB_COMMENT}
COMMENT_MARK = {"numpy": "#", "julia": "#", "matlab": "%"}


def oscillator(name: str = "benign", description: str = "") -> lg.System:
    """The oscillator with this name and description put in past the model's own check:
    a System refuses control characters as a model file does (tests/model/test_plain_text.py),
    and the export's comments are the second line of defence, tested here on their own."""
    system = copy.copy(lg.System.from_lagrangian("m*x_dot**2/2 - k*x**2/2", coordinates=["x"]))
    object.__setattr__(system, "name", name)
    object.__setattr__(system, "description", description)
    return system


def code_part(text: str, language: str) -> str:
    """The file without its header comment (C: the first /* ... */ block; others: every
    comment line), after checking that the header comment is closed once, at its end."""
    if language == "c":
        head, rest = text.split("\n */\n", 1)
        assert head.startswith("/*\n") and "*/" not in head
        return rest
    mark = COMMENT_MARK[language]
    return "\n".join(line for line in text.splitlines() if not line.startswith(mark))


@pytest.mark.parametrize("language", STYLES)
@pytest.mark.parametrize("text", HOSTILE_TEXT, ids=range(len(HOSTILE_TEXT)))
def test_free_text_changes_only_comments(language, text):
    benign = export_code(oscillator(), language, name="model_rhs")
    hostile = export_code(oscillator(text, text), language, name="model_rhs")
    assert code_part(hostile, language) == code_part(benign, language)
    assert "PWNED" not in code_part(hostile, language)
    for line in hostile.splitlines():  # nothing ends a line but "\n"
        assert line == line.strip("\r\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029") and "\x00" not in line


@pytest.mark.parametrize("language", STYLES)
def test_the_header_is_one_comment(language):
    """Julia's #= =# and MATLAB's %{ %} blocks: every header line is a plain line comment."""
    hostile = export_code(oscillator(HOSTILE_TEXT[6], HOSTILE_TEXT[7]), language, name="m")
    if language in ("julia", "matlab"):
        mark = COMMENT_MARK[language]
        lines = hostile.splitlines()[1:] if language == "matlab" else hostile.splitlines()
        header = lines[: next(i for i, line in enumerate(lines) if not line.startswith(mark))]
        assert all(line == mark or line.startswith(mark + " ") for line in header)
        breaking = STYLES[language].breaking
        assert not any(sequence in line for line in header for sequence in breaking)


def test_hostile_c_compiles_strictly_without_the_injected_function(compiler, tmp_path):
    system = oscillator(HOSTILE_TEXT[0], " ".join(HOSTILE_TEXT))
    lib = c_library(export_code(system, "c"), tmp_path, compiler)
    assert not hasattr(lib, "pwned")
    status, rhs = call_c(lib.rhs, 0.0, [0.5, 0.1], [2.0, 1.0], [], 2)
    assert status == 0 and rhs.tolist() == [0.1, -1.0]


def test_hostile_numpy_module_imports_and_runs_nothing_injected(tmp_path):
    for index, text in enumerate(HOSTILE_TEXT):
        path = write_code(oscillator(text, text), "numpy", tmp_path / f"hostile_{index}.py")
        module = load_module(path)  # a NUL or sys.exit would fail here
        assert not hasattr(module, "PWNED")
        assert module.rhs(0.0, [0.5, 0.1], [2.0, 1.0]).tolist() == [0.1, -1.0]


def test_comment_safe_leaves_no_breaking_sequence():
    for style in STYLES.values():
        for text in [*HOSTILE_TEXT, "*/*/*", "/**/", "????/", "#=#=#", "=##=", "%{%}%", "#{#}"]:
            safe = comment_safe(text, style)
            assert not any(sequence in safe for sequence in style.breaking)
            assert safe.isprintable() or "\ufffd" in safe
    assert commented(["a\nb"], C_COMMENT) == ["/*", " * a", " * b", " */"]


def test_model_files_refuse_control_characters_in_text(tmp_path):
    body = 'coordinates = ["x"]\nlagrangian = "x_dot^2/2"\n'
    path = tmp_path / "model.toml"
    path.write_text('name = "a\\u001bb"\n' + body)
    with pytest.raises(ModelError, match=r"name: control character U\+001B not allowed"):
        lg.load(str(path))
    path.write_text('name = "ok"\ndescription = """\nline one\n\tline two"""\n' + body)
    assert lg.load(str(path)).description == "line one\n\tline two"


# -- constants and large integers -----------------------------------------------------------
CONSTANTS = (
    "k*x^2/2 + sqrt(2)*x + log(2)*x + log(10)*x + 2/pi*x + 1/pi*x + pi*x + E*x + x/sqrt(2)"
    " + 2/sqrt(pi)*x + pi/2*x + pi/4*x + x/log(2) + x*log(E)"
)
HUGE = "k*x^2*(2^64 + 1)/2 + x*10^30 - x^3*10^30/(2^70 + 3) + x^2*(-9223372036854775809)"


@pytest.mark.parametrize("potential", [CONSTANTS, HUGE], ids=["constants", "huge-integers"])
def test_c_compiles_as_c99_and_matches_our_rhs(potential, compiler, tmp_path, np_rng):
    system = lg.System.from_lagrangian(f"m*x_dot^2/2 - ({potential})", coordinates=["x"])
    text = export_code(system, "c")
    assert not re.search(r"\bM_[A-Z0-9_]+", text)
    lib = c_library(text, tmp_path, compiler)  # -std=c99 -pedantic -Wall -Wextra -Werror
    compiled = compile_equations(system.equations_of_motion())
    names = [p.name for p in system.parameters]
    for _ in range(5):
        y = np_rng.uniform(-1.5, 1.5, 2)
        params = dict(zip(names, np_rng.uniform(0.5, 2.0, len(names)), strict=True))
        status, rhs = call_c(lib.rhs, 0.0, y, [params[p] for p in names], [], 2)
        assert status == 0
        assert close(rhs, compiled.rhs(0.0, y, compiled.parameter_vector(params)))


@pytest.mark.parametrize("language", ["numpy", "julia", "matlab"])
def test_no_huge_integer_literal_in_any_language(language):
    system = lg.System.from_lagrangian(f"m*x_dot^2/2 - ({HUGE})", coordinates=["x"])
    text = code_part(export_code(system, language, name="m"), language)
    assert not re.search(r"(?<![\w.])\d{17,}", text), text


def test_numpy_huge_integers_match_our_rhs(tmp_path):
    system = lg.System.from_lagrangian(f"m*x_dot^2/2 - ({HUGE})", coordinates=["x"])
    module = load_module(write_code(system, "numpy", tmp_path / "huge.py"))
    compiled = compile_equations(system.equations_of_motion())
    values = dict(zip(module.PARAMETERS, [1.3, 0.7], strict=True))
    y = np.array([0.4, -0.2])
    ours = compiled.rhs(0.0, y, compiled.parameter_vector(values))
    assert close(module.rhs(0.0, y, [values[p] for p in module.PARAMETERS]), ours)


def test_floats_are_printed_to_read_back_exactly():
    m, k, x, x_dot = sympy.symbols("m k x x_dot")
    lagrangian = m * x_dot**2 / 2 - sympy.Float(1 / 3) * k * x**2
    system = lg.System.from_lagrangian(lagrangian, coordinates=["x"])
    for language in STYLES:
        text = export_code(system, language, name="m")
        assert repr(2 / 3) in text, language  # 0.6666666666666666, not 0.666666666666667


def test_sign_and_its_delta_term_print_in_every_language():
    system = lg.System.from_lagrangian("m*x_dot^2/2 - k*x*sign(x)", coordinates=["x"])
    for language in STYLES:
        text = export_code(system, language, name="m")
        assert "dirac" not in text.lower() and "strict" not in text


# -- file names and the Baumgarte rate ------------------------------------------------------
@pytest.mark.parametrize(
    ("language", "stem", "message"),
    [
        ("matlab", "end", "it is a keyword"),
        ("matlab", "while", "it is a keyword"),
        ("matlab", "rhs", "the file calls 'rhs'"),
        ("matlab", "sqrt", "the file calls 'sqrt'"),
        ("matlab", "mass_matrix", "the file calls 'mass_matrix'"),
        ("matlab", "2model", "needs a name that is an identifier"),
        ("numpy", "numpy", "would be imported instead of Python's 'numpy'"),
        ("numpy", "math", "would be imported instead of Python's 'math'"),
        ("numpy", "scipy", "would be imported instead of Python's 'scipy'"),
        ("numpy", "lambda", "an identifier and not a keyword"),
        ("numpy", "my-model", "an identifier and not a keyword"),
    ],
)
def test_file_names_a_language_would_misread(language, stem, message, tmp_path):
    suffix = ".m" if language == "matlab" else ".py"
    with pytest.raises(ModelError, match=re.escape(message)):
        write_code(lg.load("simple_pendulum"), language, tmp_path / f"{stem}{suffix}")
    assert list(tmp_path.iterdir()) == []


def test_matlab_names_used_by_this_model_are_refused_through_the_api():
    system = lg.System.from_lagrangian("m*x_dot^2/2 - k*cosh(x)", coordinates=["x"])
    with pytest.raises(ModelError, match="the file calls 'cosh'"):
        export_code(system, "matlab", name="cosh")
    for name in ("model", "x", "y", "p_k", "w_0", "q_x"):  # variables of the file: no clash
        assert export_code(system, "matlab", name=name).startswith(f"function model = {name}()")


@functools.cache
def rolling_disc() -> lg.System:
    """The rolling disc, loaded (and its equations derived) once for the tests below: the
    System is immutable and keeps its derivation."""
    return lg.load("rolling_disc")


@pytest.mark.parametrize("alpha", [math.nan, math.inf, -math.inf, -1.0, 1e308, 1.0000001e6])
def test_baumgarte_rate_is_finite_and_bounded(alpha):
    disc = rolling_disc()
    with pytest.raises(ModelError, match=r"^baumgarte: the Baumgarte stabilisation rate alpha"):
        export_code(disc, "c", baumgarte=alpha)
    with pytest.raises(ModelError, match=r"^baumgarte: "):
        compile_equations(disc.equations_of_motion(), baumgarte=alpha)


def test_baumgarte_bounds_are_accepted():
    disc = rolling_disc()
    for alpha in (0.0, 1e6):
        assert "alpha = " in export_code(disc, "c", baumgarte=alpha)


# -- the other generators carry no model text -----------------------------------------------
def test_numba_and_cuda_sources_hold_no_model_text_and_no_math_macros():
    from lagrangian.codegen.forms import symbolic_forms
    from lagrangian.codegen.numba import generated_source
    from lagrangian.ensemble.cuda_source import kernel_source

    system = lg.System.from_lagrangian(
        f"m*x_dot^2/2 - ({CONSTANTS}) - ({HUGE})",
        coordinates=["x"],
        name=HOSTILE_TEXT[0] + "NAMEMARK",
        description="DESCRIPTIONMARK\n" + HOSTILE_TEXT[2],
    )
    forms = symbolic_forms(system.equations_of_motion(), {})
    numba_text = str(generated_source(forms)[1])
    cuda_text = kernel_source(forms, "rk4", "float64")[1]
    for text in (numba_text, cuda_text):
        assert "MARK" not in text and "pwned" not in text and "PWNED" not in text
        assert not re.search(r"\bM_[A-Z0-9_]+", text)
        assert not re.search(r"(?<![\w.])\d{17,}", text)
    compile(numba_text, "generated", "exec")

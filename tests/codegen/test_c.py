"""The one C printer and the one C linear solve (lagrangian.codegen.c), compiled strictly."""

from __future__ import annotations

import ctypes
import math
import re
import subprocess

import numpy as np
import pytest
import sympy

from lagrangian.codegen.c import CPrinter, gaussian_elimination

FLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", "-shared", "-fPIC"]


def built(text, tmp_path, compiler):
    source = tmp_path / "solve.c"
    source.write_text("#include <math.h>\n" + text)
    library = tmp_path / "solve.so"
    subprocess.run([compiler, *FLAGS, str(source), "-o", str(library), "-lm"], check=True,
                   capture_output=True, text=True)  # fmt: skip
    return ctypes.CDLL(str(library))


@pytest.mark.parametrize("precision", ["float64", "float32"])
@pytest.mark.parametrize("n", [1, 2, 5])
def test_elimination_solves_and_flags_singular_matrices(precision, n, compiler, tmp_path, np_rng):
    printer = CPrinter(precision)
    text = gaussian_elimination("solve", n, printer, qualifiers="")
    solve = built(text, tmp_path, compiler).solve
    dtype = np.float32 if precision == "float32" else np.float64
    pointer = ctypes.POINTER(ctypes.c_float if precision == "float32" else ctypes.c_double)
    solve.argtypes, solve.restype = [pointer] * 3 + [ctypes.c_int], ctypes.c_int

    def run(matrix, rhs):
        a, b = (np.array(v, dtype=dtype) for v in (matrix, rhs))  # copies: both overwritten
        x = np.empty(n, dtype=dtype)
        status = solve(*(v.ctypes.data_as(pointer) for v in (a, b, x)), 0)
        return status, x

    matrix = np_rng.uniform(-1, 1, (n, n)) + np.diag(np_rng.uniform(-1, 1, n))
    rhs = np_rng.uniform(-1, 1, n)
    status, x = run(matrix, rhs)
    assert status == 0
    tolerance = 1e-4 if precision == "float32" else 1e-12
    np.testing.assert_allclose(x, np.linalg.solve(matrix, rhs), rtol=tolerance, atol=tolerance)
    assert run(np.zeros((n, n)), rhs)[0] == 1
    assert run(np.full((n, n), np.nan), rhs)[0] == 1
    assert run(np.full((n, n), np.inf), rhs)[0] == 1


def test_printer_precisions():
    x = sympy.Symbol("x")
    expr = sympy.sin(x) ** 2 + sympy.pi * x + sympy.Float(0.1) * x + sympy.E
    double = CPrinter("float64").doprint(expr)
    assert "sin(x)*sin(x)" in double and repr(math.pi) in double and repr(math.e) in double
    single = CPrinter("float32").doprint(expr)
    assert "sinf(x)" in single and "sin(" not in single
    # every floating literal carries the suffix, and no POSIX macro appears
    assert not re.findall(r"\b\d+\.\d*(?:e[-+]?\d+)?(?![\dfFe])", single)
    assert not re.search(r"\bM_[A-Z0-9_]+", double + single)
    with pytest.raises(ValueError):
        CPrinter("float16")

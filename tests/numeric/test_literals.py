"""Numbers in generated code: exact numbers a double cannot hold become floats, and floats
print as text that reads back as the same double."""

from __future__ import annotations

import sympy
from sympy.printing.c import C99CodePrinter
from sympy.printing.pycode import PythonCodePrinter

from lagrangian.codegen.literals import FloatLiterals, machine_numbers

x = sympy.Symbol("x")


def test_exact_numbers_beyond_a_double_become_floats():
    assert machine_numbers(2**53 - 1 + x) == 2**53 - 1 + x  # exact in a double: kept
    big = machine_numbers((2**64 + 1) * x).as_coeff_Mul()[0]
    assert big.is_Float and float(big) == 2.0**64
    small = machine_numbers(x / (2**70 + 3)).as_coeff_Mul()[0]
    assert small.is_Float and float(small) == 1 / (2**70 + 3)
    assert machine_numbers(sympy.Integer(10) ** 400 * x) == sympy.oo * x
    assert machine_numbers(-(sympy.Integer(10) ** 400) * x) == -sympy.oo * x


def test_floats_read_back_as_the_same_double():
    class Printer(FloatLiterals, PythonCodePrinter):
        pass

    for value in (1 / 3, 2 / 3, 0.1, 1e-300, 1.7976931348623157e308, -2.5):
        assert float(Printer().doprint(sympy.Float(value))) == value
    assert PythonCodePrinter().doprint(sympy.Float(1 / 3)) != repr(1 / 3)  # why it exists

    class CPrinter(FloatLiterals, C99CodePrinter):
        pass

    assert CPrinter().doprint(sympy.Float("1e400")) == "INFINITY"

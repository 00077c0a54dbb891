"""No module of the package evaluates Python: no eval, exec, sympify, parse_expr or S(...).

The source is read as Python syntax trees, so the names may appear in comments
and docstrings, but never as a call (or, for SymPy's parsers, even as a name).
Nothing is allowlisted.
"""

from __future__ import annotations

import ast
from pathlib import Path

import lagrangian

PACKAGE = Path(lagrangian.__file__).parent
CALLS = frozenset({"eval", "exec", "compile", "__import__", "sympify", "parse_expr", "S"})
NAMES = frozenset({"sympify", "parse_expr", "parse_latex", "eval", "exec"})


def _called_name(node: ast.Call) -> str | None:
    if isinstance(node.func, ast.Name):
        return node.func.id
    if isinstance(node.func, ast.Attribute):
        return node.func.attr
    return None


def _violations(source: str, filename: str) -> list[str]:
    found = []
    for node in ast.walk(ast.parse(source, filename)):
        where = f"{filename}:{getattr(node, 'lineno', '?')}"
        if isinstance(node, ast.Call):
            name = _called_name(node)
            if name in CALLS and not (
                name == "compile" and isinstance(node.func, ast.Attribute)  # re.compile
            ):
                found.append(f"{where}: call of {name}")
        elif isinstance(node, ast.Name) and node.id in NAMES:
            found.append(f"{where}: name {node.id}")
        elif isinstance(node, ast.Attribute) and node.attr in NAMES - {"eval"}:
            found.append(f"{where}: attribute {node.attr}")
        elif isinstance(node, ast.alias) and node.name.split(".")[-1] in NAMES:
            found.append(f"{where}: import of {node.name}")
    return found


def test_the_package_is_found():
    assert (PACKAGE / "parsing" / "parser.py").is_file()


def test_no_module_evaluates_python():
    problems = []
    for path in sorted(PACKAGE.rglob("*.py")):
        problems += _violations(path.read_text(encoding="utf-8"), str(path.relative_to(PACKAGE)))
    assert problems == []


def test_the_check_finds_what_it_looks_for():
    bad = """
import sympy
from sympy import sympify
from sympy.parsing.sympy_parser import parse_expr
eval(text)
exec(code)
sympy.sympify(text)
sympy.S(text)
S(text)
f = sympy.parsing.sympy_parser.parse_expr
__import__("os")
"""
    found = _violations(bad, "bad.py")
    assert len(found) >= 9
    good = 're.compile("x")\nsympy.S.Zero\nx.evalf()\n"""eval(text) in a docstring"""\n'
    assert _violations(good, "good.py") == []

"""Code generation: one program form of the equations, printed (and loaded) by targets.

The layer.  ``codegen`` sits between ``analysis`` and ``numeric`` (the contract in
pyproject.toml, checked by ``lint-imports``): it reads an
:class:`~lagrangian.derive.EquationsOfMotion` and imports nothing above it.  ``numeric``
compiles through it, ``integrate`` and ``ensemble`` read what it made, and
``lagrangian.export`` (``export_code``, ``write_code``, ``LANGUAGES``) is its face for files.

The data flow, one module each:

    forms.py        SymbolicForms: M and f of M q'' = f, L, p, Q, h, the constraints,
                    declared functions replaced by their definitions (definitions.py);
                    the Baumgarte rate of the constraints' stabilisation
    program.py      Program: the forms' symbols renamed for every language (q_x, v_x, p_g,
                    u_F, t), the routines mass_matrix, forcing and dynamics with their
                    common subexpressions taken out once (sympy.cse, w_0, w_1, ...), made
                    on first use; and the one fingerprint (sha256 of the expressions)
    schemes.py      the entries the fixed-step schemes need (rk4, midpoint, Stormer-Verlet)
    steps.py        the fixed-step schemes and the one linear solve (Gaussian elimination
                    with partial pivoting) written once as a small program, printed as C,
                    numba and JavaScript; arrays.py walks it over NumPy / JAX arrays (and
                    heyoka's expressions); loops.py writes numba_loop.py (the template of
                    the compiled fixed-step loops: the ensemble's and the single run's)
    target.py       the Target protocol (below)
    cache.py        one in-memory cache keyed by (fingerprint, target, options), and the
                    checked on-disk cache of generated modules
    literals.py     floats that read back exactly, integers beyond a double
    comments.py     the model's free text kept inside comments; header.py: file headers
    <target>.py     one module per target

A :class:`~lagrangian.numeric.CompiledSystem` keeps its ``program`` (made by
``compile_equations`` at no cost: the renaming and the CSE wait for the first target
that needs them), and everything that generates code reads it; nobody derives the forms
again.

The Target protocol (:mod:`.target`).  A target is a class with the class constants
``name`` (its key in :data:`TARGETS`), ``language``, ``suffix``, ``base`` (index of a first
element) and ``standalone`` (its text is a file a user keeps); ``check()`` raises
:class:`~lagrangian.errors.MissingDependencyError` when its package is missing;
``render(program, name) -> str`` is its text.  :class:`AbstractLoadedTarget` adds
``load(program)``: the code as objects this process runs (numba's module, SymEngine's LLVM
function, heyoka's ODE).  The export languages (:data:`lagrangian.export.LANGUAGES`) are
the standalone targets.

Adding a target: write one module here with one :class:`AbstractTarget` subclass (see
``javascript.py``: about 150 lines, tested against our rhs through node), and add its
class to :data:`TARGETS` below: ``export --to`` and the CLI's choices read the registry.
The targets' modules are imported when :data:`TARGETS` is first read, not with the
package: a page needs the JavaScript target only, a derivation none.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from types import MappingProxyType

from .program import Program, Quantity, Routine, program
from .target import AbstractLoadedTarget, AbstractTarget

#: (module, class) of every target: every language and backend code is generated for.  A
#: new target is one module and one line here.
_TARGET_CLASSES = (
    (".c_file", "CTarget"),
    (".heyoka", "HeyokaTarget"),
    (".javascript", "JavaScriptTarget"),
    (".julia", "JuliaTarget"),
    (".llvm", "LLVMTarget"),
    (".matlab", "MatlabTarget"),
    (".numba", "NumbaTarget"),
    (".numpy_text", "NumPyTextTarget"),
)


def __getattr__(name: str) -> object:
    """``TARGETS``, target name -> class, made when first read (PEP 562)."""
    if name != "TARGETS":
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    classes = (
        getattr(importlib.import_module(module, __name__), cls) for module, cls in _TARGET_CLASSES
    )
    targets: Mapping[str, type[AbstractTarget]] = MappingProxyType({t.name: t for t in classes})
    globals()["TARGETS"] = targets
    return targets


__all__ = [
    "TARGETS",
    "AbstractLoadedTarget",
    "AbstractTarget",
    "Program",
    "Quantity",
    "Routine",
    "program",
]

"""Code generation: one program form of the equations, printed (and loaded) by targets."""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from .javascript import JavaScriptTarget
from .julia import JuliaTarget
from .matlab import MatlabTarget
from .numpy_text import NumPyTextTarget
from .program import Program, Quantity, Routine, program
from .target import AbstractLoadedTarget, AbstractTarget

#: Target name -> class: every language and backend code is generated for.  A new target
#: is one module and one line here.
TARGETS: Mapping[str, type[AbstractTarget]] = MappingProxyType(
    {
        target.name: target
        for target in (
            JavaScriptTarget,
            JuliaTarget,
            MatlabTarget,
            NumPyTextTarget,
        )
    }
)

__all__ = [
    "TARGETS",
    "AbstractLoadedTarget",
    "AbstractTarget",
    "Program",
    "Quantity",
    "Routine",
    "program",
]

"""Public names of a package imported on first use (PEP 562 module ``__getattr__``).

A package's ``__init__`` that imported every module would load, for any command, what
only some need (SciPy's integrators, xarray, the code generators): ``import lagrangian``
and the command line stay light when the heavy names are resolved here, the first time
they are read (``from package import name`` reads them too).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping


def on_use(package: str, names: Mapping[str, str]) -> Callable[[str], object]:
    """The ``__getattr__`` of ``package``: each of ``names`` (public name -> the module
    that defines it, relative to ``package`` when it starts with a dot) imported when first
    read and then kept in the package."""

    def __getattr__(name: str) -> object:
        if name not in names:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = importlib.import_module(package)
        value = getattr(importlib.import_module(names[name], package), name)
        setattr(module, name, value)  # read once: the next access finds it
        return value

    return __getattr__

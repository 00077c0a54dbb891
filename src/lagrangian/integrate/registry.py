"""The registry of integration methods: name (``--method NAME``) -> class.

>>> sorted(METHODS)
['dop853', 'radau', 'rk4', 'taylor', 'variational']
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from ..errors import ModelError
from .base import AbstractIntegrator
from .explicit_rk import RK4
from .scipy_methods import Dop853, Radau
from .taylor import Taylor
from .variational import Variational

METHODS: Mapping[str, type[AbstractIntegrator]] = MappingProxyType(
    {cls.name: cls for cls in (Dop853, Radau, RK4, Variational, Taylor)}
)


def method_class(name: str) -> type[AbstractIntegrator]:
    """The integrator class registered as ``name``; ModelError listing the names otherwise."""
    try:
        return METHODS[name]
    except (KeyError, TypeError):
        raise ModelError(f"unknown method {name!r} (methods: {', '.join(METHODS)})") from None

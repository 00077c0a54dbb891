"""Made on first use: public names of a package imported when first read (PEP 562 module
``__getattr__``), and dataclass fields whose value is made when first read (:class:`Later`).

A package's ``__init__`` that imported every module would load, for any command, what
only some need (SciPy's integrators, xarray, the code generators): ``import lagrangian``
and the command line stay light when the heavy names are resolved here, the first time
they are read (``from package import name`` reads them too).

A large model's SymPy forms (L and T of the 100-link chain, the equations' M and f) cost
tenths of a second to convert from SymEngine and most commands never read them: such a
field is given as ``Later(make)`` and made by its :class:`MadeOnRead` descriptor on the
first read, the same object for every reader after.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping

_UNMADE = object()


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


class Later:
    """A value made on first read: a :class:`MadeOnRead` field may be given as
    ``Later(make)``; :meth:`value` makes it once and keeps it."""

    __slots__ = ("_value", "make")

    def __init__(self, make: Callable[[], object]):
        self.make = make
        self._value = _UNMADE

    def value(self) -> object:
        if self._value is _UNMADE:
            self._value = self.make()
        return self._value

    def holds(self, stored: object) -> bool:
        """Whether ``stored`` (a field's stored value) is this value, made or not yet."""
        return stored is self or (self._value is not _UNMADE and stored is self._value)


def value_of(x: object) -> object:
    """``x`` itself, or the value a :class:`Later` makes."""
    return x.value() if isinstance(x, Later) else x


class MadeOnRead:
    """A dataclass field that holds its value, or a :class:`Later` it replaces by the value
    on the first read.  A data descriptor, so that a frozen dataclass's ``__init__`` (which
    sets fields by ``object.__setattr__``) stores through it.  With no ``default`` given the
    field has none (reading it from the class raises AttributeError, as dataclasses ask)."""

    def __init__(self, default: object = _UNMADE):
        self.default = default

    def __set_name__(self, owner, name: str) -> None:
        self.name = name

    def __get__(self, instance, owner=None):
        if instance is None:
            if self.default is _UNMADE:
                raise AttributeError(self.name)
            return self.default
        value = instance.__dict__[self.name]
        if isinstance(value, Later):
            value = instance.__dict__[self.name] = value.value()
        return value

    def __set__(self, instance, value) -> None:
        instance.__dict__[self.name] = value


def stored(instance: object, name: str) -> object:
    """What ``instance``'s field ``name`` holds, a :class:`Later` not made: for copying
    a dataclass (``cls(**fields)``, ``replace(x, **unread)``) without making its values."""
    return instance.__dict__[name]

"""Methods a result class declares and the facade provides: its picture, its LaTeX in
Jupyter, its text at the REPL.

The plots and printers are in ``output/``, above every layer that makes a result (a
Lyapunov spectrum in ``integrate/``, an analysis report in ``analysis/``), and a layer
imports nothing above it, inside functions neither.  So the class says which methods it
has, ``plot = Provided()``, and :mod:`lagrangian.facade` gives their functions
(:func:`provide`) when ``lagrangian`` is imported, which Python does before it runs any
module of the package: the class's module need not be imported then, and is not (the
integrators and the ensemble stay out of ``import lagrangian``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

#: "module.Class.method" -> the function the facade gives for it.
_FUNCTIONS: dict[str, Callable] = {}


def provide(functions: Mapping[str, Callable]) -> None:
    """The functions of methods declared with :class:`Provided`, by "module.Class.method"."""
    _FUNCTIONS.update(functions)


class Provided:
    """A method of the class it is declared in whose function :func:`provide` gives; read
    before that (or never given), the attribute is missing, as it would be undeclared."""

    def __set_name__(self, owner: type, name: str) -> None:
        self.key = f"{owner.__module__}.{owner.__qualname__}.{name}"

    def __get__(self, instance: object, owner: type | None = None):
        function = _FUNCTIONS.get(self.key)
        if function is None:
            raise AttributeError(f"{self.key} is given by lagrangian.facade, not imported")
        return function if instance is None else function.__get__(instance, owner)

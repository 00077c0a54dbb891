"""The editor's text as a model: a model file (TOML) or a Lagrangian alone.

A Lagrangian is an expression, and the expression language has no ``=``, while every
model file sets keys with ``=``; so a text with an ``=`` (after an optional leading
``L =``) is read as TOML, any other as the Lagrangian.  Both go through the project's
safe readers (the TOML loader, the expression parser): nothing the user types is
evaluated.

For a Lagrangian the rest of the model follows from its names: every ``NAME_dot``
makes ``NAME`` a coordinate (sorted by name), time is ``t``, and every other name is
a parameter.  The parameters start at 1 and the state at rest at 0, as the page's
sliders show; a model file says its own values.
"""

from __future__ import annotations

import re

from ..errors import ModelError, ParseError
from ..facade import System, loads
from ..model.limits import MAX_FILE_BYTES
from ..parsing import referenced_names
from ..symbols import TIME_NAME, VELOCITY_SUFFIX, velocity_name

#: How the editor's text is named in error messages (as a file's path would be).
SOURCE = "editor"
#: The value each parameter of a Lagrangian typed alone starts at.
PARAMETER_START = 1.0

_LEADING_L = re.compile(r"\A\s*L\s*=")


def model_from_text(text: str) -> System:
    """The model the editor's ``text`` describes (see the module's docstring).

    >>> model_from_text("m*x_dot**2/2 - k*x**2/2").coordinate_names
    ('x',)
    >>> model_from_text("L = m*x_dot**2/2 - k*x**2/2").parameter_names
    ('k', 'm')
    """
    if len(text) > MAX_FILE_BYTES:
        raise ModelError(f"the text is longer than {MAX_FILE_BYTES} characters", source=SOURCE)
    lagrangian = _LEADING_L.sub("", text, count=1)
    if "=" in lagrangian:
        return loads(text, source=SOURCE)
    return lagrangian_model(lagrangian)


def lagrangian_model(lagrangian: str) -> System:
    """The system of the Lagrangian ``lagrangian`` alone, its coordinates read from the
    velocities it uses (``x_dot`` makes ``x`` a coordinate)."""
    if not lagrangian.strip():
        raise ModelError(
            "type a model file (TOML) or a Lagrangian, e.g. m*x_dot**2/2 - k*x**2/2",
            source=SOURCE,
        )
    try:
        names = referenced_names(lagrangian).symbols
    except ParseError as error:
        raise ModelError(str(error), source=SOURCE, field="lagrangian", text=lagrangian) from None
    coordinates = sorted(
        name.removesuffix(VELOCITY_SUFFIX) for name in names if name.endswith(VELOCITY_SUFFIX)
    )
    if not coordinates:
        raise ModelError(
            "the Lagrangian has no velocity: write the velocity of a coordinate q as q_dot",
            source=SOURCE,
            field="lagrangian",
        )
    known = {TIME_NAME, *coordinates, *map(velocity_name, coordinates)}
    parameters = {name: PARAMETER_START for name in sorted(names - known)}
    return System.from_lagrangian(
        lagrangian,
        coordinates=coordinates,
        parameters=parameters,
        name="Lagrangian",
        source=SOURCE,
    )

"""Read a model file (TOML, DESIGN section 2) into a `System`.

Only the structure is checked here (known keys, types, sizes); every
expression is parsed and checked by :func:`~lagrangian.model.build.build_system`.
Errors name the file and the field.  What a file may cost to read is bounded
by :mod:`.limits`: only a regular file is opened (a FIFO, ``/dev/zero``, a
folder or a socket is refused by its type, never read), up to its size limit.
"""

from __future__ import annotations

import math
import os
import stat
import tomllib
from collections.abc import Mapping
from pathlib import Path

from ..errors import ModelError
from .build import ModelSpec, build_system
from .components import Gravity, Particle, RigidBody, RigidBody2D, Spring
from .impacts import read_impact
from .limits import (
    MAX_FILE_BYTES,
    check_counts,
    check_plain_text,
    check_table_keys,
    check_toml_keys,
    file_size_problem,
)
from .linkage_io import read_joints, read_links
from .system import System

_KINDS = {
    stat.S_IFDIR: "a folder",
    stat.S_IFIFO: "a named pipe (FIFO)",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
}

TOP_LEVEL_KEYS = frozenset(
    {
        "name", "description", "coordinates", "parameters", "lagrangian", "kinetic",
        "potential", "particles", "bodies", "springs", "gravity", "forces",
        "conservative_forces", "dissipation", "constraints", "functions", "initial",
        "simulate", "inputs", "units", "impacts", "links", "joints",
    }
)  # fmt: skip
SIMULATE_KEYS = frozenset({"t_end", "dt", "rtol", "atol", "method", "steps"})
#: The [simulate] keys that hold text; the others are numbers (true is not 1.0 here).
_SIMULATE_TEXT = frozenset({"method"})


def _check_simulate_value(key: str, value: object) -> None:
    """ModelError naming ``simulate.key`` when its value is not of the key's type."""
    if key in _SIMULATE_TEXT:
        if not isinstance(value, str):
            raise ModelError(f"expected a name, got {value!r}", field=f"simulate.{key}")
        return
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ModelError(f"expected a number, got {value!r}", field=f"simulate.{key}")
    if not math.isfinite(value):
        raise ModelError(f"expected a finite number, got {value!r}", field=f"simulate.{key}")


_COUNTED = (
    "coordinates", "parameters", "particles", "bodies", "springs", "constraints", "functions",
    "forces", "conservative_forces", "initial", "inputs", "units", "impacts", "links", "joints",
)  # fmt: skip


def load_file(path: str | Path) -> System:
    """The system described by the model file at ``path``."""
    source = str(path)
    try:
        data = _read_regular_file(Path(path))
        text = data.decode("utf-8")
    except FileNotFoundError:
        raise ModelError("no such model file or built-in example", source=source) from None
    except ModelError as error:
        raise error.located(source=source) from None
    except UnicodeDecodeError as error:
        raise ModelError(f"cannot read: not UTF-8 text ({error.reason})", source=source) from None
    except OSError as error:
        raise ModelError(f"cannot read: {error.strerror or error}", source=source) from None
    return loads(text, source=source)


def _read_regular_file(path: Path) -> bytes:
    """The bytes of ``path`` if it is a regular file within :data:`MAX_FILE_BYTES`.

    The type is checked before opening (opening a FIFO for reading waits for a
    writer), and again on the open file, which is opened non-blocking in case
    the path was replaced in between; at most one byte past the limit is read.
    """
    _check_regular(os.stat(path))
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    descriptor = os.open(path, flags)
    with os.fdopen(descriptor, "rb") as file:
        _check_regular(os.fstat(descriptor))
        data = file.read(MAX_FILE_BYTES + 1)
    problem = file_size_problem(len(data))
    if problem is not None:
        raise ModelError(problem)
    return data


def _check_regular(status: os.stat_result) -> None:
    if not stat.S_ISREG(status.st_mode):
        kind = _KINDS.get(stat.S_IFMT(status.st_mode), "not a regular file")
        raise ModelError(f"is {kind}, not a model file (a regular TOML file)")
    problem = file_size_problem(status.st_size)
    if problem is not None:
        raise ModelError(problem)


def loads(text: str, *, source: str = "<model>") -> System:
    """The system described by the TOML ``text``; ``source`` names it in errors."""
    problem = file_size_problem(len(text), unit="characters")
    if problem is not None:
        raise ModelError(problem, source=source)
    try:
        check_toml_keys(text)
        data = tomllib.loads(text)
    except ModelError as error:
        raise error.located(source=source) from None
    except tomllib.TOMLDecodeError as error:
        raise ModelError(f"invalid TOML: {error}", source=source) from None
    except RecursionError:  # arrays or inline tables nested thousands deep
        message = "invalid TOML: arrays or tables nested too deeply"
        raise ModelError(message, source=source) from None
    return build_system(spec_from_mapping(data, source=source))


def spec_from_mapping(data: Mapping[str, object], *, source: str | None = None) -> ModelSpec:
    """Check the structure of a parsed model file and turn it into a :class:`ModelSpec`."""
    try:
        return _spec(data, source)
    except ModelError as error:
        raise error.located(source=source) from None


def _spec(data: Mapping[str, object], source: str | None) -> ModelSpec:
    unknown = set(data) - TOP_LEVEL_KEYS
    if unknown:
        name = sorted(unknown)[0]
        raise ModelError(
            f"unknown key (expected one of {', '.join(sorted(TOP_LEVEL_KEYS))})", field=name
        )
    if "coordinates" not in data:
        raise ModelError("missing field", field="coordinates")
    check_counts(
        {key: len(data[key]) for key in _COUNTED if isinstance(data.get(key), list | dict)}
    )
    simulate = _table(data, "simulate")
    for key in simulate:
        if key not in SIMULATE_KEYS:
            raise ModelError(
                f"unknown key (expected one of {', '.join(sorted(SIMULATE_KEYS))})",
                field=f"simulate.{key}",
            )
        _check_simulate_value(key, simulate[key])
    return ModelSpec(
        name=_string(data, "name", ""),
        description=_string(data, "description", "", breaks="\n\t"),
        coordinates=tuple(_list(data, "coordinates")),
        parameters=_table(data, "parameters"),
        lagrangian=_scalar(data, "lagrangian"),
        kinetic=_scalar(data, "kinetic"),
        potential=_scalar(data, "potential"),
        dissipation=_scalar(data, "dissipation"),
        particles=tuple(_particle(p, i) for i, p in enumerate(_tables(data, "particles"))),
        bodies=tuple(_body(b, i) for i, b in enumerate(_tables(data, "bodies"))),
        springs=tuple(_spring(s, i) for i, s in enumerate(_tables(data, "springs"))),
        links=read_links(data.get("links", [])),
        joints=read_joints(data.get("joints", [])),
        gravity=_gravity(data["gravity"]) if "gravity" in data else None,
        forces=_table(data, "forces"),
        conservative_forces=_table(data, "conservative_forces"),
        constraints=tuple(_list(data, "constraints")),
        impacts=tuple(read_impact(t, i) for i, t in enumerate(_tables(data, "impacts"))),
        functions=_table(data, "functions"),
        inputs=_table(data, "inputs"),
        initial=_table(data, "initial"),
        simulate=simulate,
        units=_table(data, "units"),
        source=source,
    )


def _string(data, key, default, breaks=""):
    """Text without control characters (but those in ``breaks``): a name is one line of
    plain text, and what ends a line or hides text does not belong in the files it reaches."""
    return check_plain_text(data.get(key, default), key, breaks=breaks)


def _scalar(data, key, where=None):
    """An expression field: text or a number."""
    if key not in data:
        return None
    value = data[key]
    if isinstance(value, bool) or not isinstance(value, str | int | float):
        raise ModelError(
            f"expected an expression (text or number), got {type(value).__name__}",
            field=where or key,
        )
    return value


def _list(data, key, where=None):
    value = data.get(key, [])
    if not isinstance(value, list):
        raise ModelError(f"expected a list, got {type(value).__name__}", field=where or key)
    return value


def _table(data, key):
    value = data.get(key, {})
    if not isinstance(value, dict):
        raise ModelError(f"expected a table, got {type(value).__name__}", field=key)
    return value


def _tables(data, key):
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        raise ModelError(f"expected an array of tables ([[{key}]])", field=key)
    return value


def _required(table, key, where):
    if key not in table:
        raise ModelError("missing field", field=f"{where}.{key}")
    return _scalar(table, key, f"{where}.{key}")


def _vector(table, key, where, sizes=(2, 3)):
    if key not in table:
        raise ModelError("missing field", field=f"{where}.{key}")
    value = _list(table, key, f"{where}.{key}")
    if len(value) not in sizes:
        raise ModelError(
            f"expected {' or '.join(map(str, sizes))} components, got {len(value)}",
            field=f"{where}.{key}",
        )
    for k, x in enumerate(value):
        _scalar({"x": x}, "x", f"{where}.{key}[{k}]")
    return tuple(value)


def _particle(table, i):
    where = f"particles[{i}]"
    check_table_keys(table, {"name", "mass", "position"}, where)
    return Particle(
        name=_string(table, "name", ""),
        mass=_required(table, "mass", where),
        position=_vector(table, "position", where),
    )


def _body(table, i):
    where = f"bodies[{i}]"
    if "position" in table or "orientation" in table or isinstance(table.get("inertia"), list):
        return _body_3d(table, where)
    check_table_keys(table, {"name", "mass", "inertia", "center", "angle"}, where)
    return RigidBody2D(
        name=_string(table, "name", ""),
        mass=_required(table, "mass", where),
        inertia=_required(table, "inertia", where),
        center=_vector(table, "center", where, sizes=(2,)),
        angle=_required(table, "angle", where),
    )


def _body_3d(table, where):
    """A 3-D body: position, inertia (3 moments or 3 x 3), orientation {euler, convention}
    or {rotation}; shapes and values are checked when built (:mod:`.rigid_body`)."""
    check_table_keys(table, {"name", "mass", "position", "inertia", "orientation"}, where)
    for key in ("position", "inertia", "orientation"):
        if key not in table:
            raise ModelError("missing field (a 3-D body has position, inertia, orientation)",
                             field=f"{where}.{key}")  # fmt: skip
    inertia = _list(table, "inertia", f"{where}.inertia")
    orientation = table["orientation"]
    if not isinstance(orientation, dict):
        raise ModelError(
            'expected a table {euler = [...], convention = "zxz"} or {rotation = [[...], ...]}',
            field=f"{where}.orientation",
        )
    check_table_keys(orientation, {"euler", "convention", "rotation"}, f"{where}.orientation")
    convention = orientation.get("convention", "zxz")
    if not isinstance(convention, str):
        raise ModelError('expected text such as "zxz"', field=f"{where}.orientation.convention")
    euler = orientation.get("euler")
    rotation = orientation.get("rotation")
    for key, value in (("euler", euler), ("rotation", rotation)):
        if value is not None and not isinstance(value, list):
            raise ModelError(f"expected a list, got {type(value).__name__}",
                             field=f"{where}.orientation.{key}")  # fmt: skip
    if rotation is not None:
        rotation = tuple(tuple(row) if isinstance(row, list) else row for row in rotation)
    return RigidBody(
        name=_string(table, "name", ""),
        mass=_required(table, "mass", where),
        position=_vector(table, "position", where, sizes=(3,)),
        inertia=tuple(tuple(x) if isinstance(x, list) else x for x in inertia),
        euler=None if euler is None else tuple(euler),
        convention=convention,
        rotation=rotation,
    )


def _spring(table, i):
    where = f"springs[{i}]"
    check_table_keys(table, {"name", "stiffness", "rest_length", "ends"}, where)
    ends = _list(table, "ends", f"{where}.ends")
    if len(ends) != 2:
        raise ModelError("expected two ends", field=f"{where}.ends")
    parsed = []
    for e, end in enumerate(ends):
        if isinstance(end, str):
            parsed.append(end)
        else:
            parsed.append(_vector({"end": end}, "end", f"{where}.ends[{e}]"))
    return Spring(
        name=_string(table, "name", ""),
        stiffness=_required(table, "stiffness", where),
        rest_length=_scalar(table, "rest_length", f"{where}.rest_length") or 0,
        ends=tuple(parsed),
    )


def _gravity(table):
    if not isinstance(table, dict):
        raise ModelError("expected a table", field="gravity")
    check_table_keys(table, {"g", "direction"}, "gravity")
    direction = _vector(table, "direction", "gravity") if "direction" in table else None
    return Gravity(g=_required(table, "g", "gravity"), direction=direction)


def load(model: str | Path) -> System:
    """A system from a model file path or the name of a built-in example."""
    return load_file(model_path(model))


def model_path(model: str | Path) -> Path:
    """The file of ``model``: a model file path, or the file of the built-in example of
    that name (ModelError when it is neither)."""
    from ..examples import example_names, example_path

    path = Path(model)
    if path.suffix == ".toml" or _exists(path):
        return path
    builtin = example_path(str(model))
    if builtin is None:
        raise ModelError(
            f"no such model file or built-in example (examples: {', '.join(example_names())})",
            source=str(model),
        )
    return builtin


def model_bytes(model: str | Path) -> bytes:
    """The bytes of ``model``'s file (see :func:`model_path`), read as :func:`load_file`
    reads them (a regular file within the size limit); OSError or ModelError otherwise."""
    return _read_regular_file(model_path(model))


def _exists(path: Path) -> bool:
    """Whether ``path`` names something; a name the system cannot look up (too long) does not."""
    try:
        return path.exists()
    except OSError:  # ENAMETOOLONG and kin: no file has that name
        return False

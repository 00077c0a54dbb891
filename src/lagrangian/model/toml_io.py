"""Read a model file (TOML, DESIGN section 2) into a `System`.

Only the structure is checked here (known keys, types); every expression is
parsed and checked by :func:`~lagrangian.model.build.build_system`.  Errors
name the file and the field.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from pathlib import Path

from ..errors import ModelError
from .build import ModelSpec, build_system
from .components import Gravity, Particle, RigidBody2D, Spring
from .system import System

#: Model files larger than this are refused before they are parsed.
MAX_FILE_BYTES = 1_000_000

TOP_LEVEL_KEYS = frozenset(
    {
        "name", "description", "coordinates", "parameters", "lagrangian", "kinetic",
        "potential", "particles", "bodies", "springs", "gravity", "forces",
        "conservative_forces", "dissipation", "constraints", "functions", "initial",
        "simulate",
    }
)  # fmt: skip
SIMULATE_KEYS = frozenset({"t_end", "dt", "rtol", "atol", "method", "steps"})


def load_file(path: str | Path) -> System:
    """The system described by the model file at ``path``."""
    path = Path(path)
    source = str(path)
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise ModelError(
                f"file too large ({size} bytes, limit {MAX_FILE_BYTES})", source=source
            )
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ModelError("no such model file or built-in example", source=source) from None
    except (OSError, UnicodeDecodeError) as error:
        raise ModelError(f"cannot read: {error}", source=source) from None
    return loads(text, source=source)


def loads(text: str, *, source: str = "<model>") -> System:
    """The system described by the TOML ``text``; ``source`` names it in errors."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ModelError(f"invalid TOML: {error}", source=source) from None
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
    simulate = _table(data, "simulate")
    for key in simulate:
        if key not in SIMULATE_KEYS:
            raise ModelError(
                f"unknown key (expected one of {', '.join(sorted(SIMULATE_KEYS))})",
                field=f"simulate.{key}",
            )
    return ModelSpec(
        name=_string(data, "name", ""),
        description=_string(data, "description", ""),
        coordinates=tuple(_list(data, "coordinates")),
        parameters=_table(data, "parameters"),
        lagrangian=_scalar(data, "lagrangian"),
        kinetic=_scalar(data, "kinetic"),
        potential=_scalar(data, "potential"),
        dissipation=_scalar(data, "dissipation"),
        particles=tuple(_particle(p, i) for i, p in enumerate(_tables(data, "particles"))),
        bodies=tuple(_body(b, i) for i, b in enumerate(_tables(data, "bodies"))),
        springs=tuple(_spring(s, i) for i, s in enumerate(_tables(data, "springs"))),
        gravity=_gravity(data["gravity"]) if "gravity" in data else None,
        forces=_table(data, "forces"),
        conservative_forces=_table(data, "conservative_forces"),
        constraints=tuple(_list(data, "constraints")),
        functions=_table(data, "functions"),
        initial=_table(data, "initial"),
        simulate=simulate,
        source=source,
    )


def _string(data, key, default):
    value = data.get(key, default)
    if not isinstance(value, str):
        raise ModelError(f"expected text, got {type(value).__name__}", field=key)
    return value


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


def _check_keys(table, allowed, where):
    unknown = set(table) - allowed
    if unknown:
        name = sorted(unknown)[0]
        raise ModelError(
            f"unknown key (expected one of {', '.join(sorted(allowed))})", field=f"{where}.{name}"
        )


def _particle(table, i):
    where = f"particles[{i}]"
    _check_keys(table, {"name", "mass", "position"}, where)
    return Particle(
        name=_string(table, "name", ""),
        mass=_required(table, "mass", where),
        position=_vector(table, "position", where),
    )


def _body(table, i):
    where = f"bodies[{i}]"
    _check_keys(table, {"name", "mass", "inertia", "center", "angle"}, where)
    return RigidBody2D(
        name=_string(table, "name", ""),
        mass=_required(table, "mass", where),
        inertia=_required(table, "inertia", where),
        center=_vector(table, "center", where, sizes=(2,)),
        angle=_required(table, "angle", where),
    )


def _spring(table, i):
    where = f"springs[{i}]"
    _check_keys(table, {"name", "stiffness", "rest_length", "ends"}, where)
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
    _check_keys(table, {"g", "direction"}, "gravity")
    direction = _vector(table, "direction", "gravity") if "direction" in table else None
    return Gravity(g=_required(table, "g", "gravity"), direction=direction)


def load(model: str | Path) -> System:
    """A system from a model file path or the name of a built-in example."""
    from ..examples import example_names, example_path

    path = Path(model)
    if path.suffix == ".toml" or path.exists():
        return load_file(path)
    builtin = example_path(str(model))
    if builtin is None:
        raise ModelError(
            f"no such model file or built-in example (examples: {', '.join(example_names())})",
            source=str(model),
        )
    system = load_file(builtin)
    return system

"""Read ``[[links]]`` and ``[[joints]]`` tables of a model file (structure only; their
expressions are parsed when the system is built, :mod:`.linkages`)."""

from __future__ import annotations

from ..errors import ModelError
from .limits import check_table_keys
from .linkages import Joint, Link

LINK_KEYS = frozenset({"name", "length", "mass", "angle", "inertia", "center", "points"})
JOINT_KEYS = frozenset({"name", "kind", "connects", "at", "axis", "slide", "drive"})


def read_links(tables) -> tuple[Link, ...]:
    return tuple(_link(table, i) for i, table in enumerate(_array(tables, "links")))


def read_joints(tables) -> tuple[Joint, ...]:
    return tuple(_joint(table, i) for i, table in enumerate(_array(tables, "joints")))


def _array(value, key):
    if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
        raise ModelError(f"expected an array of tables ([[{key}]])", field=key)
    return value


def _link(table, i) -> Link:
    where = f"links[{i}]"
    check_table_keys(table, LINK_KEYS, where)
    points = table.get("points", {})
    if not isinstance(points, dict):
        raise ModelError("expected a table {P = [x, y]}", field=f"{where}.points")
    return Link(
        name=_name(table, where, required=True),
        length=_expression(table, "length", where, required=True),
        mass=_expression(table, "mass", where, required=True),
        angle=_name(table, where, key="angle"),
        inertia=_expression(table, "inertia", where),
        center=_expression(table, "center", where),
        points={name: _pair(points, name, f"{where}.points") for name in points},
    )


def _joint(table, i) -> Joint:
    where = f"joints[{i}]"
    check_table_keys(table, JOINT_KEYS, where)
    connects = table.get("connects")
    if not isinstance(connects, list) or len(connects) != 2:
        raise ModelError(
            'expected two sides, e.g. ["ground", "crank.start"]', field=f"{where}.connects"
        )
    kind = table.get("kind", "revolute")
    if not isinstance(kind, str):
        raise ModelError(f"expected a name, got {kind!r}", field=f"{where}.kind")
    return Joint(
        name=_name(table, where) or f"joint{i + 1}",
        kind=kind,
        connects=(connects[0], connects[1]),
        at=_pair(table, "at", where) if "at" in table else None,
        axis=_pair(table, "axis", where) if "axis" in table else None,
        slide=_name(table, where, key="slide"),
        drive=_expression(table, "drive", where),
    )


def _name(table, where, *, key="name", required=False):
    if key not in table:
        if required:
            raise ModelError("missing field", field=f"{where}.{key}")
        return None
    value = table[key]
    if not isinstance(value, str) or not value.isidentifier() or not value.isascii():
        raise ModelError(f"expected a name, got {value!r}", field=f"{where}.{key}")
    return value


def _expression(table, key, where, *, required=False):
    if key not in table:
        if required:
            raise ModelError("missing field", field=f"{where}.{key}")
        return None
    value = table[key]
    if isinstance(value, bool) or not isinstance(value, str | int | float):
        raise ModelError(
            f"expected an expression (text or number), got {type(value).__name__}",
            field=f"{where}.{key}",
        )
    return value


def _pair(table, key, where):
    value = table[key]
    if not isinstance(value, list) or len(value) != 2:
        raise ModelError("expected two components [x, y]", field=f"{where}.{key}")
    for k in range(2):
        _expression({"x": value[k]}, "x", f"{where}.{key}[{k}]")
    return (value[0], value[1])

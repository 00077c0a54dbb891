"""The built-in example models (one TOML file each), found by name."""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path


def example_names() -> tuple[str, ...]:
    """Names of the built-in examples, sorted."""
    files = resources.files(__name__).iterdir()
    return tuple(sorted(f.name.removesuffix(".toml") for f in files if f.name.endswith(".toml")))


def example_path(name: str) -> Path | None:
    """The model file of the example ``name``, or None if there is none."""
    if name not in example_names():
        return None
    return Path(str(resources.files(__name__) / f"{name}.toml"))


def example_title(name: str) -> tuple[str, tuple[str, ...]]:
    """The title and coordinate names of the example ``name``, read from its file alone.

    Listing the examples needs no model built (no SymPy): `lagrangian examples` stays a
    fraction of a second.  Every example is built and derived by the test suite.
    """
    document = tomllib.loads((resources.files(__name__) / f"{name}.toml").read_text("utf-8"))
    return str(document.get("name", name)), tuple(map(str, document.get("coordinates", ())))

"""The built-in example models (one TOML file each), found by name."""

from __future__ import annotations

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

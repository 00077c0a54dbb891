"""Stage 1: a mechanical system as frozen data (`System`) from text, TOML or Python."""

from .build import ModelSpec, build_system
from .components import Gravity, Particle, RigidBody, RigidBody2D, Spring
from .inputs import Input
from .system import FunctionDeclaration, Parameter, System
from .toml_io import load, load_file, loads

__all__ = [
    "FunctionDeclaration",
    "Gravity",
    "Input",
    "ModelSpec",
    "Parameter",
    "Particle",
    "RigidBody",
    "RigidBody2D",
    "Spring",
    "System",
    "build_system",
    "load",
    "load_file",
    "loads",
]

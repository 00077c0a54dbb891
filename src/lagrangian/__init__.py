"""lagrangian: analytical mechanics from the Lagrangian to equations, analysis and motion.

>>> import lagrangian as lg
>>> eom = lg.load("simple_pendulum").equations_of_motion()
>>> eom.accelerations["theta"]
-g*sin(theta)/l
"""

from .derive import CoordinateDerivation, EquationsOfMotion, derive
from .errors import (
    FileError,
    LagrangianError,
    LagrangianWarning,
    MissingDependencyError,
    ModelError,
    ParseError,
    SingularMassMatrixError,
)
from .integrate import Event, simulate
from .model import (
    Gravity,
    Parameter,
    Particle,
    RigidBody,
    RigidBody2D,
    Spring,
    System,
    load,
    loads,
)
from .numeric import CompiledSystem, compile_equations
from .trajectory import Trajectory

__all__ = [
    "CompiledSystem",
    "CoordinateDerivation",
    "EquationsOfMotion",
    "Event",
    "FileError",
    "Gravity",
    "LagrangianError",
    "LagrangianWarning",
    "MissingDependencyError",
    "ModelError",
    "Parameter",
    "ParseError",
    "Particle",
    "RigidBody",
    "RigidBody2D",
    "SingularMassMatrixError",
    "Spring",
    "System",
    "Trajectory",
    "compile_equations",
    "derive",
    "load",
    "loads",
    "simulate",
]
__version__ = "0.1.0"

"""lagrangian: analytical mechanics from the Lagrangian to equations, analysis and motion.

>>> import lagrangian as lg
>>> eom = lg.load("simple_pendulum").equations_of_motion()
>>> eom.accelerations["theta"]
-g*sin(theta)/l

Layers.  The package is a stack; a module imports only from its own layer and the ones
below it, inside functions too, so data flows up and nothing reaches back down:

    cli          the command line: a thin shell, no physics
    facade       lagrangian.System (the model's System with equations_of_motion,
                 simulate, equilibria, ...), load/loads, and the pictures and Jupyter
                 display of results (Trajectory.plot, _repr_latex_, ...): see facade.py
    output       text, LaTeX, JSON, plots and animations of the results
    ensemble     many runs at once (numpy, numba, jax, dask, cuda)
    simulation   one System run: derive, compile, integrate with the model's settings
    integrate    the integrators and simulate(CompiledSystem) -> Trajectory
    trajectory   Trajectory (xarray-backed) and its files (trajectory_files)
    export       export_code / write_code: the model as a file in another language
    numeric      CompiledSystem: the equations as numerical functions
    codegen      one program form of the equations, printed (and loaded) by targets
    analysis     conserved quantities, Hamiltonian, equilibria, modes, state space, Routh
    derive       EquationsOfMotion, the one object every later layer reads
    model        System as frozen data (parsed text, TOML, Python objects)
    parsing      the safe expression parser
    utilities    examples, pointwise, distributions, files, algebra, budget, symbols, errors

Inside the CLI, the command modules (ensemble, export, visual) register their commands
on the app of ``cli.app``; ``cli/__init__`` imports them all.  ``lint-imports`` (the
contracts in pyproject.toml, run by .ci/run) checks both orders, with no exceptions.
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
from .facade import System, load, loads
from .lazy import on_use
from .model import Gravity, Parameter, Particle, RigidBody, RigidBody2D, Spring
from .trajectory import Trajectory

#: Public names whose layers are imported on first use: deriving, analysing or writing a
#: page needs no integrator, and their modules (SciPy's adapters, the numeric backends,
#: the code generators they load) were a quarter of the import of the package.
_ON_USE = {
    "CompiledSystem": ".numeric",
    "compile_equations": ".numeric",
    "Event": ".integrate",
    "simulate": ".integrate",
}
__getattr__ = on_use(__name__, _ON_USE)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_ON_USE))


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

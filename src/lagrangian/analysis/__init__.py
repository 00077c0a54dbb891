"""Stage 3: what a physicist does after writing the equations.

Conserved quantities (cyclic momenta, energy / Jacobi integral, Noether
charges), the Hamiltonian, equilibria and their normal modes, Routh's reduction.
"""

from .conserved import (
    Conservation,
    ConservedQuantity,
    NotConserved,
    conserved_quantities,
    energy_function,
    noether_charge,
)
from .constrained import ConstrainedEquilibrium, constrained_equilibria, rest_points
from .equilibria import Equilibrium, equilibria
from .hamiltonian import Hamiltonian, hamiltonian
from .linear import LinearizedSystem, NormalModes, Stability, linearize
from .report import Analysis, analyze
from .routh import Reduction, SteadyMotion, reduce, steady_motions
from .state_space import NumericStateSpace, StateSpace, state_space

__all__ = [
    "Analysis",
    "Conservation",
    "ConservedQuantity",
    "ConstrainedEquilibrium",
    "Equilibrium",
    "Hamiltonian",
    "LinearizedSystem",
    "NormalModes",
    "NotConserved",
    "NumericStateSpace",
    "Reduction",
    "Stability",
    "StateSpace",
    "SteadyMotion",
    "analyze",
    "conserved_quantities",
    "constrained_equilibria",
    "energy_function",
    "equilibria",
    "hamiltonian",
    "linearize",
    "noether_charge",
    "reduce",
    "rest_points",
    "state_space",
    "steady_motions",
]

"""Stage 2: Euler-Lagrange equations, M(q,t) q'' = f(q,q',t), solved accelerations."""

from .equations import CoordinateDerivation, EquationsOfMotion
from .euler_lagrange import derive

__all__ = ["CoordinateDerivation", "EquationsOfMotion", "derive"]

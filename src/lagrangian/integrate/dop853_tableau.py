"""The coefficients of DOP853: Dormand and Prince's explicit Runge-Kutta pair of order 8(5,3)
with its 7th-order dense output.

Hairer, Norsett & Wanner, *Solving Ordinary Differential Equations I*, 2nd ed. 1993,
II.10, and Hairer's Fortran code DOP853 (http://www.unige.ch/~hairer/software.html).  The
numbers are SciPy's own (the public class attributes of ``scipy.integrate.DOP853``), so that
the compiled method (:mod:`lagrangian.integrate.compiled_dop853`) takes the steps SciPy's
takes.  Laid out as one extended tableau: stages 0-11 make the step (``A``, ``B``, ``C``;
stage 12 is f at the new state, its row of ``A`` is ``B``), ``E3``/``E5`` the 3rd- and
5th-order error estimates, stages 13-15 (``A[13:]``, ``C[13:]``) and ``D`` the dense output.
"""

import numpy as np
from scipy.integrate import DOP853 as _SCIPY

N_STAGES = _SCIPY.n_stages
N_STAGES_EXTENDED = 16
INTERPOLATOR_POWER = 7

B = np.array(_SCIPY.B, dtype=float)
E3 = np.array(_SCIPY.E3, dtype=float)
E5 = np.array(_SCIPY.E5, dtype=float)
D = np.array(_SCIPY.D, dtype=float)

A = np.zeros((N_STAGES_EXTENDED, N_STAGES_EXTENDED))
A[:N_STAGES, :N_STAGES] = _SCIPY.A
A[N_STAGES, :N_STAGES] = B
A[N_STAGES + 1 :] = _SCIPY.A_EXTRA

C = np.concatenate([_SCIPY.C, [1.0], _SCIPY.C_EXTRA])

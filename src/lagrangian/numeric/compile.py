"""`compile_equations`: EquationsOfMotion -> CompiledSystem (numerical functions).

Every expression is turned into a function by :func:`sympy.lambdify` with common
subexpressions eliminated; no text is generated or evaluated by us, except by
the ``numba`` backend, which writes its kernels as Python source from SymPy's
code printer over symbols it names itself (see
:mod:`lagrangian.numeric.numba_source`).  The
mass-matrix solve is numerical (see :mod:`lagrangian.numeric.dynamics`), the
Jacobian of the right-hand side is a compiled symbolic derivative, and the
functions broadcast over a trailing batch axis (see
:mod:`lagrangian.numeric.compiled` for the conventions).

Each function is lambdified on its first call, so compiling is cheap and a run
pays only for what it uses.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from types import MappingProxyType

import sympy

from ..codegen.definitions import Definition, function_definitions
from ..codegen.forms import DEFAULT_BAUMGARTE, SymbolicForms, checked_baumgarte, symbolic_forms
from ..codegen.program import program_of
from ..derive import EquationsOfMotion
from ..errors import ModelError
from ..model.values import check_parameter_values
from .backends import BACKENDS, ArrayBackend, array_backend
from .compiled import CompiledSystem
from .dynamics import Dynamics
from .kernels import Kernel, LazyMapping, Signature
from .llvm_functions import check_llvm, with_llvm_functions
from .numba_functions import check_numba, with_numba_functions
from .projection import ConstraintFunctions

#: Backends that replace functions of an array backend's compiled system with
#: generated, jitted kernels: name -> (the array backend, a check that it can run
#: (a ModelError naming what to install), (forms, compiled) -> compiled).
JIT_BACKENDS: Mapping[
    str, tuple[str, Callable[[], None], Callable[[SymbolicForms, CompiledSystem], CompiledSystem]]
] = MappingProxyType(
    {
        "numba": ("numpy", check_numba, with_numba_functions),
        "llvm": ("numpy", check_llvm, with_llvm_functions),
    }
)


#: The backends a single run may use: NumPy and the generated kernels.  JAX is for
#: ensembles (``jax.vmap``): called one state at a time it is far slower.
RUN_BACKENDS: tuple[str, ...] = ("numpy", *JIT_BACKENDS)


def default_backend() -> str:
    """The backend a single run uses unless told: ``"llvm"`` where SymEngine has LLVM.

    Measured (benchmarks/first_run.py): compiling and integrating a first run of the
    double pendulum or a 10-link chain is fastest with it (its code is made in
    milliseconds; numba's takes seconds, NumPy's calls cost more).  ``"numpy"``
    where SymEngine was built without LLVM.
    """
    from .llvm_functions import llvm_available

    return "llvm" if llvm_available() else "numpy"


def compile_equations(
    eom: EquationsOfMotion,
    *,
    backend: str = "numpy",
    definitions: Mapping[str, Definition] | None = None,
    baumgarte: float = DEFAULT_BAUMGARTE,
) -> CompiledSystem:
    """The equations of motion M q'' = f as numerical functions of (t, y, params).

    ``backend``: a name in :data:`~lagrangian.numeric.backends.BACKENDS`
    (``"numpy"``, or ``"jax"`` when JAX is installed) or in :data:`JIT_BACKENDS`
    (``"numba"``: the NumPy functions, with rhs, accelerations, mass_matrix,
    forcing and energy of one state as numba kernels, see
    :mod:`lagrangian.numeric.numba_functions`; constrained systems keep the
    NumPy functions, with a warning; ``"llvm"``: rhs and accelerations of one
    state compiled by SymEngine's LLVM Lambdify in milliseconds, see
    :mod:`lagrangian.numeric.llvm_functions`).  ``definitions`` gives
    the model's unspecified functions, each as text over its declared arguments,
    the parameters and ``t``, or as a :class:`sympy.Lambda`; a function used but
    not defined is a :class:`~lagrangian.errors.ModelError`.  ``baumgarte``: the
    stabilisation rate alpha of constrained systems (see
    :mod:`lagrangian.numeric.dynamics`).

    >>> import lagrangian as lg
    >>> compiled = compile_equations(lg.load("simple_pendulum").equations_of_motion())
    >>> params = compiled.parameter_vector({"g": 9.81, "l": 1.0})
    >>> compiled.rhs(0.0, [0.5, 0.0], params).round(4).tolist()
    [0.0, -4.7032]
    """
    jit = JIT_BACKENDS.get(backend) if isinstance(backend, str) else None
    if jit is not None:
        jit[1]()  # a missing package is an error now, not at the first call
    elif backend not in BACKENDS:
        valid = ", ".join(sorted([*BACKENDS, *JIT_BACKENDS]))
        raise ModelError(f"unknown backend {backend!r} (backends: {valid})")
    arrays = array_backend(jit[0] if jit is not None else backend)
    system = eom.system
    defined = function_definitions(system, definitions)
    forms = symbolic_forms(eom, defined)
    signature = Signature(arrays, system.coordinate_names, system.parameter_names)
    baumgarte = checked_baumgarte(baumgarte)
    dynamics = Dynamics(forms, signature, baumgarte)
    constraint_functions = (
        ConstraintFunctions(forms, signature) if forms.constraints is not None else None
    )
    functions = _lagrangian_functions(forms, signature)
    compiled = CompiledSystem(
        equations=eom,
        backend=arrays.name,
        coordinate_names=system.coordinate_names,
        parameter_names=system.parameter_names,
        rhs=dynamics.rhs,
        accelerations=dynamics.accelerations,
        mass_matrix=dynamics.mass_matrix,
        forcing=dynamics.forcing,
        rhs_jacobian=dynamics.rhs_jacobian,
        energy=_kernel(forms, arrays, lambda: [forms.energy]).state_function(signature, "energy"),
        invariants=LazyMapping(
            lambda: {
                name: _kernel(forms, arrays, lambda e=expression: [e]).state_function(
                    signature, name
                )
                for name, expression in forms.invariants.items()
            }
        ),
        constant_mass_matrix=forms.constant_mass_matrix,
        separable=forms.separable,
        autonomous_lagrangian=not forms.lagrangian.has(forms.time),
        has_constraints=constraint_functions is not None,
        constraint_names=tuple(
            s.name for s in (forms.constraints.multipliers if forms.constraints else ())
        ),
        multipliers=dynamics.multipliers if constraint_functions else None,
        constraint_residual=constraint_functions.residual if constraint_functions else None,
        project=constraint_functions.project if constraint_functions else None,
        default_parameters=MappingProxyType(dict(system.parameter_values)),
        parameter_signs=MappingProxyType({p.name: p.sign for p in system.parameters}),
        constraint_holonomic=forms.constraints.holonomic if forms.constraints else (),
        constraint_velocity_residual=(
            constraint_functions.velocity_residual if constraint_functions else None
        ),
        baumgarte=float(baumgarte) if constraint_functions else 0.0,
        definitions=MappingProxyType({f.__name__: body for f, body in defined.items()}),
        model_checks=functools.partial(check_parameter_values, system),
        program=program_of(forms, baumgarte),
        **functions,
    )
    return compiled if jit is None else jit[2](forms, compiled)


def _kernel(forms: SymbolicForms, arrays: ArrayBackend, build: Callable[[], list]) -> Kernel:
    """A kernel of (t, q, q', params)."""
    arguments = (forms.time, *forms.coordinates, *forms.velocities, *forms.parameters)
    return Kernel(arrays, arguments, build)


def _lagrangian_functions(forms: SymbolicForms, signature: Signature) -> dict[str, object]:
    """L, its derivatives and the non-conservative forces, for variational integrators."""
    arrays = signature.backend
    q, v = forms.coordinates, forms.velocities
    momenta = sympy.Matrix(forms.momenta)
    forces = sympy.Matrix(forms.nonconservative_forces)

    @functools.cache
    def gradient() -> sympy.Matrix:  # dL/dq, made when first needed
        return sympy.Matrix([sympy.diff(forms.lagrangian, coordinate) for coordinate in q])

    builders = {
        "lagrangian": lambda: [forms.lagrangian],
        "momenta": lambda: [list(momenta)],
        "lagrangian_gradient": lambda: [list(gradient())],
        "momenta_jacobian_q": lambda: [momenta.jacobian(q)],
        "lagrangian_hessian_q": lambda: [gradient().jacobian(q)],
        "nonconservative_forces": lambda: [list(forces)],
        "nonconservative_forces_jacobian_v": lambda: [forces.jacobian(v)],
        "nonconservative_forces_jacobian_q": lambda: [forces.jacobian(q)],
    }
    return {
        name: _kernel(forms, arrays, build).split_function(signature, name)
        for name, build in builders.items()
    }

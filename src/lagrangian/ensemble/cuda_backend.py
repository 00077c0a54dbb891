"""The cuda backend: the generated ensemble kernel (:mod:`.cuda_source`) run by CuPy.

One GPU thread integrates one member with the fixed-step loop inside the
kernel (rk4, or the variational scheme of
:class:`~lagrangian.integrate.variational.Variational`), in float64 or
float32.  The host side is shared with the CPU build of the same text
(:mod:`.cuda_cpu`): :func:`integrate_kernel` lays out the arguments (states
and parameters member-fastest, so neighbouring threads read neighbouring
words; the step grid of the single run, so the last step lands on t_end) and
reads the outputs back into the observables of
:func:`~lagrangian.ensemble.numpy_backend.integrate_chunk`.

In float32 the Newton iterations of the variational scheme cannot reach a
tolerance of 1e-14; they use ``FLOAT32_NEWTON_TOL`` and ``FLOAT32_ROUNDING_FLOOR``
(a few float32 ulps) unless the integrator asks for more.  The module is
compiled by NVRTC through ``cupy.RawModule`` once per process and text
(CuPy keeps the machine code on disk itself).  CuPy is imported only when a
kernel runs (``pip install ".[cuda]"``).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from ..codegen.cache import built
from ..errors import MissingDependencyError, ModelError
from ..integrate.fixed_step import step_grid
from ..integrate.variational import ROUNDING_FLOOR
from .cuda_source import KERNEL_PARAMETERS, PRECISIONS, kernel_source
from .observables import finish, stops_early

if TYPE_CHECKING:
    from ..integrate.fixed_step import AbstractFixedStepIntegrator
    from ..numeric.compiled import CompiledSystem

#: Newton tolerance (relative to the momenta) and rounding floor of float32 kernels:
#: about 8 and 800 float32 ulps.
FLOAT32_NEWTON_TOL = 1e-6
FLOAT32_ROUNDING_FLOOR = 1e-4
#: Threads per block.
THREADS = 128
#: Arguments the kernel writes (read back after a run).
OUTPUTS = ("final", "flips", "failures", "paths")

#: The compiled kernel per source digest (CuPy's module; the source is in codegen.cache).
_FUNCTIONS: dict[str, object] = {}
_LOCK = threading.Lock()

#: A launcher runs the kernel of (digest, text) on arguments by name, writing the outputs.
Launcher = Callable[[str, str, dict[str, object]], None]


def integrate_cuda(
    compiled: CompiledSystem,
    integrator: AbstractFixedStepIntegrator,
    y0: np.ndarray,
    params: np.ndarray,
    t_end: float,
    names: tuple[str, ...],
    *,
    save_every: int | None = None,
    precision: str = "float64",
) -> dict[str, np.ndarray]:
    """One chunk on the GPU, as :func:`~lagrangian.ensemble.numpy_backend.integrate_chunk`."""
    _cupy()
    return integrate_kernel(
        _launch_on_gpu, compiled, integrator, y0, params, t_end, names,
        save_every=save_every, precision=precision,
    )  # fmt: skip


def integrate_kernel(
    launch: Launcher,
    compiled: CompiledSystem,
    integrator: AbstractFixedStepIntegrator,
    y0: np.ndarray,
    params: np.ndarray,
    t_end: float,
    names: tuple[str, ...],
    *,
    save_every: int | None = None,
    precision: str = "float64",
) -> dict[str, np.ndarray]:
    """One chunk through the generated kernel run by ``launch`` (GPU or the CPU build)."""
    if precision not in PRECISIONS:
        raise ModelError(f"unknown precision '{precision}' (precisions: {', '.join(PRECISIONS)})")
    scheme = _scheme(compiled, integrator)
    digest, text = source_of(compiled, scheme, precision)
    dtype = np.float32 if precision == "float32" else np.float64
    grid = step_grid(0.0, float(t_end), integrator.dt)
    steps = len(grid) - 1
    states = np.ascontiguousarray(np.asarray(y0, dtype=float), dtype=dtype)
    count = states.shape[1]
    p = np.asarray(params, dtype=float)
    every = int(save_every or 0)
    saved = steps // every + 1 if every else 1
    tolerance = float(getattr(integrator, "newton_tol", 1e-14))
    floor = ROUNDING_FLOOR
    if precision == "float32":
        tolerance, floor = max(tolerance, FLOAT32_NEWTON_TOL), FLOAT32_ROUNDING_FLOOR
    arguments: dict[str, object] = {
        "count": np.int64(count),
        "y0": states,
        "params": np.ascontiguousarray(p, dtype=dtype),
        "param_row": np.int64(count if p.ndim == 2 else 1),
        "param_member": np.int64(1 if p.ndim == 2 else 0),
        "times": np.ascontiguousarray(grid[:-1], dtype=dtype),
        "widths": np.ascontiguousarray(np.diff(grid), dtype=dtype),  # as the numpy driver's tb - ta
        "steps": np.int64(steps),
        "track": np.int32("flip_time" in names),
        "stop": np.int32(stops_early(names) and not every),
        "save_every": np.int64(every),
        "newton_tol": dtype(tolerance),
        "rounding_floor": dtype(floor),
        "max_newton": np.int32(getattr(integrator, "max_newton", 30)),
        "final": np.empty_like(states),
        "flips": np.empty(count, dtype=np.int64),
        "failures": np.empty(count, dtype=np.int64),
        "paths": np.empty((saved, states.shape[0], count) if every else 1, dtype=dtype),
    }
    if count:
        launch(digest, text, arguments)
    else:
        arguments["flips"][:] = arguments["failures"][:] = -1
    failures = arguments["failures"]
    if np.any(failures >= 0):
        at = grid[int(np.min(failures[failures >= 0]))]
        raise ModelError(
            f"the ensemble integration failed: Newton's method did not converge at t = {at:.17g}"
        )
    flips = arguments["flips"]
    flip_time = np.where(flips >= 0, grid[np.clip(flips, 0, steps)], np.nan)
    final = arguments["final"].astype(float)
    values = finish(
        compiled, names, t0=grid[0], y0=np.asarray(y0, float), t1=grid[-1], y1=final,
        params=params, flip_time=flip_time,
    )  # fmt: skip
    if every:
        values["paths"] = np.transpose(arguments["paths"], (1, 2, 0)).astype(float)
    values["steps"] = np.array(steps)
    return values


def source_of(compiled: CompiledSystem, scheme: str, precision: str) -> tuple[str, str]:
    """(digest, text) of the kernel of ``compiled`` (made once per equations)."""
    if compiled.has_constraints:
        raise ModelError("backend 'cuda' does not handle constraints (use backend numpy)")
    forms = compiled.forms
    if forms is None:
        raise ModelError(
            "backend 'cuda' generates code from derived equations, not given functions"
        )
    build = lambda: kernel_source(forms, scheme, precision)  # noqa: E731
    return built(forms.fingerprint, "cuda", build, scheme, precision)


def _scheme(compiled: CompiledSystem, integrator: AbstractFixedStepIntegrator) -> str:
    if integrator.name == "rk4":
        return "rk4"
    if integrator.name == "variational":
        return integrator.scheme(compiled)
    raise ModelError(f"backend 'cuda' integrates with rk4 or variational, not {integrator.name}")


def _cupy():
    try:
        import cupy
    except ImportError:
        raise MissingDependencyError("backend 'cuda'", "CuPy and an NVIDIA GPU", "cuda") from None
    try:
        count = cupy.cuda.runtime.getDeviceCount()
    except Exception:  # CUDARuntimeError without a driver; its text spans lines
        count = 0
    if count < 1:
        raise ModelError("backend 'cuda' found no NVIDIA GPU (CuPy is installed)")
    return cupy


def _function(cupy, digest: str, text: str):
    """The compiled kernel of ``text``, once per process (CuPy caches the binary on disk)."""
    with _LOCK:
        function = _FUNCTIONS.get(digest)
        if function is None:
            try:
                module = cupy.RawModule(code=text, options=("--std=c++14",))
                function = module.get_function("lg_integrate")
            except Exception as error:  # NVRTC's CompileException: a long log
                first = str(error).strip().splitlines()[0] if str(error).strip() else ""
                raise ModelError(f"backend 'cuda' cannot compile the kernel: {first}") from None
            _FUNCTIONS[digest] = function
        return function


def _launch_on_gpu(digest: str, text: str, arguments: dict[str, object]) -> None:
    cupy = _cupy()
    function = _function(cupy, digest, text)
    device = {
        name: cupy.asarray(value) if isinstance(value, np.ndarray) else value
        for name, value in arguments.items()
    }
    count = int(arguments["count"])
    blocks = (count + THREADS - 1) // THREADS
    function((blocks,), (THREADS,), tuple(device[name] for _, name in KERNEL_PARAMETERS))
    for name in OUTPUTS:
        arguments[name][...] = cupy.asnumpy(device[name])

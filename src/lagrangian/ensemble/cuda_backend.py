"""The cuda backend: the generated ensemble kernel (:mod:`.cuda_source`) run by CuPy.

One GPU thread integrates one member with the fixed-step loop inside the
kernel (rk4, or the variational scheme of
:class:`~lagrangian.integrate.variational.Variational`), in float64 or
float32.  The host side is shared with the CPU build of the same text
(:mod:`.cuda_cpu`): :class:`AbstractKernelBackend` lays out the arguments (states
and parameters member-fastest, so neighbouring threads read neighbouring
words; the step grid of the single run, so the last step lands on t_end) and
reads the outputs back into the chunk's observables (:meth:`.chunk.Chunk.result`).

In float32 the Newton iterations of the variational scheme cannot reach a
tolerance of 1e-14; they use ``FLOAT32_NEWTON_TOL`` and ``FLOAT32_ROUNDING_FLOOR``
(a few float32 ulps) unless the integrator asks for more.  The module is
compiled by NVRTC through ``cupy.RawModule`` once per process and text
(CuPy keeps the machine code on disk itself).  CuPy is imported only when a
kernel runs (``pip install ".[cuda]"``).
"""

from __future__ import annotations

import threading
from abc import abstractmethod
from typing import TYPE_CHECKING, ClassVar

import numpy as np

from ..codegen.cache import built
from ..errors import MissingDependencyError, ModelError
from .chunk import (
    GPU_CHUNK_SIZE,
    AbstractEnsembleBackend,
    Chunk,
    Outputs,
    Progress,
    generated_forms,
)
from .cuda_source import KERNEL_PARAMETERS, PRECISIONS, kernel_source

if TYPE_CHECKING:
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


class AbstractKernelBackend(AbstractEnsembleBackend):
    """The generated kernel's host side; :meth:`launch` runs it (on the GPU or the CPU)."""

    precisions: ClassVar[tuple[str, ...]] = PRECISIONS
    chunk_size: ClassVar[int] = GPU_CHUNK_SIZE

    @abstractmethod
    def launch(self, digest: str, text: str, arguments: dict[str, object]) -> None:
        """Run the kernel of (digest, text) on ``arguments`` by name, writing the outputs."""

    def integrate(self, chunk: Chunk, progress: Progress | None = None) -> Outputs:
        digest, text = source_of(chunk.compiled, chunk.scheme("cuda"), chunk.precision)
        dtype, grid, count = chunk.dtype, chunk.grid, chunk.count
        states = np.ascontiguousarray(np.asarray(chunk.y0, dtype=float), dtype=dtype)
        p = np.asarray(chunk.params, dtype=float)
        tolerance, floor = chunk.newton.tol, chunk.newton.floor
        if chunk.precision == "float32":
            tolerance, floor = max(tolerance, FLOAT32_NEWTON_TOL), FLOAT32_ROUNDING_FLOOR
        arguments: dict[str, object] = {
            "count": np.int64(count),
            "y0": states,
            "params": np.ascontiguousarray(p, dtype=dtype),
            "param_row": np.int64(count if p.ndim == 2 else 1),
            "param_member": np.int64(1 if p.ndim == 2 else 0),
            "times": np.ascontiguousarray(grid[:-1], dtype=dtype),
            "widths": np.ascontiguousarray(np.diff(grid), dtype=dtype),  # the driver's tb - ta
            "steps": np.int64(chunk.steps),
            "track": np.int32(chunk.track),
            "stop": np.int32(chunk.stop),
            "save_every": np.int64(chunk.every),
            "newton_tol": dtype(tolerance),
            "rounding_floor": dtype(floor),
            "max_newton": np.int32(chunk.newton.iterations),
            "final": np.empty_like(states),
            "flips": np.empty(count, dtype=np.int64),
            "failures": np.empty(count, dtype=np.int64),
            "paths": np.empty((chunk.saved, states.shape[0], count) if chunk.every else 1, dtype),
        }
        if count:
            self.launch(digest, text, arguments)
        else:
            arguments["flips"][:] = arguments["failures"][:] = -1
        chunk.check_newton(arguments["failures"])
        paths = np.transpose(arguments["paths"], (1, 2, 0)) if chunk.every else None
        return chunk.result(arguments["final"], chunk.flip_times(arguments["flips"]), paths)


def source_of(compiled: CompiledSystem, scheme: str, precision: str) -> tuple[str, str]:
    """(digest, text) of the kernel of ``compiled`` (made once per equations)."""
    forms = generated_forms(compiled, "cuda")
    build = lambda: kernel_source(forms, scheme, precision)  # noqa: E731
    return built(forms.fingerprint, "cuda", build, scheme, precision)


class CudaBackend(AbstractKernelBackend):
    """The kernel on an NVIDIA GPU through CuPy."""

    name: ClassVar[str] = "cuda"

    def integrate(self, chunk: Chunk, progress: Progress | None = None) -> Outputs:
        _cupy()
        return super().integrate(chunk, progress)

    def launch(self, digest: str, text: str, arguments: dict[str, object]) -> None:
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

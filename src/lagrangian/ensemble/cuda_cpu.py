"""The CUDA ensemble kernel compiled for the CPU by a C compiler, to check it without a GPU.

The text of :func:`~lagrangian.ensemble.cuda_source.kernel_source` is plain
C99 once ``__global__``, ``__device__`` and ``__forceinline__`` are macros and
``blockIdx``/``blockDim``/``threadIdx`` are globals: a driver sets the block
index to each member in turn and calls the kernel, one member per "thread".
Compiled with ``-ffp-contract=off`` (no fused multiply-adds, as numpy) and
``-Werror=double-promotion`` (float32 text must not compute in double), loaded
with ctypes.  :class:`CudaOnCpuBackend` is :class:`~.cuda_backend.CudaBackend`
with this build instead of the GPU, so tests compare the very text the GPU
runs against the numpy backend.  Needs ``gcc`` (or ``$CC``) on the path.
"""

from __future__ import annotations

import ctypes
import os
import shutil
import subprocess
import tempfile
import threading
from pathlib import Path
from typing import ClassVar

import numpy as np

from ..errors import ModelError
from .cuda_backend import AbstractKernelBackend
from .cuda_source import KERNEL_PARAMETERS

PRELUDE = """\
#define _GNU_SOURCE /* sincos, sincosf */
#include <math.h>
#define __global__
#define __device__ static inline
#define __forceinline__
typedef struct { unsigned int x; } lg_index;
static lg_index blockIdx, blockDim = {1}, threadIdx;
"""

FLAGS = ("-std=gnu99", "-O2", "-fPIC", "-shared", "-ffp-contract=off", "-Werror=double-promotion")

_LIBRARIES: dict[str, CpuKernel] = {}
_LOCK = threading.Lock()


def compiler() -> str | None:
    """The C compiler used: ``$CC`` or gcc, None when there is none."""
    return shutil.which(os.environ.get("CC", "gcc"))


class CpuKernel:
    """The kernel built by the C compiler; call it with the arguments by name."""

    def __init__(self, source: str):
        cc = compiler()
        if cc is None:
            raise ModelError("the CPU build of the cuda kernel needs a C compiler (gcc)")
        self.source = source
        self._directory = tempfile.TemporaryDirectory(prefix="lagrangian-cuda-cpu-")
        folder = Path(self._directory.name)
        (folder / "kernel.c").write_text(PRELUDE + source + _driver(), encoding="utf-8")
        built = subprocess.run(
            [cc, *FLAGS, "-o", str(folder / "kernel.so"), str(folder / "kernel.c"), "-lm"],
            capture_output=True, text=True, check=False,
        )  # fmt: skip
        if built.returncode != 0:
            first = next((line for line in built.stderr.splitlines() if "error" in line), "")
            raise ModelError(f"the CPU build of the cuda kernel failed: {first.strip()}")
        self.warnings = built.stderr
        self._library = ctypes.CDLL(str(folder / "kernel.so"))
        self._run = self._library.lg_integrate_all
        self._run.restype = None
        self._real = ctypes.c_float if "typedef float real;" in source else ctypes.c_double

    def __call__(self, arguments: dict[str, object]) -> None:
        values = []
        for ctype, name in KERNEL_PARAMETERS:
            value = arguments[name]
            if "*" in ctype:
                values.append(ctypes.c_void_p(np.asarray(value).ctypes.data))
            elif ctype == "real":
                values.append(self._real(float(value)))
            elif ctype == "int":
                values.append(ctypes.c_int(int(value)))
            else:
                values.append(ctypes.c_longlong(int(value)))
        self._run(*values)


def cpu_library(source: str) -> CpuKernel:
    """The CPU build of ``source`` (once per process and text)."""
    with _LOCK:
        found = _LIBRARIES.get(source)
        if found is None:
            found = _LIBRARIES[source] = CpuKernel(source)
        return found


class CudaOnCpuBackend(AbstractKernelBackend):
    """The cuda backend with the CPU build of its kernel (not registered: a check)."""

    name: ClassVar[str] = "cuda"

    def launch(self, digest: str, text: str, arguments: dict[str, object]) -> None:
        cpu_library(text)(arguments)


def _driver() -> str:
    """``lg_integrate_all``: the kernel for every member in turn, as one block per member."""
    parameters = ", ".join(f"{ctype} {name}" for ctype, name in KERNEL_PARAMETERS)
    names = ", ".join(name for _, name in KERNEL_PARAMETERS)
    return f"""
void lg_integrate_all({parameters})
{{
    for (long long member = 0; member < count; ++member) {{
        blockIdx.x = (unsigned int)member;
        lg_integrate({names});
    }}
}}
"""

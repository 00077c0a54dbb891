"""Trajectory-steps per second of double-pendulum ensembles on a GPU (RK4, fixed step).

    python benchmarks/gpu.py [--members 1000000] [--steps 10000] [--repeat 3]

On a machine with CuPy and an NVIDIA GPU, against hand-written baselines:

- a hand-written CUDA C kernel (closed-form double-pendulum accelerations, one
  thread per member, RK4 loop inside), float64 and float32, and our ``cuda``
  backend (:class:`lagrangian.ensemble.cuda_backend.CudaBackend`), same
  precisions; both timed from host arrays in to host arrays out;
- with jax installed, a hand-written ``jax.vmap`` RK4 and our ``jax`` backend;
- our variational kernel (midpoint, Newton per step) in float32 and float64.

Everything is warmed up first (compile time excluded).  Medians of
``--repeat`` runs; ratio = ours / hand (< 1: we are slower).  Without a GPU it
says so and exits 0.  Not a test: nothing is asserted.

    python benchmarks/gpu.py --static [--arch sm_90]

needs only ``nvcc`` (no GPU): the generated kernels and the hand-written one,
compiled for ``--arch``, side by side: registers per thread, spilled bytes, and
the PTX instructions of the whole kernel (all, double- or single-precision
fused multiply-adds, divisions, branches), a proxy for the work per step.
"""

from __future__ import annotations

import argparse
import re
import shutil
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import lagrangian as lg
from lagrangian.errors import ModelError
from lagrangian.integrate import method_class
from lagrangian.numeric import compile_equations

HAND_KERNEL = r"""
typedef REAL real;
__device__ __forceinline__ void derivative(const real *y, const real *p, real *out)
{
    real m1 = p[0], m2 = p[1], l1 = p[2], l2 = p[3], g = p[4];
    real t1 = y[0], t2 = y[1], w1 = y[2], w2 = y[3];
    real d = t1 - t2, sd = SIN(d), cd = COS(d);
    real den = (real)2 * m1 + m2 - m2 * COS((real)2 * d);
    out[0] = w1;
    out[1] = w2;
    out[2] = (-g * ((real)2 * m1 + m2) * SIN(t1) - m2 * g * SIN(t1 - (real)2 * t2)
              - (real)2 * sd * m2 * (w2 * w2 * l2 + w1 * w1 * l1 * cd)) / (l1 * den);
    out[3] = ((real)2 * sd * (w1 * w1 * l1 * (m1 + m2) + g * (m1 + m2) * COS(t1)
              + w2 * w2 * l2 * m2 * cd)) / (l2 * den);
}

extern "C" __global__ void run(long long count, const real *y0, const real *params,
                               real dt, long long steps, real *final)
{
    long long b = (long long)blockIdx.x * blockDim.x + threadIdx.x;
    if (b >= count) return;
    real y[4], p[5], k1[4], k2[4], k3[4], k4[4], s[4];
    for (int i = 0; i < 4; ++i) y[i] = y0[i * count + b];
    for (int j = 0; j < 5; ++j) p[j] = params[j];
    real half = dt / (real)2, sixth = dt / (real)6;
    for (long long step = 0; step < steps; ++step) {
        derivative(y, p, k1);
        for (int i = 0; i < 4; ++i) s[i] = y[i] + half * k1[i];
        derivative(s, p, k2);
        for (int i = 0; i < 4; ++i) s[i] = y[i] + half * k2[i];
        derivative(s, p, k3);
        for (int i = 0; i < 4; ++i) s[i] = y[i] + dt * k3[i];
        derivative(s, p, k4);
        for (int i = 0; i < 4; ++i)
            y[i] += sixth * (k1[i] + (real)2 * k2[i] + (real)2 * k3[i] + k4[i]);
    }
    for (int i = 0; i < 4; ++i) final[i * count + b] = y[i];
}
"""


def gpu():
    """CuPy when it finds a device, else None."""
    try:
        import cupy

        return cupy if cupy.cuda.runtime.getDeviceCount() > 0 else None
    except Exception:  # no CuPy, no driver
        return None


def hand_cuda(cupy, precision: str):
    """run(y0 (4, B), params (5,), dt, steps) -> final (4, B) with the hand kernel."""
    kernel = cupy.RawKernel(hand_source(precision), "run")
    dtype = np.float32 if precision == "float32" else np.float64

    def run(y0, params, dt, steps):
        states = cupy.asarray(y0, dtype=dtype)
        count = states.shape[1]
        final = cupy.empty_like(states)
        blocks = (count + 127) // 128
        kernel(
            (blocks,), (128,),
            (np.int64(count), states, cupy.asarray(params, dtype=dtype), dtype(dt),
             np.int64(steps), final),
        )  # fmt: skip
        return final.get()

    return run


def hand_jax(jax, steps: int, dt: float):
    """A jitted jax.vmap RK4 of the closed-form double pendulum."""
    jnp = jax.numpy

    def derivative(y, p):
        m1, m2, l1, l2, g = p
        t1, t2, w1, w2 = y
        d = t1 - t2
        den = 2 * m1 + m2 - m2 * jnp.cos(2 * d)
        a1 = (
            -g * (2 * m1 + m2) * jnp.sin(t1)
            - m2 * g * jnp.sin(t1 - 2 * t2)
            - 2 * jnp.sin(d) * m2 * (w2 * w2 * l2 + w1 * w1 * l1 * jnp.cos(d))
        ) / (l1 * den)
        a2 = (
            2
            * jnp.sin(d)
            * (
                w1 * w1 * l1 * (m1 + m2)
                + g * (m1 + m2) * jnp.cos(t1)
                + w2 * w2 * l2 * m2 * jnp.cos(d)
            )
        ) / (l2 * den)
        return jnp.stack([w1, w2, a1, a2])

    def one(y, p):
        def step(_, y):
            k1 = derivative(y, p)
            k2 = derivative(y + dt / 2 * k1, p)
            k3 = derivative(y + dt / 2 * k2, p)
            k4 = derivative(y + dt * k3, p)
            return y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)

        return jax.lax.fori_loop(0, steps, step, y)

    return jax.jit(jax.vmap(one, in_axes=(1, None), out_axes=1))


def median_rate(function, work: int, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return work / statistics.median(times)


def hand_source(precision: str) -> str:
    single = precision == "float32"
    source = HAND_KERNEL.replace("REAL", "float" if single else "double")
    source = source.replace("SIN", "sinf" if single else "sin")
    return source.replace("COS", "cosf" if single else "cos")


def static(arch: str) -> None:
    """Registers, spills and PTX instruction counts of our kernels and the hand-written one."""
    nvcc = shutil.which("nvcc")
    if nvcc is None:
        print("no nvcc on the path: nothing to compile")
        return
    from lagrangian.codegen.forms import symbolic_forms
    from lagrangian.ensemble.cuda_source import kernel_source

    forms = symbolic_forms(lg.load("double_pendulum").equations_of_motion(), {})
    kernels = {}
    for precision in ("float64", "float32"):
        kernels[f"hand rk4 {precision}"] = hand_source(precision)
        for method in ("rk4", "variational"):
            kernels[f"ours {method} {precision}"] = kernel_source(forms, method, precision)[1]
    counted = {
        "all": r"^\s+[a-z]", "fma.f64": r"fma\.rn\.f64", "fma.f32": r"fma\.rn\.f32",
        "div": r"\bdiv\.", "branch": r"\bbra\b",
    }  # fmt: skip
    print(f"double pendulum kernels, nvcc -arch={arch} -O3 (PTX instructions of the whole kernel)")
    print(
        f"  {'kernel':<26}{'registers':>10}{'spilled B':>10}" + "".join(f"{k:>9}" for k in counted)
    )
    with tempfile.TemporaryDirectory() as folder:
        for label, text in kernels.items():
            source = Path(folder) / "kernel.cu"
            source.write_text(text)
            built = subprocess.run(
                [nvcc, f"-arch={arch}", "-O3", "-cubin", "-Xptxas", "-v", "-o",
                 str(Path(folder) / "kernel.cubin"), str(source)],
                capture_output=True, text=True, check=True,
            )  # fmt: skip
            registers = re.search(r"Used (\d+) registers", built.stderr).group(1)
            spilled = sum(map(int, re.findall(r"(\d+) bytes spill", built.stderr)))
            ptx = Path(folder) / "kernel.ptx"
            subprocess.run(
                [nvcc, f"-arch={arch}", "-O3", "-ptx", "-o", str(ptx), str(source)], check=True
            )
            lines = ptx.read_text().splitlines()
            counts = [sum(bool(re.search(p, line)) for line in lines) for p in counted.values()]
            print(f"  {label:<26}{registers:>10}{spilled:>10}" + "".join(f"{c:>9}" for c in counts))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--members", type=int, default=1_000_000)
    parser.add_argument("--steps", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--static", action="store_true", help="compile with nvcc only (no GPU)")
    parser.add_argument("--arch", default="sm_90", help="GPU architecture for --static")
    args = parser.parse_args()
    if args.static:
        static(args.arch)
        return
    cupy = gpu()
    if cupy is None:
        print("no NVIDIA GPU with CuPy here: nothing to measure (pip install 'lagrangian[cuda]')")
        return
    from lagrangian.ensemble.chunk import Chunk
    from lagrangian.ensemble.cuda_backend import CudaBackend

    compiled = compile_equations(lg.load("double_pendulum").equations_of_motion())
    rng = np.random.default_rng(0)
    theta = rng.uniform(-3.0, 3.0, size=(2, args.members))
    y0 = np.vstack([theta, np.zeros_like(theta)])
    p = compiled.parameter_vector()
    dt = 0.01
    work = args.members * args.steps
    name = cupy.cuda.runtime.getDeviceProperties(0)["name"].decode()
    print(f"double pendulum, dt={dt}, {args.members} members x {args.steps} steps, {name}")

    def ours(method: str, precision: str, steps: int):
        integrator = method_class(method).configure(t_span=(0.0, steps * dt), dt=dt)
        chunk = Chunk(
            compiled, integrator, y0, p, steps * dt, ("final_state",), precision=precision
        )
        return CudaBackend().integrate(chunk)

    rk4_rates = {}
    for precision in ("float64", "float32"):
        hand = hand_cuda(cupy, precision)
        hand(y0, p, dt, 2)
        ours("rk4", precision, 2)
        hand_rate = median_rate(lambda h=hand: h(y0, p, dt, args.steps), work, args.repeat)
        rate = median_rate(lambda q=precision: ours("rk4", q, args.steps), work, args.repeat)
        rk4_rates[precision] = rate
        print(f"  rk4 {precision}  hand CUDA kernel {hand_rate:10.3g}  cuda backend "
              f"{rate:10.3g} trajectory-steps/s  ours/hand {rate / hand_rate:.2f}")  # fmt: skip
    short = min(args.steps, 200)
    check = ours("rk4", "float64", short)["final_theta1"]
    agreement = float(np.max(np.abs(check - hand_cuda(cupy, "float64")(y0, p, dt, short)[0])))
    print(f"  max |theta1 ours - hand| after {short} steps (float64): {agreement:.2e}")
    for precision in ("float32", "float64"):
        ours("variational", precision, 2)
        rate = median_rate(lambda q=precision: ours("variational", q, args.steps), work, 1)
        print(f"  variational (midpoint) {precision}  cuda backend {rate:10.3g} trajectory-steps/s"
              f"  time / rk4 time {rk4_rates[precision] / rate:.2f}")  # fmt: skip
    _jax(compiled, y0, p, dt, args)


def _jax(compiled, y0, p, dt, args) -> None:
    try:
        import jax
    except ImportError:
        print("  (jax not installed: no jax comparison)")
        return
    from lagrangian.ensemble import run_ensemble

    jax.config.update("jax_enable_x64", True)
    work = args.members * args.steps
    hand = hand_jax(jax, args.steps, dt)
    states, params = jax.numpy.asarray(y0), jax.numpy.asarray(p)
    hand(states, params).block_until_ready()
    hand_rate = median_rate(lambda: hand(states, params).block_until_ready(), work, args.repeat)
    initial = {"theta1": y0[0], "theta2": y0[1]}

    def ours(steps: int):
        return run_ensemble(
            compiled, initial=initial, t_end=steps * dt, dt=dt, backend="jax",
            chunk_size=args.members,
        )  # fmt: skip

    try:
        ours(2)
    except ModelError as error:
        print(f"  jax.vmap hand {hand_rate:10.3g} trajectory-steps/s; jax backend: {error}")
        return
    rate = median_rate(lambda: ours(args.steps), work, args.repeat)
    print(f"  rk4 float64  hand jax.vmap {hand_rate:10.3g}  jax backend {rate:10.3g} "
          f"trajectory-steps/s  ours/hand {rate / hand_rate:.2f}")  # fmt: skip


if __name__ == "__main__":
    main()

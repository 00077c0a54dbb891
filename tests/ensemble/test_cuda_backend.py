"""The cuda backend: its generated kernel text, checked on the CPU against the numpy backend.

No GPU is needed for most of this: the kernel text compiles as C with a few
macros (:mod:`lagrangian.ensemble.cuda_cpu`), and that build must give the
numpy backend's numbers (float64: to rounding; float32: to float32's
accuracy over a short run).  The GPU tests run only where CuPy finds a device.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.ensemble import run_ensemble
from lagrangian.ensemble.chunk import Chunk
from lagrangian.ensemble.cuda_backend import CudaBackend, source_of
from lagrangian.ensemble.cuda_cpu import CudaOnCpuBackend, compiler
from lagrangian.ensemble.cuda_source import kernel_source
from lagrangian.ensemble.members import members
from lagrangian.errors import MissingDependencyError, ModelError
from lagrangian.integrate import method_class
from lagrangian.numeric import compile_equations

needs_cc = pytest.mark.skipif(compiler() is None, reason="no C compiler (gcc) for the CPU build")

# gyroscopic (non-uniform magnetic field), anharmonic, Rayleigh dissipation, driven in time
TRAP = """
name = "Charged particle in a trap"
coordinates = ["x", "y", "z"]
kinetic = "(x_dot^2 + y_dot^2 + z_dot^2)/2 + B*(1 + z^2/4)*(x*y_dot - y*x_dot)/2"
potential = "k*(x^2 + y^2 + 2*z^2)/2 + a*(x^2 + y^2)^2/4"
dissipation = "b*(x_dot^2 + y_dot^2 + z_dot^2)/2"
[parameters]
B = 1.5
k = 1.0
a = 0.3
b = 0.1
F = 0.5
w = 2.0
[forces]
z = "F*cos(w*t)"
"""

# a parametrically driven pendulum with a generalized force (damping and a drive)
DRIVEN = """
name = "Driven pendulum"
coordinates = ["theta"]
kinetic = "m*l^2*theta_dot^2/2"
potential = "-m*g*l*(1 + e*cos(w*t))*cos(theta)"
[parameters]
m = 1.0
l = 1.0
g = 9.81
e = 0.3
w = 5.0
c = 0.2
A = 1.0
[forces]
theta = "-c*theta_dot + A*sin(w*t/2)"
"""

# separable (constant, coupled mass matrix; V(q) only): the variational method is Stormer-Verlet
CHAIN = """
name = "Anharmonic chain"
coordinates = ["x1", "x2", "x3"]
kinetic = "m*(x1_dot^2 + x2_dot^2 + x3_dot^2)/2 + mu*(x1_dot*x2_dot + x2_dot*x3_dot)"
potential = "k*(x1^2 + (x2-x1)^2 + (x3-x2)^2 + x3^2)/2 + a*(x1^4 + x2^4 + x3^4)/4 + s*sin(x1)*x3"
[parameters]
m = 1.0
mu = 0.3
k = 2.0
a = 0.5
s = 0.4
"""

SYSTEMS = {
    "double_pendulum": (
        lambda: lg.load("double_pendulum"),
        {"theta1": np.linspace(-2.5, 2.5, 6), "theta2": 1.0, "theta2_dot": 0.5},
        {"m2": [1.0, 2.0, 0.5, 1.0, 1.5, 0.8]},
    ),
    "trap": (
        lambda: lg.loads(TRAP),
        {"x": np.linspace(-1, 1, 5), "y": 0.5, "z": 0.3, "x_dot": 0.2, "z_dot": -0.4},
        {"B": [1.5, 0.5, 2.0, 1.0, 3.0]},
    ),
    "driven": (
        lambda: lg.loads(DRIVEN),
        {"theta": np.linspace(-3, 3, 7), "theta_dot": 0.5},
        {},
    ),
    "chain": (
        lambda: lg.loads(CHAIN),
        {"x1": np.linspace(-1, 1, 4), "x2": 0.5, "x3_dot": -0.7},
        {"a": 0.5},
    ),
}
#: float32 agrees with float64 to about 1e-5 after one time unit; chaos amplifies it.
FLOAT32_TOLERANCE = 5e-4


@pytest.fixture(scope="module")
def compiled_systems():
    return {
        name: compile_equations(load().equations_of_motion())
        for name, (load, _, _) in SYSTEMS.items()
    }


def _cpu_run(compiled, initial, params, *, method, precision, t_end, dt, names, save_every=None):
    """The CPU build of the cuda kernel on the batch run_ensemble would make."""
    batch = members(compiled, initial, params)
    integrator = method_class(method).configure(t_span=(0.0, t_end), dt=dt)
    chunk = Chunk(
        compiled, integrator, batch.y0, batch.params, t_end, names,
        save_every=save_every, precision=precision,
    )  # fmt: skip
    return CudaOnCpuBackend().integrate(chunk)


@needs_cc
@pytest.mark.parametrize("precision", ["float64", "float32"])
@pytest.mark.parametrize("method", ["rk4", "variational"])
@pytest.mark.parametrize("system", list(SYSTEMS))
def test_cpu_build_equals_numpy(compiled_systems, system, method, precision):
    compiled = compiled_systems[system]
    _, initial, params = SYSTEMS[system]
    names = ("final_state", "energy_drift", "flip_time")
    options = dict(t_end=1.0, dt=0.01)
    expected = run_ensemble(
        compiled, initial=initial, params=params, method=method, observables=names, **options
    )
    got = _cpu_run(
        compiled, initial, params, method=method, precision=precision, names=names, **options
    )
    tolerance = 1e-12 if precision == "float64" else FLOAT32_TOLERANCE
    for name, values in expected.final_state.items():
        np.testing.assert_allclose(got[f"final_{name}"], values, rtol=tolerance, atol=tolerance)
    np.testing.assert_array_equal(np.isnan(got["flip_time"]), np.isnan(expected["flip_time"]))
    if precision == "float64":
        np.testing.assert_allclose(got["flip_time"], expected["flip_time"], equal_nan=True)
        np.testing.assert_allclose(got["energy_drift"], expected["energy_drift"], atol=1e-12)


@needs_cc
def test_float32_newton_converges_on_grown_angles(compiled_systems):
    # the same motions 100 turns further on: float32 rounds the angles 600 times coarser,
    # and the momenta inherit that noise; Newton must accept it at the rounding floor
    # (the fixed floor failed a member within 8 time units; on the GPU, one in 1e9 steps)
    compiled = compiled_systems["double_pendulum"]
    theta = np.random.default_rng(1).uniform(-3.0, 3.0, size=(2, 64))
    turns = 2 * np.pi * 100
    initial = {"theta1": theta[0] + turns, "theta2": theta[1] + turns}
    options = dict(method="variational", names=("final_state",), dt=0.01)
    got = _cpu_run(compiled, initial, {}, precision="float32", t_end=20.0, **options)
    assert np.all(np.isfinite(got["final_theta1"]))
    short = _cpu_run(compiled, initial, {}, precision="float32", t_end=1.0, **options)
    reference = _cpu_run(
        compiled, {"theta1": theta[0], "theta2": theta[1]}, {}, precision="float64",
        t_end=1.0, **options,
    )  # fmt: skip
    np.testing.assert_allclose(short["final_theta1"] - turns, reference["final_theta1"], atol=1e-2)


def test_variational_picks_the_numpy_scheme(compiled_systems):
    chain, trap = compiled_systems["chain"], compiled_systems["trap"]
    assert chain.separable and not trap.separable
    for compiled, scheme in ((chain, "stormer-verlet"), (trap, "midpoint")):
        integrator = method_class("variational").configure(t_span=(0.0, 1.0), dt=0.1)
        assert integrator.scheme(compiled) == scheme
        header = kernel_source(_forms(compiled), "variational", "float64")[1].splitlines()[0]
        assert f"{scheme}, float64" in header


@needs_cc
def test_flip_times_stop_early_and_paths(compiled_systems):
    compiled = compiled_systems["double_pendulum"]
    initial = {"theta1": [3.5, 0.0, 3.0, 2.0], "theta1_dot": [0.0, 0.0, 3.0, 1.0]}
    options = dict(t_end=2.0, dt=0.01)
    expected = run_ensemble(compiled, initial=initial, observables="flip_time", **options)
    got = _cpu_run(compiled, initial, {}, method="rk4", precision="float64",
                   names=("flip_time",), **options)  # fmt: skip
    np.testing.assert_array_equal(got["flip_time"], expected["flip_time"])
    assert got["flip_time"][0] == 0.0 and np.isnan(got["flip_time"][1])
    paths = run_ensemble(compiled, initial=initial, save_every=20, method="variational", **options)
    got = _cpu_run(compiled, initial, {}, method="variational", precision="float64",
                   names=("final_state",), save_every=20, **options)  # fmt: skip
    assert got["paths"].shape == (4, 4, 11)
    for i, name in enumerate(["theta1", "theta2", "theta1_dot", "theta2_dot"]):
        np.testing.assert_allclose(got["paths"][i], paths[f"path_{name}"], rtol=1e-12, atol=1e-12)


def _forms(compiled):
    from lagrangian.codegen.definitions import function_definitions
    from lagrangian.codegen.forms import symbolic_forms

    system = compiled.equations.system
    return symbolic_forms(
        compiled.equations, function_definitions(system, dict(compiled.definitions))
    )


DOUBLE_FUNCTIONS = r"\b(sin|cos|tan|exp|log|sqrt|pow|fabs|atan2|asin|acos|atan|sinh|cosh|tanh)\("


@pytest.mark.parametrize("scheme", ["rk4", "midpoint", "stormer-verlet"])
def test_float32_text_computes_in_float(compiled_systems, scheme):
    digest, text = source_of(compiled_systems["driven"], scheme, "float32")
    assert "typedef float real;" in text and "double" not in text
    assert not re.search(DOUBLE_FUNCTIONS, text)
    # every floating literal carries the f suffix (no silent promotion to double)
    assert not re.findall(r"\b\d+\.\d*(?:e[-+]?\d+)?(?![\dfFe])", text)
    double_digest, double_text = source_of(compiled_systems["driven"], scheme, "float64")
    assert digest != double_digest and "typedef double real;" in double_text
    assert re.search(DOUBLE_FUNCTIONS, double_text)


def test_the_text_names_no_model_symbol(compiled_systems):
    text = source_of(compiled_systems["double_pendulum"], "midpoint", "float64")[1]
    assert "theta" not in text and "m1" not in text
    assert 'extern "C"' in text and "__global__ void lg_integrate(" in text


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("nvcc") is None, reason="no CUDA compiler (nvcc)")
@pytest.mark.parametrize("precision", ["float64", "float32"])
def test_the_text_compiles_with_nvcc(compiled_systems, tmp_path, precision):
    for index, scheme in enumerate(["rk4", "midpoint", "stormer-verlet"]):
        source = tmp_path / f"kernel{index}.cu"
        source.write_text(source_of(compiled_systems["trap"], scheme, precision)[1])
        built = subprocess.run(
            ["nvcc", "--ptx", "-arch=sm_80", "-o", str(tmp_path / "k.ptx"), str(source)],
            capture_output=True, text=True, check=False,
        )  # fmt: skip
        assert built.returncode == 0, built.stderr


def test_errors_are_one_line(compiled_systems, monkeypatch):
    compiled = compiled_systems["driven"]
    integrator = method_class("rk4").configure(t_span=(0.0, 1.0), dt=0.1)
    y0, params = np.zeros((2, 1)), compiled.parameter_vector()
    monkeypatch.setitem(sys.modules, "cupy", None)  # import cupy raises ImportError
    with pytest.raises(MissingDependencyError) as caught:
        CudaBackend().integrate(Chunk(compiled, integrator, y0, params, 1.0, ("final_state",)))
    assert str(caught.value) == (
        "backend 'cuda' needs CuPy and an NVIDIA GPU: "
        'pip install ".[cuda]" in a clone of lagrangian'
    )
    with pytest.raises(ModelError, match=r"^unknown precision 'half' \(precisions: float64, "):
        Chunk(compiled, integrator, y0, params, 1.0, ("final_state",), precision="half")
    disc = compile_equations(lg.load("rolling_disc").equations_of_motion())
    with pytest.raises(ModelError, match=r"^backend 'cuda' does not handle constraints"):
        source_of(disc, "rk4", "float64")


def _gpu_available() -> bool:
    try:
        import cupy

        return cupy.cuda.runtime.getDeviceCount() > 0
    except Exception:
        return False


@pytest.mark.skipif(not _gpu_available(), reason="needs CuPy and an NVIDIA GPU")
@pytest.mark.parametrize("precision", ["float64", "float32"])
@pytest.mark.parametrize("method", ["rk4", "variational"])
@pytest.mark.parametrize("system", ["double_pendulum", "trap"])
def test_gpu_equals_numpy(compiled_systems, system, method, precision):
    compiled = compiled_systems[system]
    _, initial, params = SYSTEMS[system]
    batch = members(compiled, initial, params)
    integrator = method_class(method).configure(t_span=(0.0, 1.0), dt=0.01)
    names = ("final_state", "flip_time")
    expected = run_ensemble(
        compiled, initial=initial, params=params, method=method, t_end=1.0, dt=0.01,
        observables=names,
    )  # fmt: skip
    got = CudaBackend().integrate(
        Chunk(compiled, integrator, batch.y0, batch.params, 1.0, names, precision=precision)
    )
    tolerance = 1e-11 if precision == "float64" else FLOAT32_TOLERANCE  # fused multiply-adds
    for name, values in expected.final_state.items():
        np.testing.assert_allclose(got[f"final_{name}"], values, rtol=tolerance, atol=tolerance)

"""Code export: the generated C (compiled by the system compiler) and NumPy files agree
with our own compiled right-hand side, mass matrix and forcing at random states to 1e-12;
Julia and MATLAB files are checked for their structure (and run when julia / octave are
installed).  Systems: the double pendulum, a shaken cart-pole with inputs and explicit
time dependence, a nonholonomic (rolling disc) and a holonomic (Cartesian pendulum)
constrained system, handled with multipliers and Baumgarte's stabilisation."""

from __future__ import annotations

import ctypes
import functools
import importlib.util
import re
import shutil
import subprocess

import numpy as np
import pytest

import lagrangian as lg
from lagrangian.cli import main
from lagrangian.export import LANGUAGES, export_code, write_code
from lagrangian.numeric import compile_equations

SHAKEN_CART_POLE = """
name = "Shaken cart-pole"
description = "A cart shaken vertically (amplitude a, rate w) carries a pendulum."
coordinates = ["x", "theta"]
dissipation = "b*theta_dot^2/2"
[parameters]
M = 1.0
m = 0.3
l = 0.8
g = 9.81
a = 0.05
w = 12.0
b = 0.1
[[particles]]
name = "cart"
mass = "M"
position = ["x", "a*cos(w*t)"]
[[particles]]
name = "bob"
mass = "m"
position = ["x + l*sin(theta)", "a*cos(w*t) - l*cos(theta)"]
[gravity]
g = "g"
[inputs]
F = "x"
tau = "theta"
"""

SPECIAL_FUNCTIONS = """
name = "Special functions"
description = "pi, E, atan2, Abs, sign, log, sqrt, cosh, tanh, sec, cot in T, V and a force."
coordinates = ["x", "y"]
kinetic = "m*(x_dot^2 + (1 + y^2/4)*y_dot^2)/2 + c*atan2(y, 2 + x^2)*x_dot*y_dot/10"
potential = "k*(log(2 + x^2) + sqrt(1 + y^2)) + E*cosh(x/3) + pi*Abs(x)/10"
[parameters]
m = 1.0
c = 1.0
k = 2.0
b = 0.3
[forces]
x = "-b*sign(x_dot)"
y = "tanh(y)*sec(x/2) + cot(1 + y/4)/5"
"""

SYSTEMS = {
    "double_pendulum": lambda: lg.load("double_pendulum"),
    "shaken_cart_pole": lambda: lg.loads(SHAKEN_CART_POLE),
    "rolling_disc": lambda: lg.load("rolling_disc"),
    "cartesian_pendulum": lambda: lg.load("cartesian_pendulum"),
    "special_functions": lambda: lg.loads(SPECIAL_FUNCTIONS),
}


@functools.cache
def built(name: str) -> lg.System:
    """SYSTEMS[name], loaded once per module: the systems are immutable and their
    derivation is kept with them, so the tests share it instead of deriving it anew."""
    return SYSTEMS[name]()


STATES = 12
RTOL = 1e-12


def random_cases(system, rng):
    """(t, y, params (export order), u, params of our compiled system) at random points."""
    inputs = set(system.input_names)
    names = [p.name for p in system.parameters if p.name not in inputs]
    n = len(system.coordinates)
    for _ in range(STATES):
        t = rng.uniform(0.0, 3.0)
        y = rng.uniform(-1.5, 1.5, 2 * n)
        params = {name: rng.uniform(0.5, 2.0) for name in names}
        u = {name: rng.uniform(-1.0, 1.0) for name in system.input_names}
        yield t, y, np.array([params[k] for k in names]), np.array(list(u.values())), params | u


def close(ours, theirs):
    ours, theirs = np.asarray(ours, dtype=float), np.asarray(theirs, dtype=float)
    scale = max(np.abs(theirs).max(), 1e-300)
    return ours.shape == theirs.shape and np.abs(ours - theirs).max() <= RTOL * scale


def c_library(text, folder, compiler):
    source = folder / "model.c"
    source.write_text(text)
    library = folder / "model.so"
    command = [compiler, "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror",
               "-shared", "-fPIC", str(source), "-o", str(library), "-lm"]  # fmt: skip
    subprocess.run(command, check=True, capture_output=True, text=True)
    lib = ctypes.CDLL(str(library))
    pointer = ctypes.POINTER(ctypes.c_double)
    for name in ("rhs", "mass_matrix", "forcing"):
        function = getattr(lib, name)
        function.argtypes = [ctypes.c_double, pointer, pointer, pointer, pointer]
    lib.rhs.restype = ctypes.c_int
    return lib


def call_c(function, t, y, params, u, size):
    def array(values):
        values = np.ascontiguousarray(values, dtype=float)
        return values, values.ctypes.data_as(ctypes.POINTER(ctypes.c_double))

    out = np.zeros(size)
    y, y_ptr = array(y)
    params, p_ptr = array(params if len(params) else [0.0])
    u, u_ptr = array(u) if len(u) else (None, None)
    status = function(t, y_ptr, p_ptr, u_ptr, out.ctypes.data_as(ctypes.POINTER(ctypes.c_double)))
    return status, out


@pytest.mark.parametrize("name", SYSTEMS)
def test_c_matches_our_compiled_rhs(name, compiler, tmp_path, np_rng):
    system = built(name)
    lib = c_library(export_code(system, "c"), tmp_path, compiler)
    compiled = compile_equations(system.equations_of_motion())
    n = len(system.coordinates)
    for t, y, params, u, ours in random_cases(system, np_rng):
        vector = compiled.parameter_vector(ours)
        status, rhs = call_c(lib.rhs, t, y, params, u, 2 * n)
        assert status == 0
        assert close(rhs, compiled.rhs(t, y, vector))
        _, mass = call_c(lib.mass_matrix, t, y, params, u, n * n)
        assert close(mass.reshape(n, n), compiled.mass_matrix(t, y[:n], y[n:], vector))
        _, forcing = call_c(lib.forcing, t, y, params, u, n)
        assert close(forcing, compiled.forcing(t, y[:n], y[n:], vector))
        if len(u):  # u = NULL: every input 0
            _, unforced = call_c(lib.rhs, t, y, params, [], 2 * n)
            at_zero = compiled.parameter_vector(ours | dict.fromkeys(system.input_names, 0.0))
            assert close(unforced, compiled.rhs(t, y, at_zero))


def test_c_reports_a_singular_mass_matrix(compiler, tmp_path):
    """x = r cos(phi), y = r sin(phi): M = diag(m, m r^2) is singular at r = 0."""
    system = lg.System.from_particles(
        ["r", "phi"], [lg.Particle("p", "m", ("r*cos(phi)", "r*sin(phi)"))]
    )
    lib = c_library(export_code(system, "c"), tmp_path, compiler)
    status, _ = call_c(lib.rhs, 0.0, [0.0, 0.3, 0.1, 0.2], [1.0], [], 4)
    assert status == 1
    status, _ = call_c(lib.rhs, 0.0, [0.5, 0.3, 0.1, 0.2], [1.0], [], 4)
    assert status == 0


def load_module(path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name", SYSTEMS)
def test_numpy_file_matches_our_compiled_rhs(name, tmp_path, np_rng):
    system = built(name)
    path = write_code(system, "numpy", tmp_path / f"{name}_rhs.py")
    text = path.read_text()
    assert "lagrangian" not in re.sub(r"(?m)^#.*$", "", text)  # self-contained
    module = load_module(path)
    compiled = compile_equations(system.equations_of_motion())
    assert tuple(p for p in compiled.parameter_names if p not in module.INPUTS) == module.PARAMETERS
    for t, y, params, u, ours in random_cases(system, np_rng):
        vector = compiled.parameter_vector(ours)
        n = len(system.coordinates)
        assert close(module.rhs(t, y, params, u), compiled.rhs(t, y, vector))
        assert close(
            module.mass_matrix(t, y, params, u), compiled.mass_matrix(t, y[:n], y[n:], vector)
        )
        assert close(module.forcing(t, y, params, u), compiled.forcing(t, y[:n], y[n:], vector))


def test_numpy_defaults_and_a_run_with_scipy(tmp_path):
    """With the default parameters and no u, a solve_ivp run of the exported rhs ends where
    our own simulate does."""
    from scipy.integrate import solve_ivp

    system = built("double_pendulum")
    module = load_module(write_code(system, "numpy", tmp_path / "dp.py"))
    assert module.DEFAULT_PARAMS.tolist() == [system.parameter_values[p] for p in module.PARAMETERS]
    y0 = [1.0, 0.5, 0.0, 0.0]
    run = solve_ivp(module.rhs, (0, 2.0), y0, rtol=1e-11, atol=1e-11, method="DOP853")
    initial = dict(zip(module.COORDINATES, y0, strict=False))
    ours = system.simulate(t_end=2.0, initial=initial, rtol=1e-11, atol=1e-11)
    final = [ours.final_state[k] for k in ("theta1", "theta2", "theta1_dot", "theta2_dot")]
    assert np.allclose(run.y[:, -1], final, atol=1e-7)


@pytest.mark.parametrize("name", SYSTEMS)
def test_cse_leaves_no_repeated_call(name):
    """Within each generated C function no call of sin, cos, ... is written twice."""
    text = export_code(built(name), "c")
    if name not in ("cartesian_pendulum", "special_functions"):  # little to share there
        assert "const double w_0 = " in text
    for body in re.findall(r"\n\{\n(.*?)\n\}\n", text, flags=re.S):
        calls = re.findall(r"\b(?:sin|cos|tan|exp|sqrt|pow)\([^()]*\)", body)
        assert len(calls) == len(set(calls)), sorted(c for c in calls if calls.count(c) > 1)


# -- Julia and MATLAB: structure (and a run where the language is installed) ---------------
BLOCK_OPENERS = re.compile(r"^\s*(function|for|if|while)\b")


def balanced(text, comment):
    lines = [line for line in text.splitlines() if not line.lstrip().startswith(comment)]
    opened = sum(bool(BLOCK_OPENERS.match(line)) for line in lines)
    closed = sum(line.strip() == "end" for line in lines)
    return opened == closed and opened > 0


def assigned_before_use(text, assign):
    """Every temporary w_k is assigned before any line reads it (within each function)."""
    for block in re.split(r"\n(?=function )", text):
        seen = set()
        for line in block.splitlines():
            target = re.match(assign, line)
            used = set(re.findall(r"\bw_\d+\b", line.split("=", 1)[1] if "=" in line else ""))
            if not used <= seen:
                return False
            if target:
                seen.add(target.group(1))
    return True


@pytest.mark.parametrize("name", SYSTEMS)
def test_julia_structure(name):
    system = built(name)
    text = export_code(system, "julia")
    assert balanced(text, "#")
    assert assigned_before_use(text, r"\s*(w_\d+) = ")
    for function in ("mass_matrix", "forcing", "rhs"):
        assert f"function {function}(t, y, params=DEFAULT_PARAMS, u=DEFAULT_INPUTS)" in text
    assert "M \\ f" in text or "K \\ vcat(f, b)" in text
    for parameter in system.parameters:
        assert re.search(rf"# +params\[\d+\] = {parameter.name} |# +u\[\d+\] = {parameter.name}$",
                         text, flags=re.M)  # fmt: skip
    assert "[0]" not in text  # 1-based
    assert "atan2(" not in text  # Julia's two-argument arctangent is atan(y, x)


@pytest.mark.parametrize("name", SYSTEMS)
def test_matlab_structure(name):
    system = built(name)
    text = export_code(system, "matlab", name="model_rhs")
    assert text.startswith("function model = model_rhs()\n")
    assert balanced(text, "%")
    assert assigned_before_use(text, r"(w_\d+) = ")
    assert all(line.endswith((";", "end")) or line.startswith(("%", "function", "if")) or not line
               for line in text.splitlines() if not line.startswith("  "))  # fmt: skip
    assert "y(0)" not in text and "y[" not in text


def test_julia_runs_when_installed(tmp_path):
    julia = shutil.which("julia")
    if julia is None:
        pytest.skip("julia is not installed")
    system = built("double_pendulum")
    path = write_code(system, "julia", tmp_path / "dp.jl")
    script = f'include("{path}"); println(join(rhs(0.0, [1.0, 0.5, 0.2, -0.1]), " "))'
    out = subprocess.run([julia, "-e", script], check=True, capture_output=True, text=True)
    compiled = compile_equations(system.equations_of_motion())
    expected = compiled.rhs(0.0, [1.0, 0.5, 0.2, -0.1], compiled.parameter_vector({}))
    assert close([float(x) for x in out.stdout.split()], expected)


def test_octave_runs_when_installed(tmp_path):
    octave = shutil.which("octave")
    if octave is None:
        pytest.skip("octave is not installed")
    system = built("double_pendulum")
    write_code(system, "matlab", tmp_path / "dp.m")
    script = "m = dp(); printf('%.17g ', m.rhs(0, [1.0; 0.5; 0.2; -0.1]))"
    out = subprocess.run([octave, "--no-gui", "--eval", script], cwd=tmp_path, check=True,
                         capture_output=True, text=True)  # fmt: skip
    compiled = compile_equations(system.equations_of_motion())
    expected = compiled.rhs(0.0, [1.0, 0.5, 0.2, -0.1], compiled.parameter_vector({}))
    assert close([float(x) for x in out.stdout.split()], expected)


# -- the command and its errors ------------------------------------------------------------
def test_cli_writes_each_language(tmp_path, capsys):
    for language, writer in LANGUAGES.items():
        out = tmp_path / f"double_pendulum{writer.suffix}"
        assert main(["export", "double_pendulum", "--to", language, "--out", str(out)]) == 0
        assert out.read_text() == export_code(built("double_pendulum"), language,
                                              name="double_pendulum")  # fmt: skip
    assert main(["export", "simple_pendulum", "--to", "numpy"]) == 0
    assert "def rhs(t, y, params=DEFAULT_PARAMS, u=None):" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (
            ["--to", "c", "--out", "/no/such/folder/x.c"],
            "the folder /no/such/folder does not exist",
        ),
        (["--to", "matlab", "--out", "{tmp}/cart-pole.m"], "needs a name that is an identifier"),
        (["--to", "fortran"], "Invalid value for '--to'"),
    ],
)
def test_cli_errors_are_one_line(arguments, message, tmp_path, capsys):
    arguments = [a.replace("{tmp}", str(tmp_path)) for a in arguments]
    assert main(["export", "double_pendulum", *arguments]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err
    assert list(tmp_path.iterdir()) == []


def test_unspecified_functions_need_definitions(tmp_path, capsys):
    model = tmp_path / "field.toml"
    model.write_text(
        'coordinates = ["x"]\nkinetic = "m*x_dot^2/2"\npotential = "V"\n'
        '[parameters]\nm = 1.0\n[functions]\nV = ["x"]\n'
    )
    assert main(["export", str(model), "--to", "c"]) == 2
    assert "V" in capsys.readouterr().err
    assert main(["export", str(model), "--to", "numpy", "--define", "V=x^4/4"]) == 0
    assert "q_x**3" in capsys.readouterr().out
    with pytest.raises(lg.ModelError, match="unknown language 'rust'"):
        export_code(lg.load("simple_pendulum"), "rust")

"""heyoka (Taylor's method, LLVM) as a peer of our DOP853 and Radau at tight tolerances.

    python benchmarks/simulate.py --taylor [--repeat 3]     (or run this file)

heyoka (``pip install heyoka``; not a dependency of lagrangian) integrates an
explicit ODE given as its own expressions: here our equations of motion, M and f
converted with ``heyoka.from_sympy`` (parameters as numbers), q'' = M^{-1} f by
Gaussian elimination written out in heyoka expressions (M is symmetric positive
definite: no pivoting), so both tools integrate the same equations.

Systems: the double pendulum from (0.3, 0.2) at rest and the 10-link chain from
theta1 = 0.1 (small swings: regular motion, where an error grows about linearly
with time; the README's (2.0, 0.5) start is chaotic and no method keeps any digit
to t = 1000).  For t = 10 and 1000 and tolerances 1e-10 and 1e-15 (rtol = atol =
tol for ours; heyoka's ``tol``), printed are the wall time of the integration
after compilation (median of ``--repeat``), heyoka's JIT time, and the largest
error of the final (q, q') against the reference.  SciPy raises an rtol below
100 eps to 2.2e-14, so our "1e-15" runs at that.

Reference: heyoka in x87 extended precision (``long double``, 64-bit mantissa,
eps 1.1e-19) at tol 1e-18; checked at t = 10 against heyoka in quadruple precision
(``real128``) at tol 1e-28 (the difference is printed; t = 1000 in quadruple
precision takes far too long for the chain).  Nothing is asserted.
"""

from __future__ import annotations

import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rhs import chain_pendulum

import lagrangian as lg
from lagrangian.codegen.heyoka import eliminated
from lagrangian.integrate.registry import method_class
from lagrangian.integrate.scipy_methods import MIN_RTOL
from lagrangian.numeric import compile_equations, default_backend

TOLERANCES = (1e-10, 1e-15)
TIMES = (10.0, 1000.0)


def heyoka_ode(eom):
    """heyoka's [(q_i, v_i), (v_i, q''_i)] of ``eom`` with the model's parameter values."""
    import heyoka as hy

    system, coordinates = eom.system, eom.coordinates
    n = len(coordinates)
    q = [hy.make_vars(f"q{i}") for i in range(n)]
    v = [hy.make_vars(f"v{i}") for i in range(n)]
    values = dict(system.parameter_values)
    replace = {}
    for i, c in enumerate(coordinates):
        replace[c.q], replace[c.q_dot] = q[i], v[i]
    for symbol in eom.mass_matrix.free_symbols | eom.forcing.free_symbols:
        if symbol.name in values:
            replace[symbol] = hy.expression(float(values[symbol.name]))
    matrix = [[hy.from_sympy(eom.mass_matrix[i, j], replace) for j in range(n)] for i in range(n)]
    force = [hy.from_sympy(eom.forcing[i, 0], replace) for i in range(n)]
    accelerations = eliminated(matrix, force)  # the taylor method's own elimination
    return [(q[i], v[i]) for i in range(n)] + [(v[i], accelerations[i]) for i in range(n)]


def heyoka_integrator(ode, y0, tol, fp_type=float):
    """(integrator, JIT seconds)."""
    import heyoka as hy

    start = time.perf_counter()
    if fp_type is float:
        state = np.array(y0, dtype=float)
        integrator = hy.taylor_adaptive(ode, state, tol=tol, compact_mode=len(y0) > 4)
    else:
        state = np.array(y0, dtype=fp_type)
        integrator = hy.taylor_adaptive(
            ode, state, tol=fp_type(tol), fp_type=fp_type, compact_mode=True
        )
    return integrator, time.perf_counter() - start


def reference_case(system, angles, t_end):
    """(equations, y0, heyoka's ODE, the final state at tol 1e-18 in long double) of
    ``system`` started at ``angles`` (the first coordinates; the rest and every rate 0)."""
    eom = system.equations_of_motion()
    y0 = np.zeros(2 * len(eom.coordinates))
    y0[: len(angles)] = angles
    ode = heyoka_ode(eom)
    reference = heyoka_final(ode, y0, t_end, 1e-18, np.longdouble).astype(float)
    return eom, y0, ode, reference


def heyoka_final(ode, y0, t_end, tol, fp_type=float):
    integrator, _ = heyoka_integrator(ode, y0, tol, fp_type)
    integrator.propagate_until(fp_type(t_end))
    return np.array(integrator.state)


def main(repeat: int = 3) -> None:
    try:
        import heyoka as hy
    except ImportError:
        print("\nheyoka: not installed, skipped (pip install heyoka)")
        return
    backend = default_backend()
    warnings.filterwarnings("ignore", message="At least one element of `rtol` is too small")
    print(f"\nheyoka {hy.__version__} against ours (backend {backend}); error: max |final - ref|")
    cases = [
        ("double pendulum", lg.load("double_pendulum"), [0.3, 0.2]),
        ("10-link chain", chain_pendulum(10), [0.1]),
    ]
    print(
        f"{'system':>16} {'t':>6} {'tol':>6} {'method':>10} {'seconds':>9} {'error':>9} "
        f"{'/ heyoka s':>10}"
    )
    for label, system, angles in cases:
        eom = system.equations_of_motion()
        n = len(eom.coordinates)
        y0 = np.zeros(2 * n)
        y0[: len(angles)] = angles
        ode = heyoka_ode(eom)
        compiled = compile_equations(eom, backend=backend)
        params = compiled.parameter_vector()
        compiled.rhs(0.0, y0, params)
        for t_end in TIMES:
            start = time.perf_counter()
            reference = heyoka_final(ode, y0, t_end, 1e-18, np.longdouble).astype(float)
            note = f"reference: long double, tol 1e-18, {time.perf_counter() - start:.1f} s"
            if t_end == TIMES[0]:
                quad = heyoka_final(ode, y0, t_end, 1e-28, hy.real128)
                check = max(abs(float(a) - float(b)) for a, b in zip(quad, reference, strict=True))
                note += f"; against real128 (tol 1e-28): {check:.1e}"
            print(f"{label:>16} {t_end:>6g}  {note}")
            for tol in TOLERANCES:
                rows = _ours(compiled, y0, params, t_end, tol, repeat)
                integrator, jit = heyoka_integrator(ode, y0, tol)
                seconds = []
                for _ in range(repeat):
                    integrator, _ = heyoka_integrator(ode, y0, tol)
                    started = time.perf_counter()
                    integrator.propagate_until(t_end)
                    seconds.append(time.perf_counter() - started)
                heyoka_seconds = statistics.median(seconds)
                rows.append(("heyoka", heyoka_seconds, np.array(integrator.state)))
                for method, elapsed, final in rows:
                    error = float(np.max(np.abs(final - reference)))
                    print(
                        f"{label:>16} {t_end:>6g} {tol:>6.0e} {method:>10} {elapsed:>9.2e} "
                        f"{error:>9.1e} {elapsed / heyoka_seconds:>10.1f}",
                        flush=True,
                    )
                print(f"{'':>16} {'':>6} {'':>6} {'heyoka JIT':>10} {jit:>9.2f}")


def _ours(compiled, y0, params, t_end, tol, repeat):
    """[(method, median seconds, final state)] of dop853 and radau at rtol = atol = tol."""
    rows = []
    for method in ("dop853", "radau"):
        if method == "radau" and t_end > 100:
            continue  # minutes per run (double pendulum, 1e-10: 247 s); t = 10 shows the trend
        rtol = max(tol, MIN_RTOL)  # what SciPy would use anyway; lagrangian refuses less
        integrator = method_class(method).configure(t_span=(0.0, t_end), rtol=rtol, atol=tol)
        seconds, final = [], None
        for _ in range(repeat if t_end < 100 else 1):
            started = time.perf_counter()
            result = integrator.solve(compiled, (0.0, t_end), y0, params)
            seconds.append(time.perf_counter() - started)
            final = result.y[:, -1]
        rows.append((method, statistics.median(seconds), final))
    return rows


if __name__ == "__main__":
    main()

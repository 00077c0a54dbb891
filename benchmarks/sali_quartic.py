"""Issue 35 item 5: the ``sali`` rule on a system that is not a model of the project, two
quartic oscillators coupled, V = (x^4 + y^4)/4 + b x^2 y^2 (b = 3: neither separable nor
one of the integrable couplings b = 0, 1/2, 3/2), at E = 1/4.

A 12 x 12 grid of (y, p_y) on x = 0 (x' > 0 from the energy; 112 starts), numba, dt 0.02:
the ``lyapunov`` maps at t = 4000 and 10000 (chaotic above 0.01) against ``sali`` by
``--sali-t`` (chaotic once SALI falls below 1e-4); the lowest SALI at t_end of the starts
both exponent maps call regular (below 0.005), the latest crossing of the chaotic ones.

    python benchmarks/sali_quartic.py [--sali-t 1000] [--coupling 3]
"""

from __future__ import annotations

import argparse

import numpy as np

from lagrangian.derive import derive
from lagrangian.ensemble import run_ensemble
from lagrangian.facade import loads
from lagrangian.numeric import compile_equations

MODEL = """
name = "Coupled quartic oscillators"
coordinates = ["x", "y"]
kinetic = "(x_dot^2 + y_dot^2)/2"
potential = "(x^4 + y^4)/4 + b*x^2*y^2"

[parameters]
b = 3.0
"""
ENERGY = 0.25


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--sali-t", type=float, default=1000.0)
    parser.add_argument("--coupling", type=float, default=3.0)
    args = parser.parse_args()
    compiled = compile_equations(derive(loads(MODEL)))
    y, py = np.meshgrid(np.linspace(-0.99, 0.99, 12), np.linspace(-0.69, 0.69, 12))
    kinetic = 2 * (ENERGY - y**4 / 4) - py**2
    inside = kinetic > 1e-6
    initial = {"x": 0 * y[inside], "y": y[inside], "x_dot": np.sqrt(kinetic[inside])}
    initial["y_dot"] = py[inside]
    settings = {
        "initial": initial, "params": {"b": np.full(inside.sum(), args.coupling)},
        "dt": 0.02, "backend": "numba",
    }  # fmt: skip
    exponents = {
        t: run_ensemble(compiled, t_end=t, observables="lyapunov", **settings).dataset["lyapunov"]
        for t in (4000.0, 10000.0)
    }
    indicator = run_ensemble(compiled, t_end=args.sali_t, observables="sali", **settings).dataset
    called = indicator["sali_chaotic"].values
    print(f"{called.size} starts, b = {args.coupling:g}, E = {ENERGY:g}")
    for t, values in exponents.items():
        chaotic = values.values > 0.01
        print(f"exponent at t = {t:g} above 0.01: {np.mean(chaotic):.1%}; sali by "
              f"t = {args.sali_t:g} agrees on {np.mean(called == chaotic):.1%}")  # fmt: skip
    regular = np.all([values.values < 0.005 for values in exponents.values()], axis=0)
    chaotic = np.all([values.values > 0.02 for values in exponents.values()], axis=0)
    lowest = indicator["sali"].values[regular].min()
    print(f"{regular.sum()} regular by both: lowest SALI at t_end {lowest:.3g}, "
          f"{called[regular].sum()} crossed")  # fmt: skip
    print(f"{chaotic.sum()} chaotic by both (> 0.02): {called[chaotic].mean():.1%} crossed, the "
          f"last at t = {np.nanmax(indicator['sali_time'].values[chaotic]):g}")  # fmt: skip


if __name__ == "__main__":
    main()

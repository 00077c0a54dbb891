"""Issue 35 item 5: which SALI rule classifies Hénon–Heiles starts as the Lyapunov map does.

The starts of benchmarks/indicators.py (--size 16: 164 starts on x = 0 at E = 1/8) are
stepped once to ``--t-end`` (10000) with three deviation vectors (rk4, dt 0.05, the numpy
backend's TangentFlows, renormalised every step), keeping SALI, GALI_3 and the running
Lyapunov estimate (the stretch of w_1, the ``lyapunov`` observable's displacement) every
time unit.  From that one run it prints how often each rule agrees with the Lyapunov map
(exponent above 0.01 at t = 4000, and at t = 10000):

- SALI at t below a threshold (the rule of the SALI literature, thresholds 1e-2 .. 1e-12);
- SALI below a threshold at some time up to t, the first crossing (a member can stop
  there), with its cost: the mean time the members run, as a share of the Lyapunov map's
  4000 (per time unit a SALI step costs ``--step-ratio`` Lyapunov steps);
- the lowest SALI of the starts both Lyapunov maps call regular (exponent < 0.005).

    python benchmarks/sali_thresholds.py [--size 16] [--t-end 10000] [--step-ratio 1.0]
"""

from __future__ import annotations

import argparse

import numpy as np
from indicators import starts

from lagrangian.budget import cpu_seconds
from lagrangian.derive import derive
from lagrangian.facade import load
from lagrangian.integrate import method_class
from lagrangian.integrate.base import Work
from lagrangian.integrate.indicators import TangentFlows, gali, sali
from lagrangian.numeric import compile_equations

DT = 0.05
EVERY = 20  # steps between samples: one time unit
THRESHOLDS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-8, 1e-10, 1e-12)


def series(size: int, t_end: float):
    """(SALI, GALI_3, running exponent), each (time units, members), and the CPU seconds."""
    compiled = compile_equations(derive(load("henon_heiles")))
    initial = starts(size)
    names = compiled.coordinate_names
    y = np.array([initial[q] for q in names] + [initial[f"{q}_dot"] for q in names])
    integrator = method_class("rk4").configure(t_span=(0.0, t_end), dt=DT)
    tangent, p, work = TangentFlows(compiled, 3), compiled.parameter_vector(), Work()
    z, stretch = tangent.start(y), np.zeros(y.shape[1])
    state = integrator.init(compiled, 0.0, y, p, work)
    kept: tuple[list, list, list] = ([], [], [])
    cpu = cpu_seconds()
    for k in range(1, round(t_end / DT) + 1):
        z, state = integrator.step(tangent, (k - 1) * DT, DT, z, state, p, work)
        z, logarithm = tangent.renormalised(z)
        stretch += logarithm
        if k % EVERY == 0:
            vectors = tangent.vectors(z)
            kept[0].append(sali(vectors))
            kept[1].append(gali(vectors, 3))
            kept[2].append(stretch / (k * DT))
    return (*(np.array(values) for values in kept), cpu_seconds() - cpu)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--size", type=int, default=16)
    parser.add_argument("--t-end", type=float, default=10000.0)
    parser.add_argument("--step-ratio", type=float, default=1.0)
    args = parser.parse_args()
    values, galis, exponents, cpu = series(args.size, args.t_end)
    at = lambda t: round(t) - 1  # noqa: E731  (the sample at time t)
    references = {t: exponents[at(t)] > 0.01 for t in (4000, args.t_end) if t <= args.t_end}
    print(f"{values.shape[1]} starts, stepped to t = {args.t_end:g} in {cpu:.0f} s CPU")
    for t, chaotic in references.items():
        print(f"exponent at t = {t:g} above 0.01: {np.mean(chaotic):.1%} of the starts")
    reference = references[4000]
    print("\nSALI(t) below the threshold, agreement with the map at t = 4000:")
    print("t     " + "".join(f"{threshold:>8.0e}" for threshold in THRESHOLDS))
    for t in (500, 700, 900, 1000, 1200):
        row = [np.mean((values[at(t)] < threshold) == reference) for threshold in THRESHOLDS]
        print(f"{t:<6}" + "".join(f"{share:>8.1%}" for share in row))
    print("\nSALI below the threshold by t (first crossing; the member stops there):")
    for threshold in (1e-4, 1e-5, 1e-6, 1e-8):
        for t in (700, 750, 800, 900, 1000, 1200, 1500):
            below = values[: at(t) + 1] < threshold
            crossed = below.any(axis=0)
            stops = np.where(crossed, np.argmax(below, axis=0) + 1, t)
            cost = stops.mean() * args.step_ratio / 4000
            shares = ", ".join(f"t = {r:g}: {np.mean(crossed == c):.1%}"
                               for r, c in references.items())  # fmt: skip
            print(f"{threshold:.0e} by t = {t}: cost {cost:.3f}; agreement {shares}")
    regular = np.all([exponents[at(t)] < 0.005 for t in references], axis=0)
    print(f"\nthe {regular.sum()} starts every map calls regular (exponent < 0.005), lowest SALI:")
    for t in (900, 1500, 4000):
        print(f"by t = {t}: {np.sort(values[: at(t) + 1, regular].min(axis=0))[:3]}")
    print("\nGALI_3(t) below the threshold, agreement with the map at t = 4000:")
    for t in (500, 700, 900):
        row = [np.mean((galis[at(t)] < threshold) == reference) for threshold in THRESHOLDS]
        print(f"{t:<6}" + "".join(f"{share:>8.1%}" for share in row))


if __name__ == "__main__":
    main()

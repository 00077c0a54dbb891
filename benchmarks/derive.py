"""CPU seconds to derive the n-link pendulum: lagrangian against sympy.physics.mechanics.

    python benchmarks/derive.py [--repeat 3] [--large] [--all]

The chain of point masses on massless links (angles from the downward vertical)
is built from particles and derived by each tool in the same run:

- ours: ``System.from_particles`` (T assembled) and ``equations_of_motion`` (M, f);
- ``LagrangesMethod``: ``Lagrangian`` of the particles and ``form_lagranges_equations``;
- ``KanesMethod``: ``kanes_equations`` with u_i = theta_i'.

Printed per n: the median seconds over ``--repeat`` runs (one run for the
mechanics methods), the ratios mechanics / ours, and the operation count of
M and f after common-subexpression elimination (SymEngine's ``cse``).  n = 5,
10, 20; ``--large`` adds 50 and 100.  LagrangesMethod takes minutes above
n = 10, so it runs there only with ``--all``; otherwise the reference figures
measured on a 2-core machine are printed in its place (KanesMethod runs up to
n = 20 unless --all).  Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import sympy
from sympy.core.cache import clear_cache

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rhs import chain_pendulum

from lagrangian.algebra import to_symengine

#: Seconds measured earlier on a 2-core machine (n = 20), printed when not rerun.
REFERENCE = {20: {"LagrangesMethod": 146.6, "KanesMethod": 6.3}}


def ours(n: int) -> tuple[float, float, object]:
    clear_cache()  # SymPy's cache would make a repeated run look faster than a first one
    start = time.process_time()
    system = chain_pendulum(n)
    built = time.process_time()
    eom = system.equations_of_motion()
    return built - start, time.process_time() - built, eom


def _mechanics_chain(n: int, generalized_speeds: bool):
    from sympy.physics import mechanics as me

    q = me.dynamicsymbols(f"q1:{n + 1}")
    u = me.dynamicsymbols(f"u1:{n + 1}")
    m = sympy.symbols(f"m1:{n + 1}", positive=True)
    l = sympy.symbols(f"l1:{n + 1}", positive=True)
    g = sympy.Symbol("g", positive=True)
    frame = me.ReferenceFrame("N")
    origin = me.Point("O")
    origin.set_vel(frame, 0)
    previous, particles, forces = origin, [], []
    for i in range(n):
        link = frame.orientnew(f"A{i}", "Axis", [q[i], frame.z])
        link.set_ang_vel(frame, (u[i] if generalized_speeds else q[i].diff()) * frame.z)
        point = previous.locatenew(f"P{i}", -l[i] * link.y)
        point.v2pt_theory(previous, frame, link)
        particle = me.Particle(f"B{i}", point, m[i])
        particle.potential_energy = m[i] * g * point.pos_from(origin).dot(frame.y)
        particles.append(particle)
        forces.append((point, -m[i] * g * frame.y))
        previous = point
    return me, frame, q, u, particles, forces


def lagranges_method(n: int) -> float:
    start = time.process_time()
    me, frame, q, _, particles, _ = _mechanics_chain(n, generalized_speeds=False)
    method = me.LagrangesMethod(me.Lagrangian(frame, *particles), q)
    method.form_lagranges_equations()
    return time.process_time() - start


def kanes_method(n: int) -> float:
    start = time.process_time()
    me, frame, q, u, particles, forces = _mechanics_chain(n, generalized_speeds=True)
    kinematics = [qi.diff() - ui for qi, ui in zip(q, u, strict=True)]
    method = me.KanesMethod(frame, q_ind=q, u_ind=u, kd_eqs=kinematics)
    method.kanes_equations(particles, forces)
    return time.process_time() - start


def cse_operations(eom) -> int:
    """Operations of M and f after SymEngine's common-subexpression elimination."""
    import symengine as se

    cache: dict = {}
    exprs = [to_symengine(e, cache) for e in [*eom.mass_matrix, *eom.forcing]]
    replacements, reduced = se.cse(exprs)
    return sum(_operations(e) for _, e in replacements) + sum(_operations(e) for e in reduced)


def _operations(expr) -> int:
    args = expr.args
    if not args:
        return 0
    own = len(args) - 1 if len(args) > 1 else 1
    return own + sum(_operations(a) for a in args)


def _ratios(theirs: float, total: float, derive: float) -> str:
    return f"{theirs / total:>5.0f}|{theirs / derive:<4.0f}"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--large", action="store_true", help="also n = 50 and 100")
    parser.add_argument("--all", action="store_true", help="LagrangesMethod above n = 10 too")
    args = parser.parse_args(argv)
    sizes = [5, 10, 20] + ([50, 100] if args.large else [])
    ours(3)  # imports and caches warm
    print(
        f"{'n':>4} {'build s':>9} {'derive s':>9} {'ours s':>9} {'Lagrange s':>11} "
        f"{'ratio':>10} {'Kane s':>9} {'ratio':>10} {'CSE ops':>9}"
    )
    for n in sizes:
        runs = [ours(n) for _ in range(args.repeat)]
        build = statistics.median(r[0] for r in runs)
        derive = statistics.median(r[1] for r in runs)
        total = statistics.median(r[0] + r[1] for r in runs)
        reference = REFERENCE.get(n, {})
        lagrange_note = kane_note = ""
        if n <= 10 or args.all:
            lagrange = lagranges_method(n)
        elif "LagrangesMethod" in reference:
            lagrange, lagrange_note = reference["LagrangesMethod"], "*"
        else:
            lagrange = float("nan")
        if n <= 20 or args.all:
            kane = kanes_method(n)
        elif "KanesMethod" in reference:
            kane, kane_note = reference["KanesMethod"], "*"
        else:
            kane = float("nan")
        print(
            f"{n:>4} {build:>9.3f} {derive:>9.3f} {total:>9.3f} "
            f"{lagrange:>10.2f}{lagrange_note or ' '} {_ratios(lagrange, total, derive)} "
            f"{kane:>8.2f}{kane_note or ' '} {_ratios(kane, total, derive)} "
            f"{cse_operations(runs[0][2]):>9}"
        )
    print("ratio: mechanics seconds / ours (build + derive) | / ours (derive only)")
    print("* reference figure measured earlier on a 2-core machine, not rerun (use --all)")


if __name__ == "__main__":
    main()

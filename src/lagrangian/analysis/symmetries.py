"""Continuous point symmetries found automatically, and their Noether charges.

Noether: if L(q, q', t) is invariant under q -> q + eps xi(q, t) to first order,

    dL = sum_i dL/dq_i xi_i + dL/dq_i' xi_i' = 0     (xi' = d xi / dt),

and the forces do no work along xi (sum_i (Q_i - dF/dq_i') xi_i = 0, and every
constraint force A^T lambda is orthogonal to it: A xi = 0), then
sum_i p_i xi_i is conserved.  Searched here: the affine fields

    xi = B q + c,   c constant, B constant,

with B only among coordinates that enter L algebraically (Cartesian-like: no
angle inside a sine).  dL is linear in the unknowns (c, B): writing each
coefficient function e_u in expanded form and collecting the terms by their
dependence on the state gives one linear equation per distinct term, solved
exactly (the answer may depend on the parameters).  This finds translations
(of the whole molecule: c = (1, 1, 1)), rotations of particles given in
Cartesian coordinates (B antisymmetric in the mass metric) and any linear
combination of coordinates along which L is invariant.  Terms that cancel only
through an identity (sin^2 + cos^2 = 1) are not seen: the search may miss a
symmetry, never invent one, and every charge is also checked numerically
along the motion.

Galilean boosts: for a shift c with M c constant and no velocity-independent
momentum along c (dL/dq' . c = c^T M q'), L changes under q -> q + eps t c by
the total derivative eps d/dt (c^T M q), so G = t p.c - c^T M q is conserved:
for particles, the centre of mass moving uniformly (m X - P t, up to sign)
[Goldstein, Classical Mechanics, 13.7; Arnold, Mathematical Methods, 20].
"""

from __future__ import annotations

import random
import weakref
from dataclasses import dataclass

import numpy as np
import sympy

from ..algebra import is_zero, tidy
from ..derive import EquationsOfMotion
from ..model import System
from ..sizes import ops_exceed
from .motion import vanishes_along_motion

#: Largest number of coordinates mixed by a linear part B (k^2 unknowns).
LINEAR_MAX_COORDINATES = 9
#: Largest coefficient function (operation count) expanded for the search.
EXPAND_MAX_OPS = 3_000
_AXES = "xyz"


@dataclass(frozen=True)
class Symmetry:
    """A point symmetry xi(q, t) with its charge; ``broken`` says why it is not conserved."""

    name: str
    generator: tuple[sympy.Expr, ...]
    charge: sympy.Expr
    reason: str
    broken: str = ""


def point_symmetries(
    eom: EquationsOfMotion, cyclic: tuple[str, ...] = (), reported: tuple[str, ...] = ()
) -> tuple[Symmetry, ...]:
    """The affine point symmetries of L and the boosts (see the module docstring).

    Shifts of one coordinate in ``cyclic`` (conserved momenta) or ``reported``
    (momenta already listed, conserved or not) are left out; a generator that a
    force, dissipation or a constraint breaks has ``broken``.  Boosts are formed
    from the shifts that are conserved (a boost cannot be when its shift is not),
    for translations of all particles or of several coordinates together (a
    single angle turning uniformly is no centre of mass).
    """
    system = eom.system
    found = _affine_generators(system)
    if found is None:
        return ()
    n = len(system.coordinates)
    index = {c.name: i for i, c in enumerate(system.coordinates)}
    shifts, others = [], []
    for xi in found:
        (shifts if all(not x.free_symbols & _q(system) for x in xi) else others).append(xi)
    left_out = [index[name] for name in {*cyclic, *reported}]
    translations = [_symmetry(eom, xi) for xi in _without_cyclic(shifts, left_out, n)]
    results = translations + [_symmetry(eom, xi) for xi in others]
    unbroken = [s.generator for s in translations if not s.broken]
    cyclic_shifts = [
        tuple(sympy.Integer(int(i == index[name])) for i in range(n)) for name in cyclic
    ]
    for c in _independent([*cyclic_shifts, *unbroken]):
        boost = _boost(eom, c)
        if boost is not None:
            results.append(boost)
    return tuple(s for s in results if s.broken or vanishes_along_motion(s.charge, eom))


def generators(eom: EquationsOfMotion) -> tuple[tuple[str, tuple[sympy.Expr, ...]], ...]:
    """Every affine point symmetry of L (cyclic shifts included): (what it is, xi).

    Forces are not consulted: this names directions (a zero mode along which L is
    invariant), it claims nothing conserved.  Computed once per equations.
    """
    if eom not in _GENERATORS:
        found = _affine_generators(eom.system) or []
        _GENERATORS[eom] = tuple((_describe(eom.system, xi)[1], xi) for xi in found)
    return _GENERATORS[eom]


_GENERATORS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _q(system: System) -> set:
    return {c.q for c in system.coordinates}


def _state(system: System) -> tuple[sympy.Symbol, ...]:
    return (system.time, *(x for c in system.coordinates for x in (c.q, c.q_dot)))


def _algebraic(system: System) -> list[int]:
    """Coordinates that appear in L, and only algebraically (never inside a function call)."""
    inside = set()
    for call in system.lagrangian.atoms(sympy.Function):
        inside |= call.free_symbols
    present = system.lagrangian.free_symbols
    return [i for i, c in enumerate(system.coordinates) if c.q in present and c.q not in inside]


def _affine_generators(system: System) -> list[tuple[sympy.Expr, ...]] | None:
    """A basis of the xi = B q + c with dL = 0 identically; None when L is too large."""
    coordinates = system.coordinates
    n = len(coordinates)
    lagrangian = system.lagrangian
    d_q = [sympy.diff(lagrangian, c.q) for c in coordinates]
    d_v = [sympy.diff(lagrangian, c.q_dot) for c in coordinates]
    mixed = _algebraic(system)
    if len(mixed) > LINEAR_MAX_COORDINATES:
        mixed = []
    unknowns, fields, functions = [], [], []
    for i in range(n):
        u = sympy.Dummy(f"c{i}")
        unknowns.append(u)
        fields.append((i, None))
        functions.append(d_q[i])
    for i in mixed:
        for j in mixed:
            u = sympy.Dummy(f"b{i}_{j}")
            unknowns.append(u)
            fields.append((i, j))
            functions.append(d_q[i] * coordinates[j].q + d_v[i] * coordinates[j].q_dot)
    state = _state(system)
    rows: dict[sympy.Expr, sympy.Expr] = {}
    for u, function in zip(unknowns, functions, strict=True):
        if function == 0:
            continue
        if ops_exceed(function, EXPAND_MAX_OPS):
            return None
        for term in sympy.Add.make_args(sympy.expand(function)):
            coefficient, dependence = term.as_independent(*state, as_Add=False)
            rows[dependence] = rows.get(dependence, sympy.Integer(0)) + coefficient * u
    solutions = sympy.linsolve(list(rows.values()), unknowns) if rows else None
    if solutions is None:
        general = list(unknowns)
    elif not solutions:
        return []
    else:
        general = list(next(iter(solutions)))
    free = sorted(
        set().union(*(g.free_symbols for g in general)) & set(unknowns), key=unknowns.index
    )
    basis = []
    for parameter in free:
        values = [g.xreplace({p: int(p == parameter) for p in free}) for g in general]
        xi = [sympy.Integer(0)] * n
        for value, (i, j) in zip(values, fields, strict=True):
            xi[i] += value * (1 if j is None else coordinates[j].q)
        basis.append(tuple(sympy.expand(x) for x in xi))
    return basis


def _without_cyclic(shifts: list[tuple], cyclic: list[int], n: int) -> list[tuple]:
    """The shifts with the cyclic coordinates' components removed, independent, non-zero."""
    cleaned = [
        tuple(sympy.Integer(0) if i in cyclic else x for i, x in enumerate(c)) for c in shifts
    ]
    return _independent([c for c in cleaned if any(x != 0 for x in c)])


def _independent(vectors: list[tuple]) -> list[tuple]:
    kept: list[tuple] = []
    for v in vectors:
        if sympy.Matrix([*kept, v]).rank(simplify=True) > len(kept):
            kept.append(v)
    return kept


def _momenta(eom: EquationsOfMotion) -> list[sympy.Expr]:
    return [step.momentum for step in eom.steps]


def _symmetry(eom: EquationsOfMotion, xi: tuple[sympy.Expr, ...]) -> Symmetry:
    system = eom.system
    name, what, scale = _describe(system, xi)
    xi = tuple(sympy.nsimplify(scale) * x for x in xi)
    charge = tidy(
        sum((p * x for p, x in zip(_momenta(eom), xi, strict=True)), sympy.Integer(0)),
        system.state_symbols,
    )
    return Symmetry(name, xi, charge, f"L is invariant under {what}", _broken(eom, xi, what))


def _boost(eom: EquationsOfMotion, c: tuple[sympy.Expr, ...]) -> Symmetry | None:
    """G = t p.c - c^T M q when M c is constant and p.c = c^T M q' (module docstring)."""
    system = eom.system
    name, what, scale = _describe(system, c)
    if "all particles" not in what and sum(1 for x in c if x != 0) < 2:
        return None  # one coordinate turning uniformly: no centre of mass to speak of
    c = tuple(sympy.nsimplify(scale) * x for x in c)
    vector = sympy.Matrix(c)
    weighted = eom.mass_matrix * vector
    if any(
        w.has(system.time, *_q(system), *(x.q_dot for x in system.coordinates)) for w in weighted
    ):
        return None
    at_rest = {x.q_dot: 0 for x in system.coordinates}
    if not is_zero(
        sum(
            (p.xreplace(at_rest) * x for p, x in zip(_momenta(eom), c, strict=True)),
            sympy.Integer(0),
        )
    ):
        return None
    q = sympy.Matrix([x.q for x in system.coordinates])
    momentum = sum((p * x for p, x in zip(_momenta(eom), c, strict=True)), sympy.Integer(0))
    charge = tidy(system.time * momentum - (weighted.T * q)[0], system.state_symbols)
    name = "G" + name[1:] if name.startswith("P") else "G_" + name
    reason = (
        f"Galilean boost (the {what} growing as t): L changes only by a total derivative,"
        " so the centre of mass moves uniformly"
    )
    generator = tuple(system.time * x for x in c)
    return Symmetry(name, generator, charge, reason, _broken(eom, c, "the boost"))


def _broken(eom: EquationsOfMotion, xi: tuple[sympy.Expr, ...], what: str) -> str:
    """Why a symmetry of L is not conserved: forces, dissipation or constraints act along it."""
    system = eom.system
    reasons = []
    work = sum(
        (
            system.forces.get(c.name, sympy.Integer(0)) * x
            for c, x in zip(system.coordinates, xi, strict=True)
        ),
        sympy.Integer(0),
    )
    if not is_zero(work):
        acting = [
            f"Q_{c.name}"
            for c, x in zip(system.coordinates, xi, strict=True)
            if x != 0 and system.forces.get(c.name, 0) != 0
        ]
        reasons.append(", ".join(acting) + " act(s) along it")
    dissipated = sum(
        (
            sympy.diff(system.dissipation, c.q_dot) * x
            for c, x in zip(system.coordinates, xi, strict=True)
        ),
        sympy.Integer(0),
    )
    if not is_zero(dissipated):
        reasons.append("dissipation acts along it")
    if eom.constraints is not None:
        along = eom.constraints.matrix * sympy.Matrix(xi)
        if not all(is_zero(a) for a in along):
            reasons.append("a constraint force acts along it")
    return f"L is invariant under {what}, but " + "; ".join(reasons) if reasons else ""


def _describe(system: System, xi: tuple[sympy.Expr, ...]) -> tuple[str, str, float]:
    """(charge name, 'translation of ...' / 'rotation ...', the factor that makes xi a unit
    translation or rotation) of a generator."""
    rigid = _particle_motion(system, xi)
    if rigid is not None:
        return rigid
    moved = [c.name for c, x in zip(system.coordinates, xi, strict=True) if x != 0]
    if all(not x.free_symbols & _q(system) for x in xi):
        nonzero = [x for x in xi if x != 0]
        if all(is_zero(x - nonzero[0]) for x in nonzero):
            # "translation" for coordinates that enter L algebraically (positions); an angle,
            # or a coordinate L does not contain, is only shifted
            positions = [i for i in _algebraic(system) if xi[i] != 0]
            kind = "translation" if len(positions) == len(moved) else "shift"
            what = f"{kind} of " + ", ".join(moved) + (" together" if len(moved) > 1 else "")
            return "P_" + "+".join(moved), what, 1
        combination = sum(
            (x * c.q for c, x in zip(system.coordinates, xi, strict=True)), sympy.Integer(0)
        )
        what = f"the shift dq = eps ({', '.join(map(str, xi))})"
        return f"P_({combination})".replace(" ", ""), what, 1
    field = ", ".join(
        f"d{c.name} = {x}" for c, x in zip(system.coordinates, xi, strict=True) if x != 0
    )
    if _antisymmetric(system, xi):
        plane = ", ".join(moved)
        return "J_" + "_".join(moved), f"rotation in the ({plane}) plane: {field} (times eps)", 1
    return "J_" + "_".join(moved), f"the linear transformation {field} (times eps)", 1


def _antisymmetric(system: System, xi: tuple[sympy.Expr, ...]) -> bool:
    """xi = B q with B = -B^T: a rotation of the coordinates (as in the Cartesian plane)."""
    q = [c.q for c in system.coordinates]
    matrix = sympy.Matrix(xi).jacobian(q)
    linear = (matrix * sympy.Matrix(q) - sympy.Matrix(xi)).applyfunc(sympy.expand)
    return linear.is_zero_matrix is True and (matrix + matrix.T).is_zero_matrix is True


def _particle_motion(system: System, xi: tuple[sympy.Expr, ...]) -> tuple[str, str, float] | None:
    """('P_x', 'translation of all particles along x') or ('L_z', 'rotation ... about z')."""
    if not system.particles or system.bodies:
        return None
    q = [c.q for c in system.coordinates]
    rng = random.Random(13)
    samples = []
    for _ in range(3):
        table = {c.q: rng.uniform(-1.5, 1.5) for c in system.coordinates}
        table |= {
            p.symbol: rng.uniform(0.5, 2.0) * (-1 if p.sign == "negative" else 1)
            for p in system.parameters
        }
        table[system.time] = rng.uniform(0.1, 2.0)
        try:
            positions = [
                np.array(sympy.Matrix(p.position).xreplace(table).evalf(), dtype=float).ravel()
                for p in system.particles
            ]
            moves = [
                np.array(
                    (sympy.Matrix(p.position).jacobian(q) * sympy.Matrix(xi))
                    .xreplace(table)
                    .evalf(),
                    dtype=float,
                ).ravel()
                for p in system.particles
            ]
        except (TypeError, ValueError):
            return None
        samples.append((positions, moves))
    dimension = len(samples[0][0][0])
    translations = {tuple(np.round(m, 9)) for _, moves in samples for m in moves}
    if len(translations) == 1:
        d = np.array(next(iter(translations)))
        return _named("P", "translation of all particles along", d)
    # one w for every sample together: a single particle fixes w only across several points
    blocks, targets = [], []
    for positions, moves in samples:
        for r, dr in zip(positions, moves, strict=True):
            if dimension == 2:
                blocks.append(np.array([[-r[1]], [r[0]]]))
            else:
                blocks.append(np.array([[0, r[2], -r[1]], [-r[2], 0, r[0]], [r[1], -r[0], 0]]))
            targets.append(dr)
    a, b = np.vstack(blocks), np.concatenate(targets)
    w, *_ = np.linalg.lstsq(a, b, rcond=None)
    if np.abs(a @ w - b).max() > 1e-9 * max(1.0, np.abs(b).max()):
        return None
    rotations = [w]
    if dimension == 2:
        return (
            "L_z",
            "rotation of all particles about the origin (in their plane)",
            1 / rotations[0][0],
        )
    return _named("L", "rotation of all particles about", rotations[0])


def _named(letter: str, what: str, d: np.ndarray) -> tuple[str, str, float]:
    nonzero = [i for i, x in enumerate(d) if abs(x) > 1e-12]
    if len(nonzero) == 1:
        axis = _AXES[nonzero[0]]
        return f"{letter}_{axis}", f"{what} {axis}", 1 / d[nonzero[0]]
    direction = "(" + ", ".join(f"{x / np.abs(d).max():.3g}" for x in d) + ")"
    return f"{letter}_{direction}".replace(" ", ""), f"{what} {direction}", 1

"""Floquet multipliers of a periodic orbit and what they say: stability and the kind.

The multipliers are the eigenvalues of the monodromy matrix M = dG^d/dx (G the
stroboscopic map, d the orbit's least period): a small displacement from the orbit is
multiplied by them, direction by direction, once around it.  By Liouville's formula
det M = exp(∫ tr J dt) over the orbit (tr J the divergence of the flow): 1 for a
Hamiltonian flow, whose multipliers come in pairs mu, 1/mu; exp(-b d P / (m l^2)) for the
driven damped pendulum.

The kind (the usual names of the fixed points of maps; e.g. Nusse & Yorke, Dynamics:
Numerical Explorations, 2nd ed. 1998, ch. 2):

- ``node``: real multipliers all inside the unit circle (an attracting orbit) or all
  outside (a repelling one);
- ``saddle``: real multipliers, some inside and some outside;
- ``flip node`` / ``flip saddle``: as above with a negative multiplier (nearby motions
  change side every time around; one passing through -1 is a period doubling);
- ``focus``: a complex pair (nearby motions turn about the orbit), all inside or all
  outside; ``saddle-focus`` with others on the other side of the circle;
- ``elliptic``: every multiplier on the unit circle, a complex pair among them (a
  Hamiltonian orbit surrounded by invariant curves).

Stable: every |mu| <= 1 (within :data:`UNIT`): the elliptic orbits of a Hamiltonian map
are stable in this, linear, sense.  An orbit of an autonomous flow has ``trivial``
multipliers 1 (along the flow; across the energy shell of a conserved energy): the ones
closest to 1 are set aside before judging (a double 1 is a Jordan block, computed only to
about the square root of the integration's accuracy, 1e-6 here).
"""

from __future__ import annotations

import numpy as np

#: |mu| within this of 1 is on the unit circle.
UNIT = 1e-6
#: A multiplier whose imaginary part is at most this (relative to its modulus) is real.
REAL = 1e-9


def multipliers(monodromy: np.ndarray) -> np.ndarray:
    """The eigenvalues of ``monodromy``, largest modulus first (complex)."""
    values = np.linalg.eigvals(np.asarray(monodromy, dtype=float)).astype(complex)
    return values[np.argsort(-np.abs(values), kind="stable")]


def nontrivial(values: np.ndarray, trivial: int = 0) -> np.ndarray:
    """``values`` without the ``trivial`` ones closest to 1."""
    values = np.asarray(values, dtype=complex)
    if trivial <= 0:
        return values
    keep = np.argsort(np.abs(values - 1.0), kind="stable")[trivial:]
    return values[np.sort(keep)]


def is_stable(values: np.ndarray, trivial: int = 0) -> bool:
    """Whether every multiplier lies inside the unit circle or on it (within UNIT)."""
    return bool(np.all(np.abs(nontrivial(values, trivial)) <= 1.0 + UNIT))


def kind(values: np.ndarray, trivial: int = 0) -> str:
    """The orbit's kind from its multipliers (see the module docstring)."""
    values = nontrivial(values, trivial)
    if values.size == 0:
        return "neutral"
    moduli = np.abs(values)
    inside = bool(np.any(moduli < 1.0 - UNIT))
    outside = bool(np.any(moduli > 1.0 + UNIT))
    complex_pair = bool(np.any(np.abs(values.imag) > REAL * np.maximum(1.0, moduli)))
    if complex_pair:
        if not (inside or outside):
            return "elliptic"
        return "saddle-focus" if inside and outside else "focus"
    base = "saddle" if inside and outside else "node"
    flips = bool(np.any(values.real < 0.0))
    return f"flip {base}" if flips else base


def as_json(values: np.ndarray) -> list[object]:
    """Multipliers for JSON: a real one as a number, a complex one as [re, im]."""
    out: list[object] = []
    for value in np.asarray(values, dtype=complex):
        if abs(value.imag) > REAL * max(1.0, abs(value)):
            out.append([float(value.real), float(value.imag)])
        else:
            out.append(float(value.real))
    return out

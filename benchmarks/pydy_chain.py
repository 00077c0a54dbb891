"""The N-link planar pendulum as PyDy builds it: KanesMethod + Cython code generation.

    from pydy_chain import chain_by_pydy
    rhs, seconds = chain_by_pydy(10)      # None, 0.0 when PyDy (or Cython) is missing

The peer of the rhs and simulate benchmarks.  Point masses m_i on massless
rods l_i, absolute angles theta_i from the downward vertical, gravity g: the
same system as ``rhs.chain_pendulum(n)``.  ``rhs(t, y, params)`` takes the
state [theta..., omega...] and params [m..., l..., g] (the layout of
``rhs.chain_by_hand``), and ``seconds`` is the time PyDy took to derive and
generate + compile the Cython code.
"""

from __future__ import annotations

import time


def chain_by_pydy(n: int, generator: str = "cython"):
    """(rhs, derive + codegen seconds), or (None, 0.0) without PyDy."""
    try:
        from pydy.codegen.ode_function_generators import generate_ode_function
        from sympy import symbols
        from sympy.physics import mechanics as me
    except ImportError:
        return None, 0.0

    start = time.perf_counter()
    q = me.dynamicsymbols(f"theta1:{n + 1}")
    u = me.dynamicsymbols(f"omega1:{n + 1}")
    m = symbols(f"m1:{n + 1}")
    l = symbols(f"l1:{n + 1}")
    g = symbols("g")
    frame = me.ReferenceFrame("N")
    parent = me.Point("O")
    parent.set_vel(frame, 0)
    bodies, loads, kinematics = [], [], []
    for i in range(n):
        link = frame.orientnew(f"A{i}", "Axis", [q[i], frame.z])
        link.set_ang_vel(frame, u[i] * frame.z)
        point = parent.locatenew(f"P{i}", -l[i] * link.y)
        point.v2pt_theory(parent, frame, link)
        bodies.append(me.Particle(f"bob{i}", point, m[i]))
        loads.append((point, -m[i] * g * frame.y))
        kinematics.append(q[i].diff() - u[i])
        parent = point
    kane = me.KanesMethod(frame, q_ind=q, u_ind=u, kd_eqs=kinematics)
    kane.kanes_equations(bodies, loads=loads)
    rhs = generate_ode_function(
        kane.forcing_full,
        q,
        u,
        list(m) + list(l) + [g],
        mass_matrix=kane.mass_matrix_full,
        generator=generator,
    )
    seconds = time.perf_counter() - start

    def pydy_rhs(t, y, params):
        return rhs(y, t, params)

    return pydy_rhs, seconds

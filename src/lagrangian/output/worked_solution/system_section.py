"""The first section of a worked solution: the system as the model file gives it.

Its coordinates, its parameters and their values, and what it is built from: the
particles and their positions, the rigid bodies (mass, centre of mass, orientation,
inertia), the springs, gravity, the generalized forces, the constraints and the inputs.
"""

from __future__ import annotations

import sympy

from ...model import RigidBody2D, System
from ..notation import latex_name
from .document import Display, Math, Paragraph, Section, Table, joined, parts
from .printing import Shower


def system_section(system: System, show: Shower) -> Section:
    blocks: list = []  # the description is the document's subtitle
    coordinates = [parts(Math(latex_name(n))) for n in system.coordinate_names]
    blocks.append(Paragraph(parts("Generalized coordinates: ", *joined(coordinates), ".")))
    values = system.parameter_values
    if system.parameters:
        rows = tuple(
            (
                parts(Math(latex_name(p.name))),
                parts(f"{values[p.name]:g}" if p.name in values else "none"),
            )
            for p in system.parameters
        )
        blocks.append(Table(("parameter", "value"), rows))
    if system.particles:
        rows = tuple(
            (
                parts(p.name),
                parts(Math(show(p.mass))),
                parts(Math(r"\left(" + ", ".join(show(x) for x in p.position) + r"\right)")),
            )
            for p in system.particles
        )
        blocks.append(Paragraph(parts("The particles and their positions:")))
        blocks.append(Table(("particle", "mass", "position"), rows))
    if system.bodies:
        blocks.append(Paragraph(parts("The rigid bodies:")))
        blocks.append(_bodies(system.bodies, show))
    if system.springs:
        blocks.append(Paragraph(parts("The linear springs, V = k (|r_a − r_b| − rest length)²/2:")))
        rows = tuple(
            (
                parts(s.name or f"spring {i + 1}"),
                parts(Math(show(s.stiffness))),
                parts(Math(show(s.rest_length))),
            )
            for i, s in enumerate(system.springs)
        )
        blocks.append(Table(("spring", "stiffness", "rest length"), rows))
    if system.gravity is not None:
        direction = system.gravity.direction
        along = (
            Math(r"\left(" + ", ".join(show(x) for x in direction) + r"\right)")
            if direction is not None
            else "the downward vertical"
        )
        blocks.append(
            Paragraph(
                parts("Uniform gravity ", Math(show(system.gravity.g)), " along ", along, ".")
            )
        )
    if system.forces:
        blocks.append(Paragraph(parts("Generalized non-conservative forces:")))
        rows = [show.row(f"Q_{{{latex_name(n)}}}", q) for n, q in system.forces.items()]
        blocks.append(Display(tuple(rows)))
    if system.constraints:
        blocks.append(Paragraph(parts("Constraints, linear in the velocities:")))
        blocks.append(Display(tuple(show.row("0", c) for c in system.constraints)))
    if system.input_names:
        inputs = joined([parts(Math(latex_name(n))) for n in system.input_names])
        blocks.append(Paragraph(parts("Inputs (held at 0 in the analysis): ", *inputs, ".")))
    return Section(parts("The system"), tuple(blocks))


def _bodies(bodies, show) -> Table:
    """One row per body: mass, centre of mass, orientation, inertia about the centre."""
    rows = []
    for body in bodies:
        centre = r"\left(" + ", ".join(show(x) for x in body.center) + r"\right)"
        if isinstance(body, RigidBody2D):
            orientation = parts("angle ", Math(show(body.angle)))
            inertia = Math(show(body.inertia))
        else:
            if body.euler is not None:
                angles = r"\left(" + ", ".join(show(a) for a in body.euler) + r"\right)"
                orientation = parts(f"Euler angles ({body.convention}) ", Math(angles))
            else:
                orientation = parts("a rotation matrix")
            inertia = Math(_tensor(body.inertia, show))
        rows.append(
            (
                parts(body.name or "body"),
                parts(Math(show(body.mass))),
                parts(Math(centre)),
                orientation,
                parts(inertia),
            )
        )
    return Table(("body", "mass", "centre of mass", "orientation", "inertia"), tuple(rows))


def _tensor(inertia, show) -> str:
    """diag(I1, I2, I3) for principal moments, else the matrix."""
    matrix = (
        sympy.Matrix(inertia)
        if len(inertia) == 3 and isinstance(inertia[0], (tuple, list))
        else None
    )
    if matrix is None:
        return r"\operatorname{diag}\left(" + ", ".join(show(x) for x in inertia) + r"\right)"
    if matrix.is_diagonal():
        return (
            r"\operatorname{diag}\left("
            + ", ".join(show(matrix[i, i]) for i in range(3))
            + r"\right)"
        )
    rows = r"\\".join(" & ".join(show(x) for x in matrix.row(i)) for i in range(3))
    return r"\begin{pmatrix}" + rows + r"\end{pmatrix}"

"""What the page checks of a value given to a parameter (a slider, a typed value, a share
link) beyond its sign, as :func:`lagrangian.model.values.check_parameter_values` does for
``--set``: each 3-D body's inertia and each mass, as data the page's scripts read
(``page_assets/inertia.js`` and ``page.js``), so that it refuses what the command line
refuses, in its words.
"""

from __future__ import annotations

from ..algebra import as_expression
from ..model import RigidBody, System
from ..model.values import masses


def mass_entries(system: System) -> list[dict]:
    """Each mass (and planar moment of inertia) as ``check_masses`` checks it: its words,
    its expression's text, the parameters it uses, its sign, and where the page's scene
    routine gives its value (m: a particle's, W: a planar body's [mass, inertia], J: a
    3-D body's [mass, ...]); a value given in the page that breaks it is refused in the
    command line's words."""
    places = [("m", i, 0) for i in range(len(system.particles))]
    planar = solid = 0
    for body in system.bodies:
        if isinstance(body, RigidBody):
            places.append(("J", solid, 0))
            solid += 1
        else:
            places += [("W", planar, 0), ("W", planar, 1)]
            planar += 1
    entries = []
    for (field, what, expression, sign), (block, row, column) in zip(
        masses(system), places, strict=True
    ):
        used = sorted(s.name for s in expression.free_symbols)
        formula = f" ({field} = {expression})" if used else ""
        entries.append(
            {"what": what + formula, "used": used, "sign": sign, "at": [block, row, column]}
        )
    return entries


def inertia_entries(system: System) -> list[dict]:
    """Each 3-D body's inertia as ``check_inertia`` checks a value given later
    (:func:`lagrangian.model.values.check_parameter_values`): its field, the parameters
    it uses, its row of the scene routine's J, and whether its tensor is diagonal (then
    the principal moments are its diagonal, named by their expressions, else the
    eigenvalues of its nine entries); inertia.js refuses a value that breaks it in the
    command line's words."""
    entries = []
    solid = 0
    for i, body in enumerate(system.bodies):
        if not isinstance(body, RigidBody):
            continue
        tensor = body.inertia
        diagonal = all(tensor[j][k] == 0 for j in range(3) for k in range(3) if j != k)
        checked = (
            [tensor[k][k] for k in range(3)] if diagonal else [x for row in tensor for x in row]
        )
        used = {s.name for row in tensor for x in row for s in x.free_symbols}
        entries.append(
            {
                "field": f"bodies[{i}].inertia",
                "used": sorted(used),
                "row": solid,
                "diagonal": diagonal,
                "expressions": [str(as_expression(x)) for x in checked],
            }
        )
        solid += 1
    return entries

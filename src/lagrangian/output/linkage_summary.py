"""What ``derive`` says of a linkage: Grübler's count, the coordinates held at assembly, the
joints that close loops with their multipliers, and the joint reactions as expressions."""

from __future__ import annotations

from collections.abc import Callable

import sympy

from ..derive import EquationsOfMotion


def linkage_document(eom: EquationsOfMotion, text: Callable[[sympy.Expr], str]) -> dict | None:
    """The ``linkage`` entry of ``derive --json`` (None without a linkage): reactions in
    t, q, q', q'', the parameters and the multipliers' names (``lambda1``, ...)."""
    linkage = eom.system.linkage
    if linkage is None:
        return None
    names = _multiplier_names(eom)
    named = dict(zip(linkage.multipliers, names, strict=True))
    return {
        "links": [link.name for link in linkage.links],
        "degrees_of_freedom": linkage.degrees_of_freedom,
        "held": [s.name for s in linkage.held],
        "joints": {
            joint.name: {
                "kind": joint.kind,
                "connects": [side.text for side in joint.sides],
                "closes_loop": not joint.tree,
                "multipliers": [str(names[k]) for k in joint.constraints],
                **(
                    {
                        "drive": text(joint.drive),
                        "drive_multiplier": str(names[joint.drive_constraint]),
                    }
                    if joint.drive is not None
                    else {}
                ),
            }
            for joint in linkage.joints
        },
        "reactions": {name: text(expr.xreplace(named)) for name, expr in linkage.reactions.items()},
    }


def linkage_lines(eom: EquationsOfMotion) -> list[str]:
    """The lines of ``derive``'s text about the linkage (none without one)."""
    linkage = eom.system.linkage
    if linkage is None:
        return []
    names = _multiplier_names(eom)
    links, joints = len(linkage.links), len(linkage.joints)
    freedom = "degree" if linkage.degrees_of_freedom == 1 else "degrees"
    lines = [
        "",
        "Linkage:",
        f"  {links} links, {joints} joints: {linkage.degrees_of_freedom} {freedom} of freedom "
        f"(Grübler: 3 x {links} - 2 x {joints})",
        "  held at assembly: " + (", ".join(s.name for s in linkage.held) or "none (driven)"),
    ]
    for joint in linkage.joints:
        if not joint.tree:
            multipliers = ", ".join(str(names[k]) for k in joint.constraints)
            lines.append(f"  joint {joint.name} closes a loop ({multipliers})")
        if joint.drive is not None:
            lines.append(
                f"  joint {joint.name} is driven: {joint.drive} ({names[joint.drive_constraint]})"
            )
    return lines


def _multiplier_names(eom: EquationsOfMotion) -> list[sympy.Symbol]:
    """The multipliers of the linkage's constraints, in their order."""
    linkage = eom.system.linkage
    start = linkage.offset
    return list(eom.constraints.multipliers[start : start + len(linkage.constraints)])

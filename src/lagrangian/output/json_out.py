"""The JSON documents of DESIGN section 5: SymPy ``str()`` text over the model's names."""

from __future__ import annotations

from ..derive import EquationsOfMotion
from .large import plain_printer, printed


def derive_document(eom: EquationsOfMotion) -> dict:
    """``derive --json``: equations, M and f with M q'' = f, and the solved accelerations."""
    system = eom.system
    n = len(eom.coordinates)
    text = plain_printer(system)  # SymPy's str(), or SymEngine's for large systems
    shown = printed(eom)
    forcing = [text(shown.forcing[i]) for i in range(n)]  # first: the equations hold it
    document = {
        "name": system.name,
        "coordinates": list(system.coordinate_names),
        "parameters": sorted(system.parameter_names),
        "functions": {f.name: [str(a) for a in f.arguments] for f in system.functions},
        "lagrangian": text(shown.lagrangian),
        "equations": [text(e) for e in shown.equations],
        "mass_matrix": [[text(shown.mass_matrix[i][j]) for j in range(n)] for i in range(n)],
        "forcing": forcing,
    }
    if system.units is not None:  # additive: a dimensioned model's units (issue 31)
        from .units import units_section  # imported for such models only

        document["units"] = units_section(system)
    if eom.accelerations is not None:
        document["accelerations"] = {name: text(expr) for name, expr in eom.accelerations.items()}
    if eom.constraints is not None:
        document["constraints"] = [text(c) for c in system.constraints]
        document["multipliers"] = (
            {name: text(expr) for name, expr in eom.multipliers.items()}
            if eom.multipliers is not None
            else {str(s): None for s in eom.constraints.multipliers}
        )
    if system.linkage is not None:  # additive: a linkage's count, joints and reactions (issue 34)
        from .linkage_summary import linkage_document  # imported for linkages only

        document["linkage"] = linkage_document(eom, text)
    return document

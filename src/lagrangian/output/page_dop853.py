"""The coefficients of DOP853 that the page's integrators use, shipped as data.

The page steps as ``simulate --method dop853`` does, with SciPy's DOP853 (Dormand and
Prince's explicit pair of order 8(5,3)), and its Poincaré section panel locates crossings
on SciPy's 7th-order dense output (:mod:`.page_section`).  The numbers are SciPy's,
written once into ``page_assets/dop853.json`` from the public attributes of
``scipy.integrate.DOP853``: the stepper's (``n_stages``, ``A``, ``B``, ``C``, ``E3``,
``E5``) and the dense output's (``A_EXTRA``, ``C_EXTRA``, ``D``).  Reading them from the
file keeps scipy.integrate (and a private module of it) out of writing a page: 0.03 s of
CPU on a first page, whose analysis loads the rest of SciPy it needs anyway;
tests/output/test_page_dop853.py checks them equal to SciPy's, number for number, and
writes the file anew when run as a script.
"""

from __future__ import annotations

import json
from functools import cache
from importlib import resources

#: The file in ``page_assets`` that holds the coefficients.
COEFFICIENTS_FILE = "dop853.json"


def stepper_coefficients() -> dict:
    """``{"stages": 12, "A": 12 rows of 12, "B", "C": 12 each, "E3", "E5": 13 each}``: a
    step and its two error estimates (stage 13 is f at the step's end)."""
    return json.loads(_text())["stepper"]


def dense_coefficients() -> dict:
    """``{"A": rows of 13, 14 and 15, "C": 3, "D": 4 rows of 16}``: the three extra stages
    (each on the stages before it) and the interpolant's coefficients over all 16."""
    return json.loads(_text())["dense"]


@cache
def _text() -> str:
    return (
        resources.files(__package__).joinpath("page_assets", COEFFICIENTS_FILE).read_text("utf-8")
    )

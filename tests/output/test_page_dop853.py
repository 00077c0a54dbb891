"""The DOP853 coefficients shipped with the page (lagrangian.output.page_dop853) are SciPy's,
number for number: the page steps and interpolates as ``simulate --method dop853`` and
``lagrangian poincare`` do.  Run as a script, this file writes them anew from SciPy:
``python tests/output/test_page_dop853.py``."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

from lagrangian.output import page_dop853
from lagrangian.output.page_dop853 import dense_coefficients, stepper_coefficients

SHIPPED = Path(page_dop853.__file__).with_name("page_assets") / page_dop853.COEFFICIENTS_FILE


def scipy_coefficients() -> dict:
    """The file's content, from the public attributes of ``scipy.integrate.DOP853``."""
    from scipy.integrate import DOP853

    stages = DOP853.n_stages
    return {
        "source": "scipy.integrate.DOP853: n_stages, A, B, C, E3, E5; A_EXTRA, C_EXTRA, D",
        "stepper": {
            "stages": stages,
            "A": DOP853.A.tolist(),
            "B": DOP853.B.tolist(),
            "C": DOP853.C.tolist(),
            "E3": DOP853.E3.tolist(),
            "E5": DOP853.E5.tolist(),
        },
        "dense": {  # extra stage k (from stages + 1) depends on the k stages before it
            "A": [row[:k].tolist() for k, row in enumerate(DOP853.A_EXTRA, start=stages + 1)],
            "C": DOP853.C_EXTRA.tolist(),
            "D": DOP853.D.tolist(),
        },
    }


def test_the_shipped_coefficients_are_scipys_exactly():
    expected = scipy_coefficients()
    # == on floats parsed from the file: every number the same double as SciPy's
    assert stepper_coefficients() == expected["stepper"]
    assert dense_coefficients() == expected["dense"]
    assert json.loads(SHIPPED.read_text("utf-8")) == expected


def test_the_shapes_are_those_the_page_indexes():
    stepper, dense = stepper_coefficients(), dense_coefficients()
    stages = stepper["stages"]
    assert stages == 12
    assert [len(row) for row in stepper["A"]] == [stages] * stages
    assert len(stepper["B"]) == len(stepper["C"]) == stages
    assert len(stepper["E3"]) == len(stepper["E5"]) == stages + 1
    assert [len(row) for row in dense["A"]] == [13, 14, 15]
    assert len(dense["C"]) == 3
    assert [len(row) for row in dense["D"]] == [16] * 4


def test_a_caller_changing_its_copy_changes_no_other():
    stepper_coefficients()["B"][0] = 99.0
    assert stepper_coefficients()["B"][0] != 99.0


def _file_text(coefficients: dict) -> str:
    """The JSON text with each row of numbers on one line."""
    text = json.dumps(coefficients, indent=1)
    return re.sub(r"\[([^\[\]]*)\]", lambda row: f"[{' '.join(row.group(1).split())}]", text)


if __name__ == "__main__":
    SHIPPED.write_text(_file_text(scipy_coefficients()) + "\n", "utf-8")
    sys.stdout.write(f"wrote {SHIPPED}\n")

"""Long rows of the page's worked solution folded (output/page_folding.py): shortened in
their block, kept whole in an item the page typesets when it is opened."""

from __future__ import annotations

import lagrangian as lg
from lagrangian.derive import derive
from lagrangian.output.latex import aligned, equation_rows, latex_equations
from lagrangian.output.page_folding import FOLD_CHARACTERS, folded_block, shortened


def _sum(count: int) -> str:
    return " + ".join(rf"\frac{{x^{{{k}}}}}{{{k}}}" for k in range(1, count + 1))


def test_a_short_block_is_left_as_it_is():
    rows = [r"L &= \frac{m \dot{x}^{2}}{2}", r"0 &= m \ddot{x} + k x"]
    assert folded_block(rows) == [{"latex": aligned(rows)}]


def test_a_long_sum_shows_its_first_terms_and_how_many_are_left_out():
    long = _sum(300)  # 300 terms, 5,000 characters
    assert len(long) > FOLD_CHARACTERS
    block, whole = folded_block([r"L &= x", rf"V &= {long}"])
    shown = block["latex"].removesuffix("\n\\end{align*}").split(" \\\\\n")[1]
    first = shown.removeprefix("V &= ").split(r" + \cdots")[0]
    kept = first.count(r"\frac")
    assert first == _sum(kept) and 0 < kept < 300
    assert shown.endswith(rf" + \cdots \quad \text{{({300 - kept} more terms, in full below)}}")
    assert whole == {"latex": f"V = {long}", "folded": "V"}  # the document keeps it whole


def test_a_long_fraction_is_shown_as_dots():
    fraction = rf"\frac{{{_sum(200)}}}{{{_sum(150)}}}"  # one term: nothing to show of it
    assert shortened(fraction) == r"\cdots \quad \text{(in full below)}"
    assert shortened("- " + _sum(2)) == "- " + _sum(2)  # short: whole


def test_a_steps_note_stays_on_its_row():
    long = _sum(300)
    (block, whole) = folded_block([rf"0 &= {long} &&\text{{(divided by }} m\text{{)}}"])
    assert block["latex"].endswith(
        r"in full below)} &&\text{(divided by } m\text{)}" + "\n\\end{align*}"
    )
    assert whole["latex"] == rf"0 = {long} \quad \text{{(divided by }} m\text{{)}}"


def test_the_slider_cranks_solved_rows_are_folded_and_kept_whole():
    # its accelerations and multipliers: 21,000-28,000 characters each (one fraction)
    eom = derive(lg.load("slider_crank"))
    rows = equation_rows(eom)
    assert latex_equations(eom) == aligned(rows)
    items = folded_block(rows)
    long = [row for row in rows if len(row) > FOLD_CHARACTERS]
    assert len(long) == 5 and len(items) == 6  # theta, x, phi; lambda1, lambda2
    assert len(items[0]["latex"]) < 4 * FOLD_CHARACTERS
    for row, item in zip(long, items[1:], strict=True):
        lhs, _, rhs = row.partition(" &= ")
        assert item == {"latex": f"{lhs} = {rhs}", "folded": lhs}
        assert rf"{lhs} &= \cdots \quad \text{{(in full below)}}" in items[0]["latex"]

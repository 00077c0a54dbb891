"""Long rows of the page's worked solution folded, typeset whole only when asked for.

A linkage's solved accelerations and multipliers are rows of 18,000-28,000 characters of
LaTeX (a four-bar's, a slider-crank's: one fraction each), where every other built-in
example's longest row has under 600.  Typeset whole at load they made the page's DOM
165,000 elements and its load 11 s of browser CPU.  A row longer than
:data:`FOLD_CHARACTERS` is shown in its block by its first terms and ``+ \\cdots`` with
the number of terms left out (``\\cdots`` alone where its first term is already long),
and whole in an item of its own (``"folded"``: the row's left side) that the page shows
as a closed ``<details>`` and typesets when it is first opened.  The page's document keeps
every row whole; ``derive --json`` and ``--latex`` are not folded.
"""

from __future__ import annotations

from .latex import aligned, top_level_terms

#: Rows longer than this (characters of LaTeX) are folded.
FOLD_CHARACTERS = 2000
#: Characters of a folded row's first terms shown in its block at most.
SHOWN_CHARACTERS = 240
#: Where a row's left side ends and its right side begins.
RELATION = " &= "


def folded_block(rows: list[str]) -> list[dict]:
    """The items of the ``align*`` block of ``rows``: the block, with each row longer than
    FOLD_CHARACTERS shortened, then each such row whole, folded (see the module)."""
    shown, whole = [], []
    for row in rows:
        lhs, relation, rhs = row.partition(RELATION)
        if len(row) <= FOLD_CHARACTERS or not relation:
            shown.append(row)
            continue
        rhs, aligned_note, note = rhs.partition(" &&")  # a step's "(divided by ...)"
        shown.append(lhs + relation + shortened(rhs) + aligned_note + note)
        whole.append(
            {"latex": f"{lhs} = {rhs}" + (rf" \quad {note}" if note else ""), "folded": lhs}
        )
    return [{"latex": aligned(shown)}, *whole]


def shortened(latex: str) -> str:
    """The first terms of ``latex`` (a sum) up to SHOWN_CHARACTERS, and what is left out."""
    terms = top_level_terms(latex)
    kept: list[str] = []
    while len(kept) < len(terms) and len(" ".join([*kept, terms[len(kept)]])) <= SHOWN_CHARACTERS:
        kept.append(terms[len(kept)])
    left = len(terms) - len(kept)
    if not left:
        return latex
    if not kept:
        return r"\cdots \quad \text{(in full below)}"
    more = f"{left} more term{'s' if left > 1 else ''}"
    return " ".join(kept) + rf" + \cdots \quad \text{{({more}, in full below)}}"

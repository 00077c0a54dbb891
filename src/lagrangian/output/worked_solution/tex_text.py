"""Text of the model and of the analysis made safe, and readable, in a LaTeX document.

Sentences come from the model file (its name, its description) and from the analysis
(``φ is cyclic``, ``h = Σ q̇ ∂L/∂q̇ - L``).  In LaTeX every character that means
something (``\\ { } $ & # ^ _ % ~``) is written as the character itself, so that a model
cannot run a command (``\\input``, ``\\write18``) in a teacher's document; the
mathematical characters pdflatex cannot typeset from the text fonts (Greek letters,
``∂``, ``Σ``, superscripts, the combining dot of ``q̇``) become the same symbols in math
mode.  Latin letters with accents (``é``) pass: LaTeX reads UTF-8.  Anything else is
written as ``?``, so the document always compiles.
"""

from __future__ import annotations

import unicodedata

_SPECIAL = {
    "\\": r"\textbackslash{}",
    "{": r"\{",
    "}": r"\}",
    "$": r"\$",
    "&": r"\&",
    "#": r"\#",
    "^": r"\textasciicircum{}",
    "_": r"\_",
    "%": r"\%",
    "~": r"\textasciitilde{}",
    "<": r"\textless{}",
    ">": r"\textgreater{}",
    "|": r"\textbar{}",
}
_TEXT = {
    "–": "--",
    "—": "---",
    "‘": "`",
    "’": "'",
    "“": "``",
    "”": "''",
    "…": r"\ldots{}",
    "\u00a0": "~",
}
_MATH = {
    "∂": r"\partial",
    "−": "-",
    "×": r"\times",
    "·": r"\cdot",
    "≤": r"\leq",
    "≥": r"\geq",
    "≠": r"\neq",
    "≈": r"\approx",
    "→": r"\to",
    "∞": r"\infty",
    "±": r"\pm",
    "∈": r"\in",
    "∇": r"\nabla",
    "∫": r"\int",
    "√": r"\surd",
    "′": r"\prime",
    "∧": r"\wedge",
    "ħ": r"\hbar",
    "ℓ": r"\ell",
}
_SUPERSCRIPTS = dict(zip("⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻ⁿ", "0123456789+-n", strict=True))
_SUBSCRIPTS = dict(
    zip("₀₁₂₃₄₅₆₇₈₉₊₋ₐₑₒₓₕₖₗₘₙₚₛₜᵢⱼᵣᵤᵥ", "0123456789+-aeoxhklmnpstijruv", strict=True)
)
_COMBINING = {"\u0307": "dot", "\u0308": "ddot", "\u0302": "hat", "\u0304": "bar", "\u20d7": "vec"}
#: LaTeX has no command for the capitals that look like Latin letters.
_GREEK_CAPITALS_LATIN = dict(zip("ΑΒΕΖΗΙΚΜΝΟΡΤΧ", "ABEZHIKMNOPTX", strict=True))
#: φ is the toolkit's phi (notation.unicode_name), typeset as latex_name types it: \phi.
_VARIANTS = {
    "ϕ": r"\phi",
    "φ": r"\phi",
    "ϑ": r"\vartheta",
    "ϵ": r"\epsilon",
    "ε": r"\varepsilon",
}


def tex_text(text: str) -> str:
    """``text`` as LaTeX text (see the module): nothing in it is a command."""
    pieces: list[tuple[bool, str]] = []  # (math?, LaTeX)
    for char in "".join(map(_decomposed, text)):
        if char in _COMBINING:
            accent = _COMBINING[char]
            base = pieces.pop() if pieces else (True, r"\,")
            inner = base[1] if base[0] else _math_letter(base[1])
            pieces.append((True, rf"\{accent}{{{inner}}}"))
        elif char in _SUPERSCRIPTS:
            pieces.append((True, f"^{{{_SUPERSCRIPTS[char]}}}"))
        elif char in _SUBSCRIPTS:
            pieces.append((True, f"_{{{_SUBSCRIPTS[char]}}}"))
        elif char in _MATH or _greek(char):
            pieces.append((True, _MATH.get(char) or _greek(char)))
        elif char in _SPECIAL:
            pieces.append((False, _SPECIAL[char]))
        elif char in _TEXT:
            pieces.append((False, _TEXT[char]))
        elif char == "\n" or char == "\t":
            pieces.append((False, " "))
        elif char == "-" and pieces and pieces[-1] == (False, "-"):
            pieces.append((False, "{}-"))  # --json, not an en dash
        elif ord(char) < 128 or _latin(char):
            pieces.append((False, char))
        else:
            pieces.append((False, "?"))
    return _joined(pieces)


def _joined(pieces: list[tuple[bool, str]]) -> str:
    """Runs of math pieces in one ``\\ensuremath{...}`` each (``ω²`` as ``\\omega^{2}``)."""
    out, run = [], []
    for math, latex in pieces:
        if math:
            # a superscript or subscript binds to the text letter before it (p_x, x^2)
            if latex[0] in "^_" and not run and out and _is_letter(out[-1]):
                run.append(out.pop())
            run.append(latex + (" " if latex[-1].isalpha() else ""))
            continue
        if run:
            out.append(r"\ensuremath{" + "".join(run).strip() + "}")
            run = []
        out.append(latex)
    if run:
        out.append(r"\ensuremath{" + "".join(run).strip() + "}")
    return "".join(out)


def _is_letter(text: str) -> bool:
    return len(text) == 1 and text.isascii() and text.isalnum()


def _math_letter(text: str) -> str:
    """A text piece as the nucleus of an accent: a letter stays, a special one is escaped."""
    return text if _is_letter(text) else r"\text{" + text + "}"


def _greek(char: str) -> str:
    if char in _VARIANTS:
        return _VARIANTS[char]
    if not "\u0391" <= char <= "\u03c9":
        return ""
    name = unicodedata.name(char, "")
    if not name.startswith("GREEK"):
        return ""
    letter = name.rsplit(" ", 1)[-1].lower()
    letter = {"lamda": "lambda", "omicron": "o", "final": "varsigma"}.get(letter, letter)
    if "CAPITAL" in name:
        if char in _GREEK_CAPITALS_LATIN:
            return _GREEK_CAPITALS_LATIN[char]
        return "\\" + letter.capitalize()
    return "\\" + letter


def _decomposed(char: str) -> str:
    """``ẋ`` (one character) as ``x`` and the combining dot; ``é`` stays whole."""
    parts = unicodedata.normalize("NFD", char)
    return parts if len(parts) == 2 and parts[1] in _COMBINING else char


def _latin(char: str) -> bool:
    """A letter with an accent that LaTeX's UTF-8 input and T1 fonts set (é, ü, ß)."""
    return ord(char) < 0x250 and unicodedata.category(char).startswith("L")

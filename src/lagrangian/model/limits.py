"""Size limits of a model, all in one place, checked before any symbolic work.

Each expression is bounded by the parser (:class:`~lagrangian.parsing.ParseLimits`);
these bound how many there are and what reading a model file may cost.  They
are generous for hand-written and generated models (the largest built-in
example has 3 coordinates) and keep a hostile file to a second or two of work:

* :data:`MAX_FILE_BYTES`: a model file is read whole; TOML parses at about a
  microsecond a byte.
* :data:`MAX_KEY_PARTS`: Python's TOML reader takes time quadratic in the parts
  of one dotted key (``a.a.a....`` with 100,000 parts: minutes), so longer
  keys are refused by a linear scan before it runs.  Nesting of arrays and
  tables deeper than Python's recursion limit is refused from its RecursionError.
* :data:`MAX_COUNTS`: coordinates, parameters, particles ... (each becomes SymPy
  symbols and expressions, and derivation grows with their number).
* :data:`MAX_EXPRESSION_CHARACTERS`: the text of all expressions together
  (the parser takes about 10 microseconds a character).
* :data:`MAX_KINETIC_PAIRS`: the work of assembling T from particles and bodies,
  estimated from how many coordinates each one moves with, before it starts.
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Iterable, Mapping
from types import MappingProxyType

from ..errors import ModelError

MAX_FILE_BYTES = 1 << 20
"""Largest model file read (1 MiB)."""

MAX_KEY_PARTS = 32
"""Most parts of one dotted TOML key (``a.b.c`` has 3)."""

MAX_COUNTS: Mapping[str, int] = MappingProxyType(
    {
        "coordinates": 200,
        "parameters": 1_000,
        "particles": 500,
        "bodies": 500,
        "springs": 500,
        "links": 100,  # each closing joint adds two constraints
        "joints": 100,
        "constraints": 200,
        "impacts": 200,
        "functions": 100,
        "forces": 200,
        "conservative_forces": 200,
        "initial": 400,
        "inputs": 200,
        "units": 1_500,  # one per coordinate, parameter, input and function at most
    }
)
"""Most entries of each list or table of a model."""

MAX_EXPRESSION_CHARACTERS = 200_000
"""Most characters of expression text in one model, all fields together."""

MAX_KINETIC_PAIRS = 200_000
"""Most pairs of velocities, summed over the particles and bodies, that the kinetic
energy of a geometric model couples: a point moving with ``k`` coordinates adds
``k (k + 1) / 2`` (a 100-link pendulum chain has 171,700 and builds in 2-4 s; 4
points moving with 200 coordinates each, 80,400 pairs, in 1.4 s)."""

# A dotted key of more than MAX_KEY_PARTS parts.  Possessive parts and the look-behind
# (no start inside a key) keep the scan linear on any text; a match inside a string
# value would need 33 dotted words without spaces, which no model's text has.
_KEY_PART = r"""(?:[A-Za-z0-9_-]++|"(?:[^"\\\n]|\\.)*+"|'[^'\n]*+')"""
_DEEP_KEY = re.compile(
    rf"(?<![A-Za-z0-9_\-\"'.]){_KEY_PART}(?:[ \t]*+\.[ \t]*+{_KEY_PART}){{{MAX_KEY_PARTS},}}"
)


def file_size_problem(size: int, unit: str = "bytes") -> str | None:
    """Why a model file of ``size`` bytes (or characters of text) is not read, or None."""
    if size > MAX_FILE_BYTES:
        return f"file too large ({size} {unit}, limit {MAX_FILE_BYTES} = 1 MiB)"
    return None


def check_toml_keys(text: str) -> None:
    """Refuse a dotted key too long for the TOML reader (before it runs)."""
    # such a key has more than MAX_KEY_PARTS dots on one line: most files have no such
    # line, and the scan of every position costs (0.03 s for the 100-link chain's 200 kB)
    if all(line.count(".") < MAX_KEY_PARTS for line in text.split("\n")):
        return
    found = _DEEP_KEY.search(text)
    if found is not None:
        line = text.count("\n", 0, found.start()) + 1
        raise ModelError(
            f"invalid TOML: a dotted key of more than {MAX_KEY_PARTS} parts (line {line})"
        )


def check_table_keys(table: Mapping[str, object], allowed: set[str], where: str) -> None:
    """Refuse a key of the model file's table at ``where`` not in ``allowed`` (the first
    such key by name, so the message does not depend on the file's order)."""
    unknown = set(table) - allowed
    if unknown:
        name = sorted(unknown)[0]
        raise ModelError(
            f"unknown key (expected one of {', '.join(sorted(allowed))})", field=f"{where}.{name}"
        )


def check_counts(counts: Mapping[str, int]) -> None:
    """Refuse a model with more entries of a kind than :data:`MAX_COUNTS` allows.

    >>> check_counts({"coordinates": 3, "particles": 2})
    >>> check_counts({"coordinates": 50_000})
    Traceback (most recent call last):
    ...
    lagrangian.errors.ModelError: coordinates: too many (50000, limit 200)
    """
    for kind, count in counts.items():
        limit = MAX_COUNTS[kind]
        if count > limit:
            raise ModelError(f"too many ({count}, limit {limit})", field=kind)


def check_expression_text(lengths: Mapping[str, int]) -> None:
    """Refuse a model whose expressions (field -> characters) hold more than
    :data:`MAX_EXPRESSION_CHARACTERS` in all, naming the longest."""
    total = sum(lengths.values())
    if total > MAX_EXPRESSION_CHARACTERS:
        longest = max(lengths, key=lengths.__getitem__)
        raise ModelError(
            f"expressions too long in all ({total} characters in {len(lengths)} fields, "
            f"limit {MAX_EXPRESSION_CHARACTERS}; this one has {lengths[longest]})",
            field=longest,
        )


def check_kinetic_work(moving_with: Iterable[int]) -> None:
    """Refuse particles and bodies (each moving with so many coordinates) whose kinetic
    energy couples more than :data:`MAX_KINETIC_PAIRS` pairs of velocities."""
    pairs = sum(k * (k + 1) // 2 for k in moving_with)
    if pairs > MAX_KINETIC_PAIRS:
        raise ModelError(
            f"kinetic energy too large to assemble: the particles and bodies couple {pairs} "
            f"pairs of velocities (limit {MAX_KINETIC_PAIRS}); give fewer points that each "
            "move with fewer coordinates",
            field="particles",
        )


#: Unicode categories refused in plain text (a name, a description): controls (NUL, CR, ...),
#: format characters (bidirectional overrides, ...), the line and paragraph separators, and
#: lone surrogates (Python strings may hold them, UTF-8 files and pages cannot).
_REFUSED_CATEGORIES = frozenset({"Cc", "Cf", "Zl", "Zp", "Cs"})


def check_plain_text(value: object, field: str, *, breaks: str = "") -> str:
    """``value`` if it is text a model file could hold: no control character (but those in
    ``breaks``) and no lone surrogate, which every file and page it reaches would refuse
    to encode; ModelError naming ``field`` and the character otherwise.

    >>> check_plain_text("Pendulum", "name")
    'Pendulum'
    >>> check_plain_text("a\\rb", "name")
    Traceback (most recent call last):
    ...
    lagrangian.errors.ModelError: name: control character U+000D not allowed in text
    """
    if not isinstance(value, str):
        raise ModelError(f"expected text, got {type(value).__name__}", field=field)
    for character in value:
        category = unicodedata.category(character)
        if category in _REFUSED_CATEGORIES and character not in breaks:
            what = "lone surrogate" if category == "Cs" else "control character"
            why = " (it has no UTF-8 form)" if category == "Cs" else ""
            raise ModelError(f"{what} U+{ord(character):04X} not allowed in text{why}", field=field)
    return value

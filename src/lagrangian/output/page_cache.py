"""Pages written before, kept on disk: ``lagrangian page`` of a model seen before.

Writing a page derives and analyses the model exactly (seconds of SymPy: the double
pendulum's equilibria and their normal modes are most of it), and the same model gives
the same page.  So a page is kept as ``<cache>/pages/<key>.html`` (``<cache>`` is
``$LAGRANGIAN_CACHE`` or the user cache folder, :func:`lagrangian.codegen.cache.cache_root`)
and written from there the next time, without loading SymPy's work again.

The key is the sha256 of everything the page is made from: the model file's bytes, the
values and definitions given, and the code that makes it (the package's files, by
relative path, size and modification time, as Python's bytecode cache judges a source,
and the versions of Python, SymPy, SymEngine, NumPy and SciPy).  A page is kept only when
its analysis decided every stage within its time and nothing was warned: a stage cut
short on a busy machine is not remembered, and a warning is said again on every run.
At most :data:`KEPT_PAGES` are kept, the least recently written going first.

A kept page is text this process writes into a file, never runs.  It is read only from
this user's private folder and files (as the code cache: not another user's, not
writable by others), and its first line holds the sha256 of the rest: a file damaged on
disk, cut short or edited is ignored and written again.  ``--no-cache`` or
``LAGRANGIAN_NO_CACHE=1`` neither reads nor writes the cache.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import warnings
from collections.abc import Callable, Mapping
from pathlib import Path

from ..codegen.cache import cache_root, folder_problem, trusted_bytes
from ..errors import FileError, LagrangianError
from ..files import write_atomically
from .page import Page

#: Set (to anything but "" or "0") to neither read nor write kept pages.
NO_CACHE_VARIABLE = "LAGRANGIAN_NO_CACHE"
#: The first line of a kept page; the sha256 of the rest follows it.
_HEADER = "<!-- lagrangian page cache: sha256="
_END = " -->\n"
#: Part of every key: a change in what a kept file holds makes the old ones unused.
_FORMAT = "lagrangian page cache 1"
#: Pages kept at most (about 0.7-1 MB each): the least recently written go first.
KEPT_PAGES = 64


def cache_enabled() -> bool:
    """Whether pages are kept and reused (not when ``LAGRANGIAN_NO_CACHE`` is set)."""
    return os.environ.get(NO_CACHE_VARIABLE, "") in ("", "0")


def cached_page(model_bytes: bytes, inputs: Mapping[str, object], build: Callable[[], Page]) -> str:
    """The page of the model file ``model_bytes`` with ``inputs`` (the values and definitions
    given, JSON-ready): the one kept on disk, else ``build()``'s, kept when it decided
    everything without a warning."""
    path = _folder() / f"{_key(model_bytes, inputs)}.html"
    kept = _read(path)
    if kept is not None:
        return kept
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        page = build()
    for warning in caught:  # said again to the caller, as if no one had listened
        warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    if page.decided and not caught:
        _write(path, page.html)
    return page.html


def _key(model_bytes: bytes, inputs: Mapping[str, object]) -> str:
    digest = hashlib.sha256()
    for part in (_FORMAT, _code_signature(), json.dumps(inputs, sort_keys=True)):
        digest.update(part.encode("utf-8") + b"\0")
    digest.update(model_bytes)
    return digest.hexdigest()


def _code_signature() -> str:
    """What the page's code is: the versions of its libraries and, for each file of the
    package, its relative path, size and modification time."""
    import numpy
    import sympy

    versions = [sys.version, sympy.__version__, numpy.__version__]
    for name in ("scipy", "symengine"):
        versions.append(_version(name))
    package = Path(__file__).resolve().parent.parent
    files = []
    for folder, subfolders, names in os.walk(package):
        subfolders[:] = sorted(s for s in subfolders if s != "__pycache__")
        for name in sorted(names):
            status = os.stat(os.path.join(folder, name))
            relative = os.path.relpath(os.path.join(folder, name), package)
            files.append(f"{relative}:{status.st_size}:{status.st_mtime_ns}")
    return "\n".join([*versions, *files])


def _version(distribution: str) -> str:
    from importlib import metadata

    try:
        return f"{distribution} {metadata.version(distribution)}"
    except metadata.PackageNotFoundError:
        return f"{distribution} absent"


def _folder() -> Path:
    return cache_root() / "pages"


def _read(path: Path) -> str | None:
    """The page kept at ``path`` when it is this user's file, that others cannot write, and
    its digest matches; else None."""
    data = trusted_bytes(path)
    if data is None:
        return None
    header, _, body = data.partition(_END.encode("ascii"))
    if header != (_HEADER + hashlib.sha256(body).hexdigest()).encode("ascii"):
        return None
    try:
        return body.decode("utf-8")
    except UnicodeDecodeError:
        return None


def _write(path: Path, html: str) -> None:
    """Keep ``html`` at ``path``; a cache that cannot be written is skipped, silently (the
    page itself is written where it was asked for)."""
    if folder_problem(path.parent) is not None:
        return
    body = html.encode("utf-8")
    text = _HEADER.encode("ascii") + hashlib.sha256(body).hexdigest().encode("ascii")
    try:
        write_atomically(path, lambda temporary: temporary.write_bytes(text + _END.encode() + body))
        path.chmod(0o600)  # a group-writable file (umask 002) would never be read back
        _forget_oldest(path.parent)
    except (FileError, LagrangianError, OSError):
        return


def _forget_oldest(folder: Path) -> None:
    """Delete the pages beyond :data:`KEPT_PAGES`, the least recently written first (a
    page read back is not touched: reading writes nothing)."""
    pages = sorted(folder.glob("*.html"), key=lambda page: page.stat().st_mtime_ns)
    for page in pages[: max(0, len(pages) - KEPT_PAGES)]:
        page.unlink(missing_ok=True)

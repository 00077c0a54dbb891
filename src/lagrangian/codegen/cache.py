"""The caches of generated code: one in memory, keyed by (fingerprint, target), and on disk.

In memory, :func:`built` keeps what a target made from a program in this process (a
jitted loop, a CUDA source, heyoka's integrator, the midpoint fillers), keyed by the
forms' fingerprint (:func:`~lagrangian.codegen.program.forms_fingerprint`), the target's
name and the options it was made with: two compiled systems of the same equations share
it, and the :data:`BUILT_LIMIT` oldest entries beyond the limit are let go.

On disk, the numba backend's generated modules, checked before they run.

A generated module is the file ``<cache>/numba/<digest>.py`` (``<cache>`` is
``$LAGRANGIAN_CACHE`` or the user cache folder, see :func:`cache_directory`).
Its first line holds the sha256 of the rest::

    # lagrangian code cache: sha256=<64 hex digits>

The digest is only the key: a hash that sits in the file it protects vouches
for nothing (whoever can write the file can write the hash).  What runs is the
text this process generates (tens of milliseconds: 25-70 ms for the double
pendulum's and the heavy top's modules), handed to the import system from
memory under the file's name so that numba finds its machine code; the file is
compared with it byte for byte, and one that differs (damaged, edited,
replanted) is written again and numba's files beside it are forgotten.

The folder is made private (0700), and a folder or file of the cache that is
not owned by this user or that others may write is not used: its machine code
(pickles numba loads) could be anyone's.

numba keeps the machine code beside the module (``__pycache__/<digest>.*.nbi``,
``.nbc``), pickles it reads without checking: a damaged index stops every
later run with an ``UnpicklingError``, damaged machine code can abort the
process inside LLVM.  So after each of numba's saves, and at exit, the sha256 of
those files goes into ``<digest>.numba-sha256``, and before a module is used its
numba files are compared with it; files that do not match, or that no list
vouches for (a run killed between a save and its listing), are deleted and numba
compiles again.

A cache folder that cannot be written (read-only, a path through a file), or
that is another user's or writable by others, is replaced by a private
temporary folder for this process, with one
:class:`~lagrangian.errors.CacheWarning`.
"""

from __future__ import annotations

import atexit
import contextlib
import functools
import hashlib
import importlib.machinery
import importlib.util
import os
import shutil
import stat
import sys
import tempfile
import threading
import warnings
from collections.abc import Callable, Hashable, Sequence
from pathlib import Path
from types import ModuleType
from typing import TypeVar

from ..errors import CacheWarning, FileError, ModelError
from ..files import write_atomically

_HEADER = "# lagrangian code cache: sha256="
_MODULES: dict[str, ModuleType] = {}
_CHOSEN: dict[str, Path] = {}  # configured folder -> the folder used in this process
_LOADED: set[Path] = set()  # modules whose numba files are listed at exit
_LOCK = threading.RLock()

#: How many built objects the in-memory cache keeps (the oldest go first).
BUILT_LIMIT = 128
_BUILT: dict[tuple[Hashable, ...], object] = {}
_ABSENT = object()
T = TypeVar("T")


def built(fingerprint: str, target: str, build: Callable[[], T], *options: Hashable) -> T:
    """What ``build()`` makes for (``fingerprint``, ``target``, ``options``), made once per
    process: later calls (every step of a run may ask) return it without a lock."""
    key = (fingerprint, target, *options)
    found = _BUILT.get(key, _ABSENT)
    if found is not _ABSENT:
        return found  # type: ignore[return-value]
    with _LOCK:
        if key not in _BUILT:
            _BUILT[key] = build()
            while len(_BUILT) > BUILT_LIMIT:
                del _BUILT[next(iter(_BUILT))]
        return _BUILT[key]  # type: ignore[return-value]


def built_already(fingerprint: str, target: str, *options: Hashable) -> bool:
    """Whether :func:`built` holds what it made for these keys in this process."""
    return (fingerprint, target, *options) in _BUILT


def cache_root() -> Path:
    """The folder of every cache of the package: ``$LAGRANGIAN_CACHE`` or the user cache's
    ``lagrangian`` (generated modules in ``numba``, pages in ``pages``)."""
    root = os.environ.get("LAGRANGIAN_CACHE")
    if root:
        return Path(root)
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Caches"
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "lagrangian"


def cache_directory() -> Path:
    """Where generated modules live: ``$LAGRANGIAN_CACHE/numba`` or the user cache."""
    return cache_root() / "numba"


def usable_directory() -> Path:
    """:func:`cache_directory` if it can be written, else a temporary folder (one warning)."""
    configured = cache_directory()
    with _LOCK:
        chosen = _CHOSEN.get(str(configured))
        if chosen is None:
            problem = folder_problem(configured)
            chosen = configured if problem is None else _temporary_folder(configured, problem)
            _CHOSEN[str(configured)] = chosen
        return chosen


def load_text(digest: str, source: object) -> ModuleType:
    """The module ``<digest>.py`` of the text ``str(source)``: from this process, else the
    text generated now, run from memory; the file on disk is kept when it holds the same
    bytes (numba's machine code beside it stays usable), else written again."""
    path = usable_directory() / f"{digest}.py"
    with _LOCK:
        module = _MODULES.get(str(path))
        if module is not None:
            return module
        body = str(source)
        text = _HEADER + hashlib.sha256(body.encode()).hexdigest() + "\n" + body
        if trusted_bytes(path) == text.encode("utf-8"):
            _check_numba_files(path)
        else:
            _forget_numba_files(path)  # machine code of whatever was there before
            _write(path, text)
        module = _import(path, text)
        _MODULES[str(path)] = module
        _LOADED.add(path)
        return module


@functools.cache  # a package file, read once per process (a run's choice asks for its hash)
def package_text(module_file: Path) -> tuple[str, str]:
    """(sha256, text) of a numba module of the package that goes into the code cache as it
    is (the same for every system: compiled once on a machine)."""
    text = module_file.read_text(encoding="utf-8")
    return hashlib.sha256(text.encode()).hexdigest(), text


def filled_template(template: Path, generated: Sequence[str]) -> tuple[str, str]:
    """(sha256, text) of the template module ``template`` (a numba template of the
    package) with the lines ``generated`` in place of the block between its
    ``# -- generated: begin`` and ``# -- generated: end`` markers."""
    head, rest = template.read_text(encoding="utf-8").split(_GENERATED_BEGIN, 1)
    tail = rest.split(_GENERATED_END, 1)[1].split("\n", 1)[1]
    text = "\n".join([head.rstrip("\n"), "", *generated, "", tail])
    return hashlib.sha256(text.encode()).hexdigest(), text


_GENERATED_BEGIN, _GENERATED_END = "# -- generated: begin", "# -- generated: end"


def trusted_bytes(path: Path) -> bytes | None:
    """The bytes of ``path`` when it is this user's regular file that others cannot write."""
    try:
        if _foreign(path.lstat(), regular=True) is None:
            return path.read_bytes()
    except OSError:
        pass
    return None


def module_name(path: Path) -> str:
    """The name the generated module of ``path`` is imported under."""
    folder = hashlib.sha256(str(path).encode()).hexdigest()[:8]
    return f"_lagrangian_numba_{folder}_{path.stem[:16]}"


def compiled_on_disk(digest: str, function: str) -> bool:
    """Whether numba's machine code of ``function`` of the module ``<digest>.py`` is in the
    cache (its index file; whether it is sound is checked when the module loads)."""
    folder = usable_directory() / "__pycache__"
    return any(folder.glob(f"{digest}.{function}-*.nbi"))


def _import(path: Path, text: str) -> ModuleType:
    """Run ``text`` as the module of ``path`` (numba's disk cache finds globals by name)."""
    name = module_name(path)
    loader = _VerifiedLoader(name, path, text.encode("utf-8"))
    spec = importlib.util.spec_from_file_location(name, path, loader=loader)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return module


class _VerifiedLoader(importlib.machinery.SourceFileLoader):
    """Loads the text that was checked: no second read of the file, no ``.pyc`` (Python's
    bytecode cache is another file that could be damaged, and is checked by date only)."""

    def __init__(self, name: str, path: Path, data: bytes):
        super().__init__(name, str(path))
        self._data = data

    def get_data(self, path: str) -> bytes:
        if path == self.path:
            return self._data
        raise OSError("generated modules keep no bytecode cache")

    def set_data(self, path: str, data: bytes, *, _mode: int = 0o666) -> None:
        pass


def _write(path: Path, text: str) -> None:
    try:
        write_atomically(path, lambda temporary: temporary.write_text(text, encoding="utf-8"))
    except FileError as error:
        raise ModelError(
            f"backend 'numba' cannot write its code cache: {error}; "
            "set LAGRANGIAN_CACHE to a writable folder"
        ) from None


# -- the folder ------------------------------------------------------------------------
def folder_problem(folder: Path) -> str | None:
    """Why ``folder`` cannot hold the cache, or None when it is this user's private folder
    and a file can be made in it."""
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        status = folder.lstat()
        problem = _foreign(status, regular=False)
        if problem is not None:
            return problem
        if stat.S_IMODE(status.st_mode) & 0o077:  # ours, from an older version: made private
            folder.chmod(0o700)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as error:
        return error.strerror or str(error)
    return None


def _foreign(status: os.stat_result, *, regular: bool) -> str | None:
    """Why a cache folder (or file) of this ``status`` is not to be trusted, or None."""
    kind = "file" if regular else "folder"
    expected = stat.S_ISREG(status.st_mode) if regular else stat.S_ISDIR(status.st_mode)
    if not expected:
        return f"it is not a {kind}"
    owner = os.getuid() if hasattr(os, "getuid") else None
    if owner is not None and status.st_uid != owner:
        return f"it is owned by another user (uid {status.st_uid})"
    if status.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        return f"others may write to it (mode {stat.S_IMODE(status.st_mode):04o})"
    return None


def _temporary_folder(configured: Path, problem: str) -> Path:
    folder = Path(tempfile.mkdtemp(prefix="lagrangian-cache-"))  # private: mode 0o700
    atexit.register(shutil.rmtree, folder, ignore_errors=True)
    warnings.warn(
        CacheWarning(
            f"the code cache {configured} cannot be used ({problem.lower()}); compiled code "
            "goes to a temporary folder for this run (set LAGRANGIAN_CACHE to a writable folder)"
        ),
        stacklevel=2,
    )
    return folder


# -- numba's files beside a module -----------------------------------------------------
def _numba_files(path: Path) -> list[Path]:
    return sorted((path.parent / "__pycache__").glob(f"{path.stem}.*.nb[ic]"))


def _trusted(files: list[Path]) -> bool:
    """Whether numba's folder and ``files`` are this user's and no one else may write them."""
    try:
        statuses = [(path.parent.lstat(), False) for path in files[:1]]
        statuses += [(path.lstat(), True) for path in files]
    except OSError:
        return False
    return all(_foreign(status, regular=regular) is None for status, regular in statuses)


def _manifest(path: Path) -> Path:
    return path.with_name(f"{path.stem}.numba-sha256")


def _listing(files: list[Path]) -> str:
    return "".join(f"{hashlib.sha256(f.read_bytes()).hexdigest()}  {f.name}\n" for f in files)


def _check_numba_files(path: Path) -> None:
    """Delete numba's files of ``path`` unless the list of the last exit vouches for them."""
    files = _numba_files(path)
    if not files:
        return
    try:
        listing = trusted_bytes(_manifest(path))
        if _trusted(files) and listing is not None and listing.decode() == _listing(files):
            return
    except (OSError, UnicodeDecodeError):
        pass
    _forget_numba_files(path)


def _forget_numba_files(path: Path) -> None:
    for file in (*_numba_files(path), _manifest(path)):
        with contextlib.suppress(OSError):
            file.unlink()


@atexit.register
def _list_numba_files() -> None:
    """At exit: the sha256 of numba's files of every module this process used."""
    for path in sorted(_LOADED):
        vouch_for_numba_files(path)


def vouch_for_numba_files(module_file: str | os.PathLike) -> None:
    """List the sha256 of numba's files of a module this process loaded from the cache.

    Called at exit and as soon as numba has saved machine code (see
    :mod:`~lagrangian.codegen.numba_cache`): another process that starts meanwhile (a
    second worker, a subprocess, a command run beside a long session) finds the files
    vouched for and loads them, where a listing made only at exit would have it delete
    and compile them again.  numba writes each file whole (a temporary file, then a
    rename), so a listing made after a save vouches for complete files."""
    path = Path(module_file)
    if path not in _LOADED:
        return  # not a module of the cache, or not this process's
    with contextlib.suppress(OSError, FileError):
        files = _numba_files(path)
        listing = _listing(files) if files else ""
        manifest = _manifest(path)
        if not files or (manifest.exists() and manifest.read_text() == listing):
            return
        write_atomically(manifest, lambda target: target.write_text(listing))

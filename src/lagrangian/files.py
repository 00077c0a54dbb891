"""Files in and out: atomic writes, and one-line errors for paths that cannot be used.

Every stage that writes a file (trajectories, ensembles, figures, animations,
the generated code of the numba backend) goes through :func:`write_atomically`:
the content is written to a temporary file in the target's own folder (a
rename across file systems would be a copy), flushed to the disk (``fsync``),
then renamed over the target (``os.replace``, atomic on POSIX and Windows).
A reader sees the old file or the complete new one, never half of one: when
the writer raises, or SIGTERM / SIGHUP arrive during the write, the temporary
file is removed and the target is untouched.

Paths the user gives are checked where they are used, and every problem is a
:class:`~lagrangian.errors.FileError` naming the file: a missing folder, a
folder that cannot be written, a name too long, a full disk, a target that is a
folder; on the reading side a missing, empty, or too large file, or a folder.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import signal
import stat
import threading
from collections.abc import Callable, Iterator
from pathlib import Path

from .errors import FileError

#: Signals that end a run from outside (``kill``, a closed terminal): the
#: temporary file of a write in progress is removed before the process ends.
TERMINATING_SIGNALS = tuple(
    getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name)
)

#: The reasons given for the errno values a user can cause with an output path.
_WRITE_REASONS = {
    errno.ENOENT: "the folder {folder} does not exist",
    errno.ENOTDIR: "{folder} is not a folder",
    errno.EACCES: "permission denied: the folder {folder} is not writable",
    errno.EPERM: "permission denied: the folder {folder} is not writable",
    errno.EROFS: "the folder {folder} is on a read-only file system",
    errno.ENAMETOOLONG: "the file name is too long",
    errno.ENOSPC: "no space left on the device; nothing was written",
    errno.EDQUOT: "the disk quota is exceeded; nothing was written",
    errno.EISDIR: "it is a folder, not a file",
    errno.EEXIST: "it is a file, not a folder",
}


def write_atomically(path: str | os.PathLike, write: Callable[[Path], object]) -> Path:
    """Run ``write(temporary)`` on a new file beside ``path``, then rename it to ``path``.

    ``write`` gets the path of an empty file it may open and overwrite.  An
    existing target keeps its permission bits; a new one gets those of a plain
    ``open`` (0o666 less the umask).  A symbolic link is written through (the
    file it points to is replaced).  Errors of the path are a
    :class:`FileError`; whatever ``write`` raises passes through, the target
    untouched and no temporary file left.
    """
    target = check_output_path(path)
    with _removed_on_termination() as pending:
        temporary = _new_temporary(target, pending)
        try:
            write(temporary)
            _keep_permissions(target, temporary)
            with open(temporary, "rb+") as stream:
                os.fsync(stream.fileno())
            _refuse_special(target)  # again: it may have appeared during the write
            os.replace(temporary, target)
        except BaseException as error:
            temporary.unlink(missing_ok=True)
            if _about(error, temporary, target):
                raise output_error(target, error) from None
            raise
        finally:
            pending.clear()
    _sync_folder(target.parent)
    return target


def write_csv(path: str | os.PathLike, table, columns: tuple[str, ...] | list[str]) -> Path:
    """The rows of ``table`` (a 2-D NumPy array) as CSV under the header ``columns``, in
    full float precision (``%.17g``: read back bit for bit), atomically."""
    import numpy as np

    def write(target: Path) -> None:
        with open(target, "w", newline="", encoding="utf-8") as stream:
            np.savetxt(
                stream, table, fmt="%.17g", delimiter=",", header=",".join(columns), comments=""
            )

    return write_atomically(path, write)


def check_output_path(path: str | os.PathLike) -> Path:
    """The path a file will be written to (links resolved), or a FileError saying why not.

    Cheap checks only (the folder exists and is one, the target is not a
    folder, nor a device, FIFO or socket, which the rename would replace):
    the write itself finds the rest (permissions, space).  Call it before long
    work, so that a typo in ``--out`` fails at once.
    """
    target = Path(path)
    try:
        if target.is_symlink():
            target = Path(os.path.realpath(target))
        folder = target.parent
        if target.is_dir():
            raise OSError(errno.EISDIR, os.strerror(errno.EISDIR))
        _refuse_special(target)
        if not folder.is_dir():
            code = errno.ENOTDIR if _exists_as_file(folder) else errno.ENOENT
            raise OSError(code, os.strerror(code))
        os.stat(folder)  # ENAMETOOLONG, ELOOP of the folder part
    except OSError as error:
        raise output_error(target, error) from None
    if len(os.fsencode(target.name)) > _name_max(target.parent):
        raise output_error(target, OSError(errno.ENAMETOOLONG, "File name too long"))
    return target


def output_error(path: str | os.PathLike, error: OSError) -> FileError:
    """The one-line FileError of an OSError met while writing ``path``."""
    folder = Path(path).parent
    reason = _WRITE_REASONS.get(error.errno)
    if reason is None:
        reason = error.strerror or str(error)
    return FileError(path, "cannot write: " + reason.format(folder=_shown(folder)))


def check_input_file(path: str | os.PathLike, *, what: str, max_bytes: int) -> int:
    """The size of the regular file ``path`` holding ``what``, or a FileError saying why not.

    Refuses a missing file, a folder, an empty file and a file above
    ``max_bytes`` (reading it would take the machine's memory).
    """
    try:
        status = os.stat(path)
    except OSError as error:
        if error.errno == errno.ENOENT:
            raise FileError(path, "no such file") from None
        raise FileError(path, f"cannot read: {error.strerror or error}") from None
    if stat.S_ISDIR(status.st_mode):
        raise FileError(path, f"is a folder, not {what}")
    if not stat.S_ISREG(status.st_mode):
        raise FileError(path, f"is not a regular file, not {what}")
    if status.st_size == 0:
        raise FileError(path, f"is empty, not {what}")
    if status.st_size > max_bytes:
        raise FileError(
            path,
            f"is too large to be read ({status.st_size / 2**20:.0f} MiB; "
            f"{what} is read up to {max_bytes / 2**20:.0f} MiB)",
        )
    return status.st_size


# -- the parts of a write ----------------------------------------------------------------
#: What a path that exists but is no regular file is, by its ``stat`` mode.
_SPECIAL_KINDS = (
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISSOCK, "a socket"),
)


def _refuse_special(target: Path) -> None:
    """A FileError when ``target`` exists and is a device, FIFO or socket.

    The rename of an atomic write would unlink such a node and put a file in
    its place (``--out /dev/null`` would replace the null device when run as
    root), so it is never written to.
    """
    try:
        mode = os.stat(target).st_mode
    except OSError:
        return  # absent (or unreadable: the write says why)
    for is_kind, kind in _SPECIAL_KINDS:
        if is_kind(mode):
            raise FileError(
                target, f"cannot write: it is {kind}, not a regular file; give a file path"
            )
    if not stat.S_ISREG(mode) and not stat.S_ISDIR(mode):
        raise FileError(target, "cannot write: it is not a regular file; give a file path")


def _new_temporary(target: Path, pending: list[Path]) -> Path:
    """A new empty file beside ``target``: ``.<name>.<random>.tmp``, mode 0o666 & ~umask.

    Its name goes into ``pending`` before it exists, so that a signal arriving
    right after the create still finds it to remove.
    """
    stem = target.name[:80]  # the random part must fit in NAME_MAX with a long target name
    while True:
        temporary = target.parent / f".{stem}.{secrets.token_hex(6)}.tmp"
        pending[:] = [temporary]
        try:  # O_EXCL: never reuse a file; 0o666 & ~umask: the permissions of a plain open
            os.close(os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            return temporary
        except FileExistsError:  # pragma: no cover - 48 random bits collided
            continue
        except OSError as error:
            raise output_error(target, error) from None


def _keep_permissions(target: Path, temporary: Path) -> None:
    """An existing target's permission bits on the new file (a user's chmod survives)."""
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except FileNotFoundError:
        return
    os.chmod(temporary, mode)


def _sync_folder(folder: Path) -> None:
    """Flush the folder's entry of the rename (POSIX); best effort, the file is complete."""
    with contextlib.suppress(OSError, AttributeError):
        descriptor = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(descriptor)
        finally:
            os.close(descriptor)


class _Terminated(BaseException):
    """SIGTERM or SIGHUP arrived during a write (not an Exception: nothing may catch it)."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


@contextlib.contextmanager
def _removed_on_termination() -> Iterator[list[Path]]:
    """While inside, SIGTERM / SIGHUP unwind the write (removing the temporary file in
    ``pending``), then end the process as the signal would have.

    Handlers are installed only in the main thread (Python allows no other) and
    only for signals not ignored (``nohup``), and the previous ones come back on
    the way out.
    """
    pending: list[Path] = []
    previous: dict[int, object] = {}

    def handler(signum, frame):
        raise _Terminated(signum)

    if threading.current_thread() is threading.main_thread():
        for signum in TERMINATING_SIGNALS:
            if signal.getsignal(signum) is not signal.SIG_IGN:
                previous[signum] = signal.signal(signum, handler)
    try:
        yield pending
    except _Terminated as terminated:
        for temporary in pending:  # a signal between the create and the try
            temporary.unlink(missing_ok=True)
        _restore(previous)
        _deliver(terminated.signum, previous.get(terminated.signum))
        raise SystemExit(128 + terminated.signum) from None  # a Python handler returned
    finally:
        _restore(previous)


def _restore(previous: dict[int, object]) -> None:
    for signum, handler in previous.items():
        signal.signal(signum, handler)
    previous.clear()


def _deliver(signum: int, handler: object) -> None:
    """End the process as ``signum`` would have without us: the default action kills
    it (status 128 + signum to a shell), a Python handler is called."""
    if callable(handler):
        handler(signum, None)
    else:
        signal.raise_signal(signum)


# -- small helpers -----------------------------------------------------------------------
def _about(error: BaseException, temporary: Path, target: Path) -> bool:
    """An OSError of the file being written (not of some other file the writer opened)."""
    if not isinstance(error, OSError) or error.errno not in _WRITE_REASONS:
        return False
    return error.filename is None or str(error.filename) in (str(temporary), str(target))


def _exists_as_file(folder: Path) -> bool:
    """Some part of ``folder`` is a file (ENOTDIR), rather than missing (ENOENT)."""
    for part in (folder, *folder.parents):
        with contextlib.suppress(OSError):
            if part.exists():
                return not part.is_dir()
    return False


def _name_max(folder: Path) -> int:
    try:
        return os.pathconf(folder, "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        return 255


def _shown(folder: Path) -> str:
    return str(folder) if str(folder) else "."

"""Errors with one-line messages that say what is wrong and where.

Every error a user can cause derives from :class:`LagrangianError`; the CLI
prints ``str(error)`` on one line and exits with status 2.  Anything else that
escapes is a bug in the toolkit (exit status 1).  The kinds are also the
built-in exceptions a Python caller expects: a :class:`ModelError` (bad
values, a model that cannot be built) is a ``ValueError``, a
:class:`MissingDependencyError` (an optional package not installed) an
``ImportError``; file problems are :class:`FileError`.
"""

from __future__ import annotations

import re
from collections.abc import Mapping

#: How the library names its settings in a message (:func:`setting`): the Python
#: keyword arguments.  The command line spells the same settings as its flags
#: (``lagrangian.cli.FLAGS``), by :meth:`Spelled.spelled`.
PYTHON_SPELLING: Mapping[str, str] = {
    "t_end": "t_end",
    "dt": "dt",
    "rtol": "rtol",
    "atol": "atol",
    "timeout": "timeout",
    "backend": "backend",
    "params": "params",
    "params=": "params={NAME: VALUE}",
    "definitions=": "definitions={NAME: EXPR}",
    "grid": "grid axis",
    "at": "at",
    "at=": "at={NAME: VALUE}",
    "language": "language",
    "path": "path",
    "n_out": "n_out",
    "dt_out": "dt_out",
    "save_every": "save_every",
    "vary": "vary",
    "samples": "samples",
    "transient": "transient",
    "allow_remote": "allow_remote=True",
    "allow_host": "allowed_hosts",
    "count": "count",
    "interval": "interval",
    "strobe": "strobe",
    "observe=": "observe={NAME: EXPR}",
}
_SETTING = re.compile(r"\u27e6([a-z_=]+)\u27e7")
_CHOICES = re.compile(r"\u27ea([^\u27eb]*)\u27eb")
_CHOICE_SEPARATOR = "\u2016"


def setting(name: str) -> str:
    """A setting named in a message (a key of :data:`PYTHON_SPELLING`): ``dt`` when
    the message is read in Python, ``--dt`` when the command line prints it."""
    return f"\u27e6{name}\u27e7"


def choices(*remedies: str) -> str:
    """Remedies offered in a message, as a list ("a shorter t_end, a looser rtol or a
    larger dt"); a remedy that names a :func:`setting` the reader has no way to give (a
    command without that option: not in its spelling) is left out of it."""
    return f"\u27ea{_CHOICE_SEPARATOR.join(remedies)}\u27eb"


def spelled(text: str, spelling: Mapping[str, str]) -> str:
    """``text`` with every :func:`setting` written as ``spelling`` says (Python's
    keyword where ``spelling`` has no entry), and every list of :func:`choices` without
    the remedies whose settings ``spelling`` does not have."""

    def offered(found: re.Match) -> str:
        remedies = [
            remedy
            for remedy in found[1].split(_CHOICE_SEPARATOR)
            if all(name in spelling for name in _SETTING.findall(remedy))
        ]
        if len(remedies) < 2:
            return "".join(remedies)
        return f"{', '.join(remedies[:-1])} or {remedies[-1]}"

    return _SETTING.sub(
        lambda found: spelling.get(found[1], PYTHON_SPELLING.get(found[1], found[1])),
        _CHOICES.sub(offered, text),
    )


class Spelled:
    """A message that names settings: ``str()`` spells them as Python does,
    :meth:`spelled` as the caller says (the CLI: as its flags)."""

    def __str__(self) -> str:
        return spelled(super().__str__(), PYTHON_SPELLING)

    def spelled(self, spelling: Mapping[str, str]) -> str:
        return spelled(super().__str__(), spelling)


class LagrangianError(Spelled, Exception):
    """Base of every error caused by the user's input."""


class ParseError(LagrangianError):
    """Text that is not a valid expression.

    ``position`` is the 0-based character offset in ``text`` where the problem
    was found (``None`` when it concerns the whole text, e.g. its length).
    """

    def __init__(self, message: str, text: str = "", position: int | None = None):
        self.message = message
        self.text = text
        self.position = position
        super().__init__(self._render())

    def _render(self) -> str:
        if self.position is None:
            return self.message
        return f"{self.message} at position {self.position + 1}"


class UnknownNameError(ParseError):
    """An identifier that is neither declared nor built in (``suggestion``: the likely one)."""

    def __init__(
        self,
        name: str,
        text: str = "",
        position: int | None = None,
        suggestion: str | None = None,
    ):
        self.name = name
        self.suggestion = suggestion
        hint = f" (did you mean '{suggestion}'?)" if suggestion else ""
        super().__init__(f"unknown symbol '{name}'{hint}", text, position)


class ModelError(LagrangianError, ValueError):
    """A model that cannot be built: names the file, the field and the offending text."""

    def __init__(
        self,
        message: str,
        *,
        source: str | None = None,
        field: str | None = None,
        text: str | None = None,
    ):
        self.message = message
        self.source = source
        self.field = field
        self.text = text
        super().__init__(self._render())

    def _render(self) -> str:
        where = ": ".join(_shortened(part) for part in (self.source, self.field) if part)
        quoted = ""
        if self.text is not None:
            shown = self.text if len(self.text) <= 60 else self.text[:57] + "..."
            quoted = f" in '{_visible(shown)}'"
        prefix = f"{where}: " if where else ""
        message = self.message  # may quote a value of the user's: a line, not a page
        if len(message) > 300:
            message = message[:297] + "..."
        return _single_line(f"{prefix}{_visible(message)}{quoted}")

    def located(self, *, source: str | None = None, field: str | None = None) -> ModelError:
        """The same error with the file (and field, if not yet known) filled in."""
        return ModelError(
            self.message,
            source=self.source or source,
            field=self.field or field,
            text=self.text,
        )


class FileError(LagrangianError):
    """A file that cannot be read or written: names the file and what is wrong with it."""

    def __init__(self, path: object, message: str):
        self.path = str(path)
        self.message = message
        super().__init__(_single_line(f"{_visible(_shortened(self.path))}: {message}"))


class MissingDependencyError(LagrangianError, ImportError):
    """An optional package a feature needs is not installed: names the extra that brings it.

    ``feature`` says what needs it (``"method 'taylor'"``), ``package`` what is
    missing (``"heyoka"``), ``extra`` the optional dependency group of
    lagrangian that installs it (``"taylor"``), if there is one.
    """

    def __init__(self, feature: str, package: str, extra: str | None = None):
        self.feature = feature
        self.package = package
        self.extra = extra
        how = (
            f'pip install ".[{extra}]" in a clone of lagrangian'
            if extra
            else f"pip install {package}"
        )
        super().__init__(f"{feature} needs {package}: {how}")


class LagrangianWarning(Spelled, UserWarning):
    """Base of the toolkit's own warnings: the CLI prints each as one line
    (``lagrangian: warning: ...``); warnings of other libraries it keeps quiet."""


class LikelyTypoWarning(LagrangianWarning):
    """A parameter whose name looks like a slip for a coordinate or velocity (``xdot``)."""


class CacheWarning(LagrangianWarning):
    """The code cache could not be used as configured (a temporary one was used)."""


class SingularMassMatrixError(LagrangianError):
    """The equations cannot be solved for the accelerations."""

    @classmethod
    def at_state(
        cls, t: float | None, names=(), values=(), *, constrained: bool = False
    ) -> SingularMassMatrixError:
        """M is singular at this state of a run (``t`` None: somewhere in a batch)."""
        what = "the mass matrix with the constraints" if constrained else "the mass matrix"
        if t is None:
            where = "at one of the states of the batch"
        else:
            shown = ", ".join(f"{n} = {v:.6g}" for n, v in zip(names, values, strict=True))
            where = f"at t = {t:.6g} ({shown})"
        return cls(
            f"{what} is singular {where}: the coordinates are degenerate there "
            "(an angle at a pole, a collision); start the motion away from that state"
        )


def _visible(text: str) -> str:
    """The text as typed (LaTeX backslashes intact), control characters escaped."""
    return "".join(ch if ch.isprintable() else ascii(ch)[1:-1] for ch in text)


def _shortened(name: str) -> str:
    """A path or name of any length as at most 120 characters: its start and its end."""
    return name if len(name) <= 120 else name[:58] + "..." + name[-59:]


def _single_line(message: str) -> str:
    return " ".join(message.split())

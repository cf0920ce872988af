"""Exceptions raised by ddgsa.

Every error a user can cause subclasses :class:`DdgsaError` *and* the built-in
exception that best describes it, so ``except ValueError`` keeps working.
Messages name the thing, the offending value and what is allowed.
"""

from __future__ import annotations

import difflib
import reprlib
from collections.abc import Iterable


class DdgsaError(Exception):
    """Base class of all ddgsa errors."""


class SpaceError(DdgsaError, ValueError):
    """An invalid parameter or parameter-space definition."""


class MethodError(DdgsaError, ValueError):
    """An unknown GSA method or an invalid option of one."""


class ModelError(DdgsaError, ValueError):
    """An unknown model, fidelity, parameter or output name."""


class SceneError(DdgsaError, ValueError):
    """An invalid scene (wind speed, turbulence, duration, time step...)."""


class StudyError(DdgsaError, ValueError):
    """An invalid study file; the message names the file and the field."""


class OutputFolderError(DdgsaError, ValueError):
    """An output folder that holds another study's results or files ddgsa did not write."""


class FolderBusyError(DdgsaError, RuntimeError):
    """An output folder that another live ddgsa process is writing to."""


class StoreCorruptError(OutputFolderError):
    """An evaluation store SQLite cannot read; the message names the file and the way out (``--force``)."""


class StoreLostError(DdgsaError, RuntimeError):
    """The evaluation store or the folder's lock was deleted or replaced while a run held it."""


class SchedulerLostError(DdgsaError, RuntimeError):
    """The Dask scheduler a run used stopped answering."""


class StoreWriteError(DdgsaError, RuntimeError):
    """The evaluation store cannot be written (disk full, read-only folder, I/O error)."""


class WorkingFolderError(DdgsaError, FileNotFoundError):
    """The process's working folder no longer exists, so relative paths cannot be resolved."""


MESSAGE_INPUT_CHARS = 200
"""At most this many characters of a user's input are echoed in one error message."""
_BOUNDED = reprlib.Repr()
"""A repr of nested data that stops after a few levels and items (an alias bomb's repr is exponential)."""
_BOUNDED.maxlevel, _BOUNDED.maxlist, _BOUNDED.maxdict, _BOUNDED.maxstring, _BOUNDED.maxother = 2, 4, 4, 60, 60


def clip(value: object, limit: int = MESSAGE_INPUT_CHARS) -> str:
    """``repr(value)`` cut to ``limit`` characters (a hostile input never floods a message).

    Examples
    --------
    >>> clip("x" * 1000, 12)
    "'xxxxxxxx... (1002 characters)"
    """
    text = repr(value) if isinstance(value, (str, bytes, int, float)) else _BOUNDED.repr(value)
    return text if len(text) <= limit else f"{text[:limit - 3]}... ({len(text)} characters)"


LIST_AT_MOST = 12
"""Known names listed in full in an unknown-name message; longer lists give only close matches."""


def did_you_mean(name: object, known: Iterable[str]) -> str:
    """``"did you mean 'a' or 'b'?"`` for the close matches of ``name`` among ``known`` (difflib,
    at most three), empty when none is close: the one spelling hint of every message.

    Examples
    --------
    >>> did_you_mean("mdmr", ["mdrm", "pce", "saltelli"]), did_you_mean("xyz", ["mdrm"])
    ("did you mean 'mdrm'?", '')
    """
    text = str(name)
    close = difflib.get_close_matches(text, sorted(known), n=3, cutoff=0.5) if len(text) <= 200 else []
    return f"did you mean {' or '.join(repr(c) for c in close)}?" if close else ""


def with_hint(message: str, name: object, known: Iterable[str]) -> str:
    """``message`` followed by ``"; did you mean ...?"`` where :func:`did_you_mean` finds one."""
    hint = did_you_mean(name, known)
    return f"{message}; {hint}" if hint else message


def unknown_name_message(kind: str, name: object, known: "list[str] | tuple[str, ...]", where: str = "") -> str:
    """Message for an unknown name: the close matches ("did you mean"), and the known names
    when there are at most :data:`LIST_AT_MOST` of them (or no close match).

    Parameters
    ----------
    kind : str
        What was looked up, e.g. ``"method"``.
    name : object
        The name that was given.
    known : sequence of str
        The names that exist.
    where : str
        Where the full list can be read (e.g. ``"ddgsa models"``), quoted for long lists.

    Examples
    --------
    >>> unknown_name_message("model", "drect", ["analytic", "direct_drive"])
    "unknown model 'drect'; known: analytic, direct_drive; did you mean 'direct_drive'?"
    """
    names = sorted(known)
    hint = did_you_mean(name, names)
    if len(names) <= LIST_AT_MOST or not hint:
        return f"unknown {kind} {clip(name)}; known: {', '.join(names)}" + (f"; {hint}" if hint else "")
    see = f"`{where}` lists all {len(names)}" if where else f"{len(names)} known"
    return f"unknown {kind} {clip(name)}; {hint} ({see})"

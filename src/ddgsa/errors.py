"""Exceptions raised by ddgsa.

Every error a user can cause subclasses :class:`DdgsaError` *and* the built-in
exception that best describes it, so ``except ValueError`` keeps working.
Messages name the thing, the offending value and what is allowed.
"""

from __future__ import annotations


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


def unknown_name_message(kind: str, name: object, known: "list[str] | tuple[str, ...]") -> str:
    """Message for an unknown name, listing the known ones.

    Parameters
    ----------
    kind : str
        What was looked up, e.g. ``"method"``.
    name : object
        The name that was given.
    known : sequence of str
        The names that exist.
    """
    return f"unknown {kind} {name!r}; known: {', '.join(sorted(known))}"

"""Aliasing guard (seed 003 §2.1.2 and §3.2): sampling intervals against natural frequencies.

A signal sampled every ``h`` seconds holds no information above the Nyquist frequency
``1 / (2 h)``; a mode above it folds onto a false lower frequency, and a sampled peak of a
mode with fewer than about ten samples per period is underestimated (by up to
``1 - cos(pi / n)``: 5 % at ``n`` = 10). Seed 003 found its results sensitive to the
aerodynamic and controller communication intervals once the generator's 34.5 Hz radial mode
was added, and had to go from 0.02 s to 0.007 s (controller) and 0.0001 s (aerodynamics).

Where it applies in ddgsa: model *outputs* sampled for peaks (``generator_radial``: refused
below 2, warned below 10 samples per period) and implicit *integration* steps against the
lowest natural frequency (``direct_drive``: warned below 2 steps per period -- the mode is then
damped numerically, not resolved; refining the step further changes its outputs by < 0.2 %,
measured, because the loads carry nothing above their own Nyquist frequency). The hub loads
are computed beforehand (one-way coupling) and enter as a C1 cubic between samples, so their
interval cannot alias a structural mode here; it bounds the excitation instead: modes above
``1 / (2 dt)`` respond only quasi-statically.
"""

from __future__ import annotations

import warnings

from ddgsa.errors import ModelError

NYQUIST = 2.0
"""Samples per period below which aliasing is certain (refused for outputs)."""
RESOLVED = 10.0
"""Samples per period below which peaks are under-resolved (warned)."""


class AliasingWarning(UserWarning):
    """A sampling or controller interval too coarse for a natural frequency of the model."""


def samples_per_period(interval_s: float, frequency_hz: float) -> float:
    """How many samples at ``interval_s`` [s] fall in one period of ``frequency_hz`` [Hz]."""
    return 1.0 / (interval_s * frequency_hz)


def check_interval(interval_s: float, frequency_hz: float, what: str, *, refuse: bool,
                   warn_below: float = RESOLVED, component: str = "mode", rate: bool = False) -> str | None:
    """Check that ``interval_s`` [s] resolves a mode at ``frequency_hz`` [Hz].

    Parameters
    ----------
    what : str
        What is sampled, for the message (e.g. ``"output interval"``).
    refuse : bool
        Raise below the Nyquist rate (outputs: an aliased output is wrong, not imprecise);
        otherwise warn.
    warn_below : float
        Samples per period below which to warn (default :data:`RESOLVED`).
    component : str
        What oscillates at ``frequency_hz``: ``"mode"`` (default), or e.g. ``"2x order"``.
    rate : bool
        Where the user sets a sampling rate (not an interval): the message gives the limit as a
        rate [Hz] and leaves the interval out (``what`` then names the rate).

    Returns
    -------
    str or None
        The warning issued (also sent as an :class:`AliasingWarning`), or None when resolved.

    Raises
    ------
    ModelError
        When ``refuse`` and fewer than 2 samples fall in a period.
    """
    n = samples_per_period(interval_s, frequency_hz)
    if n >= warn_below:
        return None
    if rate:
        msg = (f"{what} gives {n:.2g} samples per period of the {component} at {frequency_hz:.4g} Hz (more than "
               f"{NYQUIST * frequency_hz:.4g} Hz avoids aliasing; at least {RESOLVED * frequency_hz:.4g} Hz "
               f"resolves its peaks)")
    else:
        msg = (f"{what} {interval_s:.4g} s gives {n:.2g} samples per period of the {frequency_hz:.4g} Hz {component} "
               f"(Nyquist needs > {NYQUIST:g}, peaks need >= {RESOLVED:g}: at most "
               f"{1 / (RESOLVED * frequency_hz):.3g} s)")
    if n < NYQUIST and refuse:
        raise ModelError(f"{msg}; the sampled signal would alias")
    warnings.warn(msg, AliasingWarning, stacklevel=3)
    return msg


def sampling_row(what: str, interval_s: float, frequency_hz: float, mode: str, consequence: str) -> dict[str, object]:
    """One line of a model's sampling table: ``samples_per_period`` and a verdict
    (``ok`` >= 10, ``coarse`` >= 2, ``aliased`` below); ``consequence`` is the caller's text on what
    a coarse interval means for it (kept only when the verdict is not ``ok``)."""
    n = samples_per_period(interval_s, frequency_hz)
    verdict = "ok" if n >= RESOLVED else "coarse" if n >= NYQUIST else "aliased"
    return {"interval": what, "interval_s": float(interval_s), "mode": mode, "frequency_hz": float(frequency_hz),
            "samples_per_period": float(n), "verdict": verdict, "consequence": "" if verdict == "ok" else consequence}

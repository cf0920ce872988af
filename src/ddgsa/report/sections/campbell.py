"""Campbell diagram: ``campbell.csv`` (``ddgsa modes --campbell``), natural frequencies against rotor
speed with the 1P line, drawn by :meth:`ddgsa.mbs.campbell.CampbellDiagram.plot` (``campbell.png``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import pandas as pd

from ddgsa.mbs.campbell import CampbellDiagram
from ddgsa.report.sections.base import Chart, Folder, Section, table

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

COLUMNS = {"speed_rad_s", "speed_rpm", "mode", "frequency_hz", "damping_ratio", "whirl", "label"}


def plot_campbell(frame: pd.DataFrame) -> "Figure":
    """The diagram of a ``campbell.csv`` table (order line 1P)."""
    return CampbellDiagram(frame).plot().figure


def charts(folder: Folder) -> list[Chart]:
    cb = folder.csv("campbell.csv")
    if cb is None or not len(cb) or not COLUMNS <= set(cb.columns):
        return []
    return [Chart("campbell.png", "natural frequencies against rotor speed, forward whirl solid, backward dashed; "
                  "grey: the 1P excitation line", "campbell", lambda: plot_campbell(cb))]


def html(folder: Folder) -> str:
    found = charts(folder)
    if not found:
        return ""
    return folder.figure(found[0]) + table(folder.csv("campbell.csv"), "campbell_table", "campbell.csv")


SECTION = Section("campbell", "Campbell diagram", html, charts=charts, shows=("campbell.csv",))

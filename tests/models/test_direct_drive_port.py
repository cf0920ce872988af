"""The direct drive written on the kernel's parts reproduces the table committed before its port
(1e-6), and today's tables (1e-9): regression guards of the kernel's consolidation (issue 24), not
oracles. The port's tables hold the shaft basis it was made on (``PORT_BASIS``: Euler-Bernoulli, two
modes per plane); today's mode table holds the default basis (Timoshenko, five modes, issue 26)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ddgsa import models
from model_regression import DIRECT_MODES_TODAY, DIRECT_TODAY
from port_regression import PORT_BASIS, TABLE, objectives


def test_objectives_unchanged_by_the_port() -> None:
    """Every objective of 3 fidelities x 3 scenes x 3 points within 1e-6 relative of the pre-port table."""
    before = pd.read_csv(TABLE)
    after = objectives()
    assert list(after.columns) == list(before.columns) and len(after) == len(before) == 27
    outputs = before.columns[3:]
    np.testing.assert_allclose(after[outputs].to_numpy(float), before[outputs].to_numpy(float), rtol=1e-6, atol=0)
    today = pd.read_csv(DIRECT_TODAY)
    np.testing.assert_allclose(after[outputs].to_numpy(float), today[outputs].to_numpy(float), rtol=1e-9, atol=0)


def test_modes_unchanged_by_the_port() -> None:
    before = pd.read_csv(TABLE.parent / "direct_drive_modes.csv")
    today = pd.read_csv(DIRECT_MODES_TODAY)
    for fidelity, table in before.groupby("fidelity"):
        port = models.get("direct_drive", fidelity=fidelity, **PORT_BASIS).modes()
        np.testing.assert_allclose(port["frequency_hz"], table["frequency_hz"], rtol=1e-6)
        np.testing.assert_allclose(port["damping_ratio"], table["damping_ratio"], rtol=1e-6, atol=1e-9)
        assert list(port["label"]) == list(table["label"])
        now = models.get("direct_drive", fidelity=fidelity, shaft="table2").modes()   # the table's shaft
        held = today[today["fidelity"] == fidelity]
        np.testing.assert_allclose(now["frequency_hz"], held["frequency_hz"], rtol=1e-9)
        np.testing.assert_allclose(now["damping_ratio"], held["damping_ratio"], rtol=1e-9, atol=1e-12)
        assert list(now["label"]) == list(held["label"])

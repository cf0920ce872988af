"""A study's signals and convergence curves through the CLI into the report, against closed forms."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ddgsa.cli import main
from ddgsa.models.analytic import WAVES_T
from studytext import ishigami_study


def signal_study(name: str, signal: str) -> str:
    """A one-scene Ishigami study asking for ``signal`` with a first-order PCE."""
    return ishigami_study(name, f"signals: [{signal}]\nmethods: [{{method: pce, order: 1, n: 128}}]\n"
                                "run: {jobs: 1, batch_size: 64}\n")


def test_signal_study_per_bin_generalised_and_convergence_into_the_report(write_study, tmp_path: Path) -> None:
    """waves(t) = (12 + x1 sin 4 pi t + 2 x2 sin 10 pi t) 8/11: additive, so an order-1 PCE is exact:
    S1[x1](t) = s1^2 / (s1^2 + 4 s2^2), generalised S1[x1] = sum s1^2 / sum (s1^2 + 4 s2^2)."""
    path = write_study("sig", text=signal_study(name="sig", signal="waves"))
    out = tmp_path / "out"
    assert main(["-q", "run", str(path), "--out", str(out), "--allow-untrusted"]) == 0
    s1, s2 = np.sin(4 * np.pi * WAVES_T) ** 2, 4 * np.sin(10 * np.pi * WAVES_T) ** 2
    bins = pd.read_csv(out / "signal_indices.csv")
    pce = bins[(bins["method"] == "pce") & (bins["parameter"] == "x1")].sort_values("bin")
    live = s1 + s2 > 1e-9
    np.testing.assert_allclose(pce["axis"], WAVES_T, atol=1e-12)
    np.testing.assert_allclose(pce["S1"].to_numpy()[live], s1[live] / (s1 + s2)[live], atol=1e-5)   # CSV: 6 digits
    var_x = np.pi ** 2 / 3 * (8 / 11) ** 2                                       # Var x for x ~ U(-pi, pi)
    np.testing.assert_allclose(pce["variance"].to_numpy()[live], (var_x * (s1 + s2))[live], rtol=1e-5)
    gen = pd.read_csv(out / "signal_generalised.csv").set_index(["method", "parameter"])
    assert gen.loc[("pce", "x1"), "S1"] == pytest.approx(s1.sum() / (s1 + s2).sum(), abs=1e-5)
    assert gen.loc[("pce", "x3"), "ST"] == pytest.approx(0.0, abs=1e-5)
    # convergence: the regression PCE's Sobol' sample nests (32, 64, 128 points); the curve ends at the study's index
    conv = pd.read_csv(out / "convergence.csv")
    idx = pd.read_csv(out / "indices.csv")
    own = idx[idx["method"] == "pce"].set_index("parameter")["ST"]
    last = conv[conv["n_evals"] == conv["n_evals"].max()].set_index("parameter")["ST"]
    assert sorted(conv["n_evals"].unique()) == [32, 64, 128]
    np.testing.assert_allclose(last[own.index], own, rtol=1e-5)
    html = (out / "report.html").read_text()
    assert "Indices of signals" in html and "Indices against sample size" in html
    assert "waves: ST per bin (pce)" in html and "y_positive: ST against runs (pce)" in html


@pytest.mark.slow
def test_a_report_rebuilt_from_the_store_reads_the_signals_back(write_study, tmp_path: Path) -> None:
    """``ddgsa report`` runs no model: the signal vectors come back from the store's signals table."""
    path = write_study("sig", text=signal_study(name="sig", signal="waves"))
    out = tmp_path / "out"
    assert main(["-q", "run", str(path), "--out", str(out), "--allow-untrusted"]) == 0
    first = (out / "signal_indices.csv").read_text()
    (out / "signal_indices.csv").unlink()
    assert main(["-q", "report", str(out), "--allow-untrusted"]) == 0
    assert (out / "signal_indices.csv").read_text() == first


def test_an_unknown_signal_is_refused_with_the_known_ones(write_study, capsys) -> None:
    path = write_study("bad", text=signal_study(name="bad", signal="wave"))
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "signals[0]" in err and "waves" in err

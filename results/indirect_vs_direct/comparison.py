"""Main-bearing damage of the geared drive against the direct drive's front bearing, same scenes.

Reads the two sweep summaries (``ddgsa run studies/indirect_vs_direct.yaml`` and
``ddgsa run studies/paper_d_direct_drive.yaml`` into ``results/``) and writes ``comparison.csv``
and ``comparison.png`` beside this file. Run from the repository root:
``python results/indirect_vs_direct/comparison.py``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pandas as pd  # noqa: E402

HERE = Path(__file__).resolve().parent
RESULTS = HERE.parent


def main() -> None:
    ind = pd.read_csv(HERE / "sweep_summary.csv")
    dd = pd.read_csv(RESULTS / "paper_d_direct_drive" / "sweep_summary.csv")
    keep = ["wind_speed", "turbulence_intensity"]
    m = ind[keep + ["damage_main_mean", "main_Fr_mean_mean", "main_Fa_mean_mean"]].merge(
        dd[keep + ["damage_front_mean", "front_Fr_mean_mean", "front_Fa_mean_mean"]], on=keep)
    m["damage_ratio_indirect_to_direct"] = m["damage_main_mean"] / m["damage_front_mean"]
    m.to_csv(HERE / "comparison.csv", index=False, float_format="%.5g")
    fig, ax = plt.subplots(figsize=(7.0, 4.3))
    for k, (ti, grp) in enumerate(m.groupby("turbulence_intensity")):
        colour = f"C{k}"
        ax.plot(grp["wind_speed"], grp["damage_main_mean"], "o-", color=colour, label=f"indirect, main, I_ref {ti:g}")
        ax.plot(grp["wind_speed"], grp["damage_front_mean"], "s--", color=colour, label=f"direct, front, I_ref {ti:g}")
    ax.set_yscale("log")
    ax.set_xlabel("mean wind speed [m/s]")
    ax.set_ylabel("main-bearing damage rate [1/s]")
    ax.set_title("Main-bearing damage: indirect vs direct drive (3 realisations of 600 s, linear)", fontsize=10)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(HERE / "comparison.png", dpi=120, bbox_inches="tight")


if __name__ == "__main__":
    main()

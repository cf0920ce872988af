"""Labelled arrays: ``StudyResult.to_xarray()`` against the closed-form indices of the study's function,
round trips through NetCDF and Zarr, ``ddgsa export`` of a folder against the in-memory dataset, and
the results objects' HTML in Jupyter."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from ddgsa.cli import main
from ddgsa.execute.pipeline import execute
from ddgsa.report.write import write_report
from ddgsa.runner import EvaluationStore
from ddgsa.study.spec import load_study

xr = pytest.importorskip("xarray")

STUDY = """\
name: labelled
model: {name: analytic, fidelity: exact}
parameters:
  x1: {low: -3.14159265, high: 3.14159265}
  x2: {low: -3.14159265, high: 3.14159265}
  x3: {low: -3.14159265, high: 3.14159265}
scenes: {wind_speed: [8.0, 11.0], turbulence_intensity: 0.0, duration: 1.0, dt: 0.05}
outputs: [y_positive]
methods: [{method: pce, order: 10, n: 1024, seed: 0}, {method: mdrm, points: 5}]
"""
# y_positive = 12 + (8/11) Ishigami(a=7, b=0.1): closed-form indices (tests/study/test_report.py)
ST_EXACT = {"x1": 0.558, "x2": 0.442, "x3": 0.244}
S1_EXACT = {"x1": 0.314, "x2": 0.442, "x3": 0.0}


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[object, Path]:
    tmp = tmp_path_factory.mktemp("labelled")
    path = tmp / "labelled.yaml"
    path.write_text(STUDY)
    study = load_study(path)
    result = execute(study, EvaluationStore(tmp / "out" / "evaluations.sqlite"), jobs=1, quiet=True)
    write_report(result, tmp / "out")
    return result, tmp / "out"


def test_to_xarray_holds_the_closed_form_indices_with_labels_and_units(run: tuple[object, Path]) -> None:
    result, _ = run
    ds = result.to_xarray()
    # the study's two methods and the zero-cost cross-checks beside them: the pooled PCE
    # (ddgsa.gsa.pooled) and the given-data S1 (ddgsa.gsa.givendata)
    assert dict(ds["ST"].sizes) == {"scene": 2, "output": 1, "parameter": 3, "method": 4}
    assert set(ds["method"].values) == {"pce", "mdrm", "pooled_pce", "given_data_s1"}
    assert list(ds["wind_speed"].values) == [8.0, 11.0] and ds["wind_speed"].dims == ("scene",)
    pce = ds.sel({"output": "y_positive", "method": "pce"})     # sel(method=...) is xarray's fill method
    for p in ST_EXACT:     # PCE of order 10 on 1024 points: within 0.01 of the closed forms, both scenes
        assert np.allclose(pce["ST"].sel(parameter=p), ST_EXACT[p], atol=0.01)
        assert np.allclose(pce["S1"].sel(parameter=p), S1_EXACT[p], atol=0.01)
    assert (pce["trusted"] == 1).all()
    given = ds.sel({"output": "y_positive", "method": "given_data_s1"})   # binned on the PCE's Sobol' points
    for p in ST_EXACT:
        assert (abs(given["S1"].sel(parameter=p) - S1_EXACT[p]) <= given["S1_conf"].sel(parameter=p)).all()
    assert (ds["trusted"].sel({"method": "mdrm"}) == 0).all()     # M-DRM misses Ishigami's interaction: untrusted
    assert ds["ST"].attrs["units"] == "1" and ds["output_unit"].sel(output="y_positive").item() == "-"
    assert ds["trusted"].attrs["flag_meanings"] == "not_computed untrusted trusted"
    mom = result.moments.set_index(["scene", "output"])
    assert ds["mean"].sel(scene=0, output="y_positive").item() == mom.loc[(0, "y_positive"), "mean"]
    assert ds["n_evals"].sel({"scene": 0, "output": "y_positive", "method": "pce"}).item() == 1024


def test_netcdf_and_zarr_round_trip_and_the_folder_export_matches(run: tuple[object, Path], tmp_path: Path) -> None:
    result, out = run
    ds = result.to_xarray()
    nc = tmp_path / "x.nc"
    ds.to_netcdf(nc, engine="h5netcdf")
    with xr.open_dataset(nc, engine="h5netcdf") as back:
        assert back.load().identical(ds)
    pytest.importorskip("zarr")
    assert main(["export", str(out), "--format", "zarr", "--out", str(tmp_path / "x.zarr")]) == 0
    with xr.open_zarr(tmp_path / "x.zarr") as back:
        back = back.load()
    for name in ("S1", "ST", "S1_conf", "ST_conf", "mean", "std"):   # the CSVs hold 6 significant digits
        np.testing.assert_allclose(back[name].values, ds[name].values, rtol=1e-5, atol=1e-12)
    assert (back["trusted"].values == ds["trusted"].values).all()
    assert list(back["output_unit"].values) == list(ds["output_unit"].values)
    assert main(["export", str(out), "--format", "netcdf"]) == 0
    with xr.open_dataset(out / "indices.nc", engine="h5netcdf") as back:
        np.testing.assert_allclose(back["ST"].values, ds["ST"].values, rtol=1e-5)
    assert main(["export", str(out), "--format", "csv"]) == 0
    long = pd.read_csv(out / "indices_long.csv")
    assert len(long) == len(pd.read_csv(out / "indices.csv")) == 24     # 2 scenes x 4 methods x 3 parameters


def test_fault_statistics_of_a_committed_study_as_arrays() -> None:
    from ddgsa.report.export import folder_dataset

    folder = Path(__file__).parents[2] / "results" / "paper_a_faults"
    ds = folder_dataset(folder)
    ver = pd.read_csv(folder / "fault_verdicts.csv")
    r = ver.iloc[3]
    assert ds["pod"].sel(scene=r["scene"], output=r["output"], fault_level=r["faulty"]).item() == r["pod"]
    assert ds["detectable"].sel(scene=r["scene"], output=r["output"], fault_level=r["faulty"]).item() == int(
        r["detectable"])
    assert "combined" in ds["output"].values and ds["trusted"].sel(output="combined").max() == -1
    assert ds.attrs["fault"] == "housing_looseness" and ds["speed_rpm"].values.tolist() == [1500]
    assert ds["speed_rpm"].attrs["units"] == "rpm"                  # scene coordinates carry their units


def test_export_writes_into_a_new_folder_and_scene_fields_carry_cf_units(tmp_path: Path) -> None:
    """``--out`` in a folder that does not exist yet is created (was: an h5py traceback-like failure,
    exit 1); the wind scene's fields read back with CF units (m/s, 1)."""
    import xarray as xr

    out = tmp_path / "new" / "deeper" / "quickstart.nc"
    assert main(["export", str(Path(__file__).parents[2] / "results" / "quickstart"), "--out", str(out), "-q"]) == 0
    with xr.open_dataset(out) as ds:
        assert ds["wind_speed"].attrs["units"] == "m/s" and ds["wind_speed"].values.tolist() == [11.0]
        assert ds["turbulence_intensity"].attrs["units"] == "1"


def test_export_refuses_a_folder_without_indices(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["export", str(tmp_path)]) == 2
    assert "no indices.csv" in capsys.readouterr().err
    (tmp_path / "indices.csv").write_text("a,b\n1,2\n")         # a CSV of another tool: named, exit 2
    assert main(["export", str(tmp_path)]) == 2
    assert "not an indices table ddgsa wrote (no column(s) scene, output" in capsys.readouterr().err
    shutil.copytree(Path(__file__).parents[2] / "results" / "quickstart", tmp_path / "q")
    (tmp_path / "q" / "provenance.json").write_text("{")       # truncated JSON: named, exit 2, no traceback
    for command in ("export", "html"):
        assert main([command, str(tmp_path / "q")]) == 2
        err = capsys.readouterr().err
        assert "provenance.json: not a JSON file ddgsa wrote" in err and "Traceback" not in err


def test_results_render_as_html_tables_in_jupyter(run: tuple[object, Path]) -> None:
    result, _ = run
    html = result._repr_html_()
    assert "study labelled" in html and html.count("<tr") == len(result.indices) + 1
    untrusted = ~result.indices["trusted"]
    assert html.count('style="background:#fdecea"') == int(untrusted.sum())
    assert untrusted[result.indices["method"] == "mdrm"].all()          # M-DRM misses Ishigami's interaction
    sobol = result.results[0][1]
    html = sobol._repr_html_()
    assert f"method {sobol.method}" in html and f"{sobol.n_evals} model evaluations" in html

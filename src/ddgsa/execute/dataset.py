"""A study's indices, bounds, flags, moments and fault statistics as labelled arrays (xarray).

:func:`to_dataset` turns the report's tables (the same ones ``indices.csv``, ``output_moments.csv``,
``fault_verdicts.csv`` ... hold) into one :class:`xarray.Dataset`:

=====================  ================================================  ===========================
variable               dimensions                                        meaning
=====================  ================================================  ===========================
S1, ST                 scene, output, parameter, method                  Sobol indices [1]
S1_conf, ST_conf       scene, output, parameter, method                  error estimate (bound or
                                                                         bootstrap half-width) [1]
trusted                scene, output, parameter, method                  1: within ``tolerance``
n_evals                scene, output, method                             model runs spent
mean, std, cv          scene, output                                     output moments [output_unit]
pod, auc, ...          scene, output, fault_level                        fault detectability
ST_faulty ...          scene, output, parameter, method, fault_level     indices with the fault
diagnostic_*           diagnostic                                        one row per diagnostic
=====================  ================================================  ===========================

The scene fields (``wind_speed``, ``speed_rpm`` ...) are coordinates along ``scene``; each output's
unit is the coordinate ``output_unit``. Attributes follow CF conventions where they apply
(``units``, ``long_name``, ``flag_values``/``flag_meanings``; ``1`` for dimensionless). A
missing combination (a method that did not run in a scene) is NaN. :func:`ddgsa.report.export.export_folder` writes
a results folder's dataset as NetCDF (``h5netcdf``), Zarr (when ``zarr`` is installed) or one tidy
CSV; :meth:`ddgsa.execute.kinds.common.StudyResult.to_xarray` gives it in a session.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from ddgsa.gsa.result import VERDICTS

INDEX_VARS = {"S1": "first-order Sobol index", "ST": "total Sobol index",
              "S1_conf": "error estimate of S1 (bound or bootstrap half-width)",
              "ST_conf": "error estimate of ST (bound or bootstrap half-width)"}
EXTRA_INDEX_VARS = {"Sh": "Shapley effect (dependent inputs)", "Sh_conf": "bootstrap half-width of Sh",
                    "HSIC": "HSIC V-statistic of the standardised output", "R2_HSIC": "normalised HSIC",
                    "p_value": "permutation-test p-value of independence (HSIC)",
                    "screened_in": "1 where p_value < alpha (HSIC screening)"}
"""Per-row quantities some methods add (shapley, hsic): exported where the table has them."""
FAULT_VARS = {"pod": "probability of detection at the false-alarm rate", "pod_low": "lower end of the POD interval",
              "pod_high": "upper end of the POD interval", "auc": "ROC area under the curve",
              "auc_low": "lower end of the AUC interval", "auc_high": "upper end of the AUC interval",
              "effect_size": "standardised mean shift between the faulty and healthy populations",
              "threshold": "alarm threshold", "ST_fault": "total index of the fault parameter"}

def to_dataset(indices: pd.DataFrame, scene_fields: list[str], moments: pd.DataFrame | None = None,
               fault: pd.DataFrame | None = None, fault_indices: pd.DataFrame | None = None,
               diagnostics: pd.DataFrame | None = None, attrs: dict[str, Any] | None = None,
               units: dict[str, str] | None = None, confirmation: pd.DataFrame | None = None) -> xr.Dataset:
    """The tables of a study as one :class:`xarray.Dataset` (see the module docstring).

    Parameters
    ----------
    indices : DataFrame
        One row per (scene, method, output, parameter): ``S1, S1_conf, ST, ST_conf, trusted, n_evals``
        and the scene fields.
    scene_fields : list of str
        The columns of ``indices`` that label a scene (coordinates along ``scene``).
    moments, fault, fault_indices, diagnostics : DataFrame, optional
        ``output_moments``, ``fault_verdicts``, ``fault_indices`` and ``diagnostics`` tables.
    attrs : dict, optional
        Global attributes (study name, model, provenance summary).
    units : dict of str to str, optional
        Unit of each output and scene field, as the model declares them (:meth:`ddgsa.models.base.Model.units`;
        an output's ``indices["output_unit"]`` where present wins).
    confirmation : DataFrame, optional
        The study's verdict per (scene, output) (``confirmation.csv``,
        :func:`ddgsa.execute.confirm.confirmation_table`): variables ``verdict`` and ``next_runs``.
    """
    idx = indices.copy()
    idx["trusted"] = idx["trusted"].astype(str).str.lower().eq("true").astype("int8")
    key = ["scene", "output", "parameter", "method"]
    extra = {k: v for k, v in EXTRA_INDEX_VARS.items() if k in idx}
    cube = idx.set_index(key)[[*INDEX_VARS, *extra, "trusted"]]
    ds = xr.Dataset.from_dataframe(cube)
    ds["n_evals"] = xr.DataArray.from_series(idx.groupby(["scene", "output", "method"])["n_evals"].first())
    for name, meaning in {**INDEX_VARS, **extra}.items():
        ds[name].attrs = {"units": "1", "long_name": meaning}
    ds["n_evals"].attrs = {"units": "1", "long_name": "model evaluations the method spent in the scene"}
    scenes = idx.groupby("scene")[scene_fields].first() if scene_fields else None
    if scenes is not None:
        ds = ds.assign_coords({f: ("scene", scenes[f].reindex(ds["scene"].values).to_numpy()) for f in scene_fields})
        for f in scene_fields:           # CF: "1" for dimensionless; a field without a known unit gets none
            if units and units.get(f):
                ds[f].attrs["units"] = "1" if units[f] == "-" else units[f]
    if moments is not None and len(moments):
        mom = xr.Dataset.from_dataframe(moments.set_index(["scene", "output"])[["mean", "std", "cv"]])
        ds = ds.merge(mom, join="outer")
        ds["mean"].attrs = {"long_name": "mean of the output", "units_from": "output_unit"}
        ds["std"].attrs = {"long_name": "standard deviation of the output", "units_from": "output_unit"}
        ds["cv"].attrs = {"units": "1", "long_name": "coefficient of variation std / |mean|"}
    if confirmation is not None and len(confirmation):
        conf = confirmation.set_index(["scene", "output"])
        ds = ds.merge(xr.Dataset.from_dataframe(conf[["verdict", "next_runs"]]), join="left")
        ds["verdict"] = ds["verdict"].fillna("").astype(str)
        ds["verdict"].attrs = {"long_name": "the study's verdict on the (scene, output) pair: "
                               + ", ".join(VERDICTS) + " (confirmation.csv)"}
        ds["next_runs"].attrs = {"units": "1", "long_name": "model runs the cheapest next step would take "
                                 "(0: confirmed or nothing to rank)"}
    if fault is not None and len(fault):
        fv = fault.rename(columns={"faulty": "fault_level"}).set_index(["scene", "output", "fault_level"])
        cols = [c for c in FAULT_VARS if c in fv]
        fv = fv.assign(detectable=fv["detectable"].astype(str).map({"True": 1.0, "False": 0.0}))
        ds = ds.merge(xr.Dataset.from_dataframe(fv[[*cols, "detectable"]]), join="outer")
        for c in cols:
            ds[c].attrs = {"long_name": FAULT_VARS[c], **({"units": "1"} if c != "threshold" else {})}
        ds["fault_level"].attrs = {"long_name": f"level of the fault parameter {fault['fault'].iloc[0]}"}
        ds.attrs.update(fault=str(fault["fault"].iloc[0]), fault_healthy=float(fault["healthy"].iloc[0]),
                        false_alarm=float(fault["false_alarm"].iloc[0]))
    if fault_indices is not None and len(fault_indices):
        fi = fault_indices.rename(columns={"level": "fault_level"}).set_index(
            ["scene", "output", "parameter", "method", "fault_level"])
        sub = fi[["S1", "ST", "dS1", "dST"]].add_suffix("_faulty")
        ds = ds.merge(xr.Dataset.from_dataframe(sub), join="outer")
        for c in sub.columns:
            ds[c].attrs = {"units": "1", "long_name": f"{c[:-7]} of the other parameters with the fault at fault_level"
                           + (" minus healthy" if c.startswith("d") else "")}
    if diagnostics is not None and len(diagnostics):
        d = diagnostics.reset_index(drop=True)
        for c in ("method", "name", "severity", "output", "parameter", "message"):
            if c in d:
                d[c] = d[c].fillna("").astype(str)      # no output / parameter: empty
        for c in d.columns:
            ds[f"diagnostic_{c}"] = ("diagnostic", d[c].to_numpy())
        ds["diagnostic_value"].attrs = {"long_name": "the number the diagnostic checked"}
    # after the merges, which may add outputs (the fault's ``combined`` discriminant) and levels
    ds["trusted"] = ds["trusted"].fillna(-1).astype("int8")
    ds["trusted"].attrs = {"long_name": "every index of the row within the method's tolerance of the truth",
                           "flag_values": np.array([-1, 0, 1], "int8"), "flag_meanings": "not_computed untrusted trusted"}
    if "detectable" in ds:
        ds["detectable"] = ds["detectable"].fillna(-1).astype("int8")
        ds["detectable"].attrs = {"flag_values": np.array([-1, 0, 1], "int8"),
                                  "flag_meanings": "refused_or_not_assessed not_detectable detectable"}
    unit_of = dict(units or {})
    if "output_unit" in idx:
        unit_of.update(idx.groupby("output")["output_unit"].first().dropna().to_dict())
    ds = ds.assign_coords({c: ds[c].astype(str) for c in ("output", "parameter", "method") if c in ds.coords})
    ds = ds.assign_coords(output_unit=("output", [str(unit_of.get(o, "")) for o in ds["output"].values]))
    ds["output_unit"].attrs = {"long_name": "unit of the output (UDUNITS where it applies; empty: dimensionless "
                                            "score or not declared)"}
    for c in ("scene", "output", "parameter", "method"):
        if c in ds.coords:
            ds[c].attrs.setdefault("long_name", c)
    ds.attrs.update({"Conventions": "CF-1.10", "title": "Sobol sensitivity indices (ddgsa)", **(attrs or {})})
    return ds

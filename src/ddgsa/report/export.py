"""A results folder's tables as one labelled dataset (:func:`ddgsa.execute.dataset.to_dataset`, read back from
the folder's CSVs with the model's declared units), written as NetCDF (``h5netcdf``), Zarr (when ``zarr`` is
installed) or one tidy CSV (``ddgsa export``).
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import xarray as xr

from ddgsa.errors import OutputFolderError
from ddgsa.execute.dataset import EXTRA_INDEX_VARS, INDEX_VARS, to_dataset
from ddgsa.gsa.result import ROW_COLUMNS

FORMATS = ("netcdf", "zarr", "csv")


def folder_dataset(folder: Path) -> xr.Dataset:
    """The dataset of a results folder, from its ``indices.csv`` and the other tables beside it."""
    from ddgsa.report.sections.base import Folder

    folder = Path(folder)
    path = folder / "indices.csv"
    if not path.is_file():
        raise OutputFolderError(f"{folder}: no indices.csv (export needs a GSA or fault study's results folder)")
    indices = pd.read_csv(path)
    missing = [c for c in ("scene", "output", "parameter", "method", *INDEX_VARS, "trusted", "n_evals")
               if c not in indices]
    if missing:
        raise OutputFolderError(f"{path}: not an indices table ddgsa wrote (no column(s) {', '.join(missing)})")

    def table(name: str) -> pd.DataFrame | None:
        p = folder / name
        return pd.read_csv(p) if p.is_file() and p.stat().st_size else None

    meta = {*ROW_COLUMNS, *EXTRA_INDEX_VARS}
    fields = [c for c in indices.columns if c not in meta]
    here = Folder(folder)
    prov = here.provenance
    attrs = {k: v for k, v in {"study": prov.get("study") or folder.name,
                               "model": (prov.get("model") or {}).get("name"),
                               "fidelity": (prov.get("model") or {}).get("fidelity"),
                               "created_utc": prov.get("created_utc"),
                               "ddgsa_commit": (prov.get("code") or {}).get("commit"),
                               "source": str(folder)}.items() if v}
    return to_dataset(indices, fields, table("output_moments.csv"), table("fault_verdicts.csv"),
                      table("fault_indices.csv"), table("diagnostics.csv"), attrs, here.units,
                      confirmation=table("confirmation.csv"))


def export_folder(folder: Path, fmt: str = "netcdf", out: Path | None = None) -> Path:
    """Write a results folder's dataset: NetCDF 4 (``indices.nc``), Zarr (``indices.zarr``) or a tidy
    CSV of the index cube (``indices_long.csv``); returns the path written."""
    if fmt not in FORMATS:
        raise OutputFolderError(f"--format {fmt!r}: allowed {', '.join(FORMATS)}")
    ds = folder_dataset(folder)
    folder = Path(folder)
    if out is not None:
        Path(out).parent.mkdir(parents=True, exist_ok=True)
    if fmt == "netcdf":
        path = out or folder / "indices.nc"
        ds.to_netcdf(path, engine="h5netcdf")
    elif fmt == "zarr":
        try:
            import zarr  # noqa: F401
        except ImportError:
            raise OutputFolderError("--format zarr needs the zarr package: pip install zarr") from None
        path = out or folder / "indices.zarr"
        ds.to_zarr(path, mode="w", zarr_format=2)     # v2: string arrays readable by every Zarr library
    else:
        path = out or folder / "indices_long.csv"
        cube = ds[[*INDEX_VARS, "trusted"]].to_dataframe().reset_index()
        cube[cube["trusted"] >= 0].to_csv(path, index=False, float_format="%.6g")
    return Path(path)

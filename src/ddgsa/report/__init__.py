"""The report: what a study's result becomes in its output folder, and what is read back from one.

* :mod:`~ddgsa.report.write` -- tables, charts, ``summary.md``, ``provenance.json`` of a result;
* :mod:`~ddgsa.report.html` -- ``report.html``, rebuilt from a folder's files alone (``ddgsa html``);
* :mod:`~ddgsa.report.beyond`, :mod:`~ddgsa.report.signals` -- the sections for groups, Shapley and HSIC,
  and for indices of signals and against sample size;
* :mod:`~ddgsa.report.export` -- a folder's tables as NetCDF, Zarr or a tidy CSV (``ddgsa export``);
* :mod:`~ddgsa.report.outdir` -- the output folder's guard: its lock, stale files, the completion mark.

May import: everything below it (:mod:`ddgsa.execute` for the result it writes, :mod:`ddgsa.study`,
:mod:`ddgsa.gsa`, :mod:`ddgsa.detection`, the models' declarations). Only the CLI imports it.
"""

"""The report: what a study's result becomes in its output folder, and what is read back from one.

* :mod:`~ddgsa.report.sections` -- one module per section of the report (its CSV tables, its charts drawn
  from the folder's files, its HTML part and captions), listed in page order in ``SECTIONS``;
* :mod:`~ddgsa.report.write` -- writes every section's tables and charts (PNG), ``summary.md``,
  ``provenance.json`` of a result;
* :mod:`~ddgsa.report.html` -- ``report.html`` from the sections, rebuilt from a folder's files alone
  (``ddgsa html``), each chart the same function's figure as inline SVG;
* :mod:`~ddgsa.report.beyond` -- the summary's parts for groups, Shapley and HSIC;
* :mod:`~ddgsa.report.export` -- a folder's tables as NetCDF, Zarr or a tidy CSV (``ddgsa export``);
* :mod:`~ddgsa.report.outdir` -- the output folder's guard: its lock, stale files, the completion mark.

May import: everything below it (:mod:`ddgsa.execute` for the result it writes, :mod:`ddgsa.study`,
:mod:`ddgsa.gsa`, :mod:`ddgsa.detection`, :mod:`ddgsa.mbs` for the Campbell diagram, the models'
declarations). Imported by the CLI, and by the benchmarks for the accuracy chart they save.
"""

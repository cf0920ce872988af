"""Execution: a validated study planned, run and analysed, without writing files.

* :mod:`~ddgsa.execute.pipeline` -- :func:`~ddgsa.execute.pipeline.execute` drives a study's kind
  (plan -> runner -> analyse), aggregates realisations, adds provenance and the verdicts;
* :mod:`~ddgsa.execute.kinds` -- one module per study kind (``gsa``, ``sweep``, ``fault``) behind the
  :class:`~ddgsa.execute.kinds.common.Kind` interface, and :class:`~ddgsa.execute.kinds.common.StudyResult`;
* :mod:`~ddgsa.execute.signals` -- indices of signals and convergence curves from the stored evaluations;
* :mod:`~ddgsa.execute.confirm` -- one verdict per (scene, output) and the cheapest next step
  (``confirmation.csv``, read by every output of a study);
* :mod:`~ddgsa.execute.dataset` -- a result's tables as one labelled :class:`xarray.Dataset`.

May import: the runner, :mod:`ddgsa.study`, :mod:`ddgsa.gsa`, :mod:`ddgsa.detection`, the models and
:mod:`ddgsa.loads`. Never the report (it reads what execution returns) or the CLI.
"""

"""The study file and everything that validates it, before anything runs.

* :mod:`~ddgsa.study.spec` -- the YAML schema (pydantic), names, ranges, units converted to the model's
  SI units, and :class:`~ddgsa.study.spec.Study`, the validated study every later step reads
  (:func:`~ddgsa.study.spec.load_study`);
* :mod:`~ddgsa.study.limits` -- bounds on the file (size, encoding, depth, aliases) and on the run it
  asks for (evaluations, memory, store size);
* :mod:`~ddgsa.study.checks` -- the model's own checks over the whole study (sampling, the valid region,
  design sizes, basis, unit hints): ``ddgsa validate``.

May import: :mod:`ddgsa.errors`, :mod:`ddgsa.units`, :mod:`ddgsa.registry`, the models (their declarations),
the scenes of :mod:`ddgsa.loads`, the kernel's sampling rules and the method names of :mod:`ddgsa.gsa`.
Never execution, the runner or the report.
"""

"""Study kinds: ``gsa``, ``sweep`` and ``fault``, one module each behind one interface.

:mod:`ddgsa.execute.kinds.common` holds what every kind shares (the plan of tasks per scene, the runs,
the result) and the :class:`~ddgsa.execute.kinds.common.Kind` interface; :func:`ddgsa.execute.pipeline.execute`
picks a study's kind from :data:`ddgsa.execute.pipeline.KINDS` by ``spec.kind``.
"""

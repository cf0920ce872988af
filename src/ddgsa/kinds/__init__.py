"""Study kinds: ``gsa``, ``sweep`` and ``fault``, one module each behind one interface.

:mod:`ddgsa.kinds.common` holds what every kind shares (the plan of tasks per scene, the runs,
the result) and the :class:`~ddgsa.kinds.common.Kind` interface; :func:`ddgsa.pipeline.execute`
picks a study's kind from :data:`ddgsa.pipeline.KINDS` by ``spec.kind``.
"""

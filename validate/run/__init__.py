"""Run orchestration: one ``run``/``all`` (:mod:`.session`), the order experiments run in and the second lane
(:mod:`.schedule`, :mod:`.lane`), the staged output folder and its atomic commit (:mod:`.output`), plug-ins
(:mod:`.plugins`) and signals (:mod:`.interrupt`). The experiments' side of a run — the :class:`Context` they
compute in — is their interface, :mod:`validate.experiments.base`.

Nothing is imported here: ``python -m validate.run.lane`` starts a child interpreter through this package."""

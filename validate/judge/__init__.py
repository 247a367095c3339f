"""Judge images rendered anywhere against the Mitsuba truth of the exported scenes (``python -m validate judge``):
:func:`validate.judge.folder.judge_folder` (numbers), :func:`validate.judge.folder.run_judge` (the command),
:mod:`validate.judge.images` (reading an engine's files), :mod:`validate.judge.page` (the HTML page)."""

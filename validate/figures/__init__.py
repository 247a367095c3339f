"""The figures experiments draw (:mod:`.plots`: tone-mapped HDR images, error heatmaps, line plots, arrays in,
PNG out). Below :mod:`validate.report` on purpose: an experiment's ``report.py`` draws with these and never
loads the HTML pages (jinja2) that are rendered from ``results.json`` afterwards."""

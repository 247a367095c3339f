"""Ground truth: Mitsuba renders and quadratures of Mitsuba's own radiance, cached, with uncertainty."""

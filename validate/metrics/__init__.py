"""Error metrics. Every function returns values *and* the parameters/definitions used."""

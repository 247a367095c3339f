"""A broken plug-in: returns NaN (the output contract must stop the run with one line, exit 2)."""
import numpy as np

from validate.local_models import irradiance


@irradiance.register("broken_nan", "returns NaN")
def broken_nan(radiance, normals):
    return np.full((len(normals), 3), np.nan)

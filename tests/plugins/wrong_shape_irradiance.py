"""A broken plug-in: returns luminance (N,) instead of RGB (N, 3)."""
import numpy as np

from validate.local_models import irradiance


@irradiance.register("broken_shape", "returns (N,) instead of (N, 3)")
def broken_shape(radiance, normals):
    return np.ones(len(normals))

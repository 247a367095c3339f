"""A plug-in that reuses a built-in's name: a duplicate name is an error, never a silent replacement."""
import numpy as np

from validate.local_models import irradiance


@irradiance.register("sh9", "my own sh9")
def sh9(radiance, normals):
    return np.zeros((len(normals), 3))

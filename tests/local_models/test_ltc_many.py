"""The LTC's batched path (a light and an α per receiver, one drjit evaluation) against its per-call path, bit for
bit: :func:`ltc_many`, :func:`ltc_integral_many` and the arealights experiment's :func:`ltc_batch`."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.local_models import family
from validate.local_models.precision import family_precision
from validate.local_models.specular_arealight.ltc import ltc_integral, ltc_integral_many, ltc_many

spc = importlib.import_module("validate.experiments.arealights.specular.compute")


SHAPES = ("rectangle", "disc", "sphere", "tube")


def _configs(shape: str) -> list[tuple[dict, float, tuple[np.ndarray, np.ndarray, np.ndarray]]]:
    """(light, α, one receiver) over the experiment's configurations, three α and two sizes (both tube axes)."""
    out = []
    for a in (0.05, 0.3, 0.8):
        for sg in (2.5, 20.0):
            for cfg in spc.CONFIGS:
                for ax in spc.TUBE_AXES if shape == "tube" else ("across",):
                    out.append((spc.light_for(shape, cfg[1], cfg[2], sg, ax), a, spc._receiver(cfg[0])))
    return out


def _bits(x: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(x, dtype=np.float64).view(np.uint64)


@pytest.mark.parametrize("shape", SHAPES)
def test_ltc_many_equals_per_call_bit_for_bit(shape):
    """Row m of ltc_many (under the family's precision, as Family.call runs ltc) is ltc's one-receiver output for
    light m and α m, every bit; likewise ltc_integral_many's (F, E, E_f) against ltc_integral's."""
    fam = family("specular_arealight")
    cases = _configs(shape)
    lights, alphas = [c[0] for c in cases], [c[1] for c in cases]
    p, n, v = (np.concatenate([c[2][i] for c in cases]) for i in range(3))
    with family_precision(fam.precision):
        many = ltc_many(lights, [{"alpha": a, "f0": 1.0} for a in alphas], p, n, v)
    one = np.concatenate([fam.call("ltc", c[0], {"alpha": c[1], "f0": 1.0}, *c[2]) for c in cases])
    assert np.array_equal(_bits(many), _bits(one))
    ff, e, ef = ltc_integral_many(lights, [a * a for a in alphas], p, n, v)
    ref = np.array([np.r_[ltc_integral(c[0], c[1] * c[1], *c[2])] for c in cases])
    assert np.array_equal(_bits(np.stack([ff, e, ef], 1)), _bits(ref))
    assert np.all(ff > 0.0)  # every configuration sees its light: the comparison is not of zeros


def test_ltc_many_rgb_f0_and_radiance():
    """Per-receiver RGB F₀ and L_e enter as ltc's do (bit for bit)."""
    fam = family("specular_arealight")
    rng = np.random.default_rng(3)
    cases = _configs("disc")[:12]
    lights = [dict(c[0], radiance=float(rng.uniform(0.5, 2.0))) for c in cases]
    brdfs = [{"alpha": c[1], "f0": rng.uniform(0.0, 1.0, 3)} for c in cases]
    p, n, v = (np.concatenate([c[2][i] for c in cases]) for i in range(3))
    with family_precision(fam.precision):
        many = ltc_many(lights, brdfs, p, n, v)
    one = np.concatenate([fam.call("ltc", lt, b, *c[2]) for lt, b, c in zip(lights, brdfs, cases, strict=True)])
    assert np.array_equal(_bits(many), _bits(one))


def test_ltc_many_refuses_mixed_shapes_and_lengths():
    cases = _configs("rectangle")[:2] + _configs("disc")[:1]
    p, n, v = (np.concatenate([c[2][i] for c in cases]) for i in range(3))
    with pytest.raises(ValidateError, match="one shape"):
        ltc_integral_many([c[0] for c in cases], [0.3] * 3, p, n, v)
    with pytest.raises(ValidateError, match="per receiver"):
        ltc_integral_many([c[0] for c in cases[:2]], [0.3] * 2, p, n, v)


def test_ltc_batch_equals_measure_config():
    """The experiment's batched LTC numbers are measure_config's own per-call ones (every shape, both axes)."""
    techs = list(family("specular_arealight"))
    keys = [(sh, a, sg, cfg, ax) for sh in SHAPES for a in (0.1, 0.6) for sg in (5.0, 30.0) for cfg in spc.CONFIGS[:4]
            for ax in (spc.TUBE_AXES if sh == "tube" else ("across",))]
    batch = spc.ltc_batch(keys, techs)
    for k in keys:
        got = spc.measure_config(k[0], k[1], k[2], k[3], 16, techs, k[4], (1.0, 0.0), batch[k])
        want = spc.measure_config(k[0], k[1], k[2], k[3], 16, techs, k[4], (1.0, 0.0))
        assert got == want and list(got["techniques"]) == list(want["techniques"])
        assert batch[k][0] == want["techniques"]["ltc"]

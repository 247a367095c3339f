"""Filterable shadow maps (VSM, ESM, MSM) against closed forms and the inequalities they rest on.

Oracles:
* every one of them bounds the filtered depth test P(D ≥ t) from above: Cantelli's inequality (VSM,
  Donnelly & Lauritzen 2006 eq. 5), Markov's on e^(cD) (ESM, Annen et al. 2008), the sharp moment bound
  (MSM, Peters & Klein 2015 §3; within its bias α/2) — checked on random depth distributions;
* MSM with α = 0 reproduces a two-atom depth distribution exactly (four moments determine it);
* ESM of a single depth d₀ is e^(c (d₀ − t)) clipped to 1; VSM of a single depth is 1 in front of it;
* the lookup's 6×6 weights (5×5 Gauss ∗ bilinear) sum to 1 and read a constant map as that constant.
"""

from __future__ import annotations

import numpy as np
import pytest

from validate.local_models.precision import computing_in
from validate.local_models.shadow import shadow_map as smod
from validate.local_models.shadow.shadow_esm import C
from validate.local_models.shadow.shadow_msm import ALPHA, hamburger_4msm
from validate.local_models.shadow.shadow_vsm import MIN_VARIANCE, vsm_visibility

EXACT = 1e-9  # float64 LDLᵀ solve of a 3×3 Hankel system of a two-atom distribution: measured 3e-12
FLOAT = 1e-12


def _moments(d: np.ndarray, w: np.ndarray) -> np.ndarray:
    return np.stack([(w * d**k).sum(axis=-1) for k in range(1, 5)], axis=-1)


def test_msm_reproduces_a_two_atom_distribution() -> None:
    d, w = np.array([0.3, 0.6]), np.array([0.4, 0.6])
    z = np.array([0.2, 0.35, 0.45, 0.55, 0.65, 0.9])
    with computing_in("float64"):  # the formula's exactness (the shader's float32 is tests/local_models/test_ports.py)
        g = hamburger_4msm(np.tile(_moments(d, w), (z.size, 1)), z, alpha=0.0)
    assert np.allclose(g, [0.0, 0.4, 0.4, 0.4, 1.0, 1.0], atol=EXACT)  # G = P(D < z)


@pytest.fixture(scope="module")
def random_footprints() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """2000 random 36-texel depth distributions (1–3 occluder depths plus the receiver) and depths t."""
    rng = np.random.default_rng(11)
    n = 2000
    levels = rng.uniform(0.05, 0.95, (n, 3))
    which = rng.integers(0, 3, (n, 36))
    d = np.take_along_axis(levels, which, axis=1) + rng.normal(0, 0.002, (n, 36))
    w = rng.uniform(0.1, 1.0, (n, 36))
    w /= w.sum(axis=1, keepdims=True)
    t = rng.uniform(0.0, 1.0, n)
    return np.clip(d, 0, 1), w, t


def test_every_moment_map_bounds_the_filtered_test(random_footprints) -> None:
    d, w, t = random_footprints
    p = (w * (t[:, None] <= d)).sum(axis=1)
    b = _moments(d, w)
    vsm = vsm_visibility(b[:, 0], b[:, 1], t)
    esm = np.clip((w * np.exp(C * (d - t[:, None]))).sum(axis=1), 0, 1)
    msm = 1 - hamburger_4msm(b, t)
    assert np.all(vsm >= p - FLOAT) and np.all(esm >= p - FLOAT)
    assert np.all(msm >= p - ALPHA / 2 - FLOAT)
    # and the light-bleeding reduction (the claims' power perturbation) breaks every one of them
    for v in (vsm, esm, msm):
        assert np.max(p - np.clip((v - 0.2) / 0.8, 0, 1)) > 0.1
    # MSM is the tightest of the three on average (four moments vs two, or one exponential)
    assert np.mean(msm - p) < min(np.mean(vsm - p), np.mean(esm - p))


def test_single_depth_closed_forms() -> None:
    d0 = 0.5
    t = np.array([0.3, 0.5, 0.52, 0.7])
    b1, b2 = np.full(4, d0), np.full(4, d0 * d0)
    v = vsm_visibility(b1, b2, t)
    assert np.all(v[:2] == 1.0)
    assert np.allclose(v[2:], MIN_VARIANCE / (MIN_VARIANCE + (t[2:] - d0) ** 2))
    esm = np.clip(np.exp(C * (d0 - t)), 0, 1)
    assert esm[0] == 1.0 and esm[2] == pytest.approx(np.exp(-C * 0.02))


def test_lookup_weights_sum_to_one_and_read_a_constant_map() -> None:
    import mitsuba as mi

    from validate.backend import init

    init()
    res = 32
    view = smod.LightView(np.zeros(3), np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]),
                          np.array([0.0, 1.0, 0.0]), 0.0, 0.0, 1.0, 1.0, 3.0)
    zw = view.depth_scale * (1 - 1 / 2.0)  # every texel holds an occluder at view depth 2
    sm = smod.ShadowMap(view, res, mi.Float(np.full(res * res, zw, np.float32)),
                        mi.Float(np.zeros(res * res, np.float32)))
    rng = np.random.default_rng(2)
    s = rng.uniform(0.2, 0.8, 50)
    p = np.c_[s * 2.5, rng.uniform(0.2, 0.8, 50) * 2.5, np.full(50, 2.5)]  # receivers at depth 2.5, inside
    fp = smod.filter_footprint(sm, p)
    assert np.allclose(fp.weight.sum(axis=1), 1.0)
    assert np.allclose(fp.depth, (2.0 - 1.0) / (3.0 - 1.0), atol=1e-6)  # d = (z − n)/(f − n)
    assert np.allclose(fp.receiver, 0.75) and np.all(fp.depth_test() == 0.0)


def test_light_bleeding_case_orders_the_filterable_maps() -> None:
    """Synthetic two-occluder map, receivers fully shadowed: depth-test techniques leak nothing; at contact
    VSM leaks most and MSM least (Donnelly & Lauritzen 2006 §3.2; Annen et al. 2008 Fig. 1; Peters & Klein
    2015). Measured at contact: VSM 6.3 %, ESM 3.5 %, MSM 0.24 % mean V′."""
    from validate.experiments.shadows.compute import bleeding_case
    from validate.local_models import shadow

    b = bleeding_case([shadow[n] for n in ("hard", "pcf", "vsm", "esm", "msm")])
    for case in ("far apart", "contact"):
        assert b[case]["hard"]["leak"] == 0.0 and b[case]["pcf"]["leak"] == 0.0
    c = b["contact"]
    assert c["msm"]["leak"] < c["esm"]["leak"] < c["vsm"]["leak"]
    assert b["far apart"]["esm"]["leak"] < b["far apart"]["vsm"]["leak"]  # ESM avoids VSM's boundary leak

"""Multiple-scattering GGX compensation (validate.local_models.brdf_multiscatter) and the multiscatter experiment."""

from __future__ import annotations

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.experiments import multiscatter as ms
from validate.experiments.base import Context
from validate.local_models import family
from validate.local_models.brdf_multiscatter import tables
from validate.scenes import brdf_scenes as bs

COMPENSATED = ("ggx_kulla_conty", "ggx_fdez_aguera", "ggx_turquin", "ggx_metalness_fdez_aguera")


def furnace(tech: str, params: dict, mu: float, nodes: int = 96) -> float:
    dirs, w = bs.hemisphere_quadrature(nodes, 2 * nodes)
    v = np.tile([np.sqrt(1.0 - mu * mu), 0.0, mu], (len(dirs), 1))
    q = family("brdf").call(tech, params, np.tile([0.0, 0.0, 1.0], (len(dirs), 1)), dirs, v)
    return float(np.sum(w * q[:, 1]))


def test_table_matches_direct_quadrature_of_single_scattering():
    """E(μ) from the half-vector quadrature equals the l-space quadrature of cook_torrance (F = 1) to 10⁻³."""
    for alpha, mu in ((0.5, 0.5), (1.0, 1.0), (0.3, 0.8)):
        t = tables("ggx", alpha)
        direct = furnace("cook_torrance", {"alpha": alpha, "distribution": "ggx", "eta": 0.0, "k": 1.0}, mu)
        assert abs(float(t.lookup(t.e, np.array([mu]))[0]) - direct) < 1e-3
    assert 0.29 < float(tables("ggx", 1.0).lookup(tables("ggx", 1.0).e, np.array([1.0]))[0]) < 0.32  # ~69 % lost


@pytest.mark.parametrize("tech", COMPENSATED)
def test_compensation_closes_the_furnace(tech):
    for alpha, mu in ((0.5, 0.3), (1.0, 1.0), (1.0, 0.5)):
        p = {"alpha": alpha, "distribution": "ggx", "eta": 0.0, "k": 1.0, "metalness": 1.0, "base_color": 1.0}
        assert abs(furnace(tech, p, mu) - 1.0) < 2e-3


def test_blended_f0_bug_loses_energy_at_intermediate_metalness():
    p = {"alpha": 0.6, "distribution": "ggx", "metalness": 0.5, "base_color": 1.0}
    assert abs(furnace("ggx_metalness_fdez_aguera", p, 0.5) - 1.0) < 2e-3
    assert furnace("ggx_metalness_blended_f0_bug", p, 0.5) < 0.9
    pure = {**p, "metalness": 1.0}
    assert abs(furnace("ggx_metalness_blended_f0_bug", pure, 0.5) - 1.0) < 2e-3


def test_bad_alpha_is_one_line_error():
    with pytest.raises(ValidateError, match="ggx_turquin.*alpha"):
        family("brdf").call("ggx_turquin", {"alpha": 0.0}, np.array([[0, 0, 1.0]]), np.array([[0, 0, 1.0]]),
                            np.array([[0, 0, 1.0]]))


def test_experiment_claims_pass_and_power_fails(tmp_path):
    s = ms.Settings(alphas=(0.5, 1.0), mus=(0.3, 1.0), metalness=(0.0, 0.5, 1.0), nodes=64, walkers=50_000,
                    walk_alphas=(0.6, 1.0))
    ctx = Context(out_dir=tmp_path, quick=True, show_progress=False)
    m = ms.compute(ctx, s)
    claims = {c.id: c for c in ms.claims(m)}
    for tech in COMPENSATED:
        c = claims[f"multiscatter.technique.{tech}.furnace_error.f0_1"]
        assert c.passed and c.power.fails, c
    bug = claims["multiscatter.regression.ggx_metalness_blended_f0_bug.furnace_error.metalness"]
    assert bug.passed and bug.measured > 0.2 and bug.power.fails
    assert ms.metrics(m, "cook_torrance")["furnace_error.f0_1"]["value"] > 0.6
    for cid in ("multiscatter.walk.single_scatter", "multiscatter.walk.furnace"):
        assert claims[cid].passed and claims[cid].power.fails, claims[cid]


def test_random_walk_reference():
    """Heitz et al. 2016's walk: energy 1 at F = 1, first bounce = the height-correlated albedo, and more light than
    single scattering at F₀ < 1."""
    from validate.reference import microsurface_walk as mw
    r = mw.walk(0.8, 0.6, (1.0, 0.5), 60_000, 3)
    assert abs(r.albedo[0] - 1.0) < 1e-12 and r.truncated == 0.0
    assert abs(r.single[0] - ms.e_correlated(0.8, 0.6)) < 4 * r.single_se[0]
    assert r.albedo[1] > r.single[1] + 0.02

"""``multiscatter`` compute step: every technique's furnace grids (n and n/2 nodes), the random-walk reference
per α, the walk BSDF's own checks (:func:`bsdf_checks`) and three.js's published table; numbers only."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...backend import init
from ...local_models import family
from ...local_models.brdf.brdf_multiscatter import tables
from ...local_models.brdf.common import frozen_copy, ggx_d
from ...local_models.registry import Technique
from ...reference import microsurface_bsdf as mbsdf
from ...reference import microsurface_walk as mw
from ...scenes import brdf_scenes as bs
from ...scenes.latlong import luminance
from ..base import Context
from .settings import Settings

# three.js PR 33983's white-furnace table, single-scattering column (F₀ = 1): (roughness r, NoV, W); α = r²
PUBLISHED_SS = ((0.5, 0.5, 0.86), (0.75, 0.5, 0.66), (1.0, 0.5, 0.45), (1.0, 1.0, 0.31))


FAMILY_WISE = 0.01  # Mitsuba's ChiSquareTest default significance level, Šidák-corrected over each claim's tests
# The expected counts are walk estimates (pdf() has no closed form); their Monte Carlo variance, estimated from
# the repeats, enters the χ² denominator. Near a sharp lobe (α = 0.1) the next-event estimator is heavy-tailed: with
# 4 × 32 walks its variance estimate is unreliable (measured: max Var Ê/Ê = 92–165, p ≈ 10⁻⁶⁰ for a sampler that
# Mitsuba's own roughconductor-through-the-same-harness test shows the grid resolves, p = 0.91). So a case's walks are
# quadrupled (with 16 repeats) until Var Ê ≤ Ê in every cell with Ê > 5, i.e. until the pdf's own noise is below
# the histogram's Poisson noise (α = 0.1: 4 × 32 → 16 × 512 walks, p 3·10⁻⁵⁴ → ≈ 0.02).
MAX_PDF_VARIANCE_RATIO = 1.0
PDF_REPEATS = 16
MAX_CHI2_WALKS = 2048
CHI2_POWER = {"sample_alpha_scale": 1.1}
RECIP_POWER = {"nee_distant_g1": True}


@dataclass
class Measurements:
    settings: Settings
    techniques: list[Technique]
    # w[tech][key] = {"value", "half"}; key "f0_1" → (α, μ) grid, "metal" → (m, α, μ), "f0_<x>" → scalar
    w: dict[str, dict[str, Any]] = field(default_factory=dict)
    published: list[dict[str, float]] = field(default_factory=list)
    walk: list[dict[str, Any]] = field(default_factory=list)  # per α: the reference walk and every technique's W
    bsdf: dict[str, Any] = field(default_factory=dict)  # the walk as a Mitsuba BSDF: χ², reciprocity, furnaces


def chi2_case(alpha: float, theta_i: float, kw: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """One χ² case of the walk BSDF (:func:`validate.reference.microsurface_bsdf.chi2_walk`), its pdf walks quadrupled
    (with :data:`PDF_REPEATS` seeds) until max Var Ê/Ê ≤ :data:`MAX_PDF_VARIANCE_RATIO` (see there); returns the row
    (with the walks and repeats used) and the keyword arguments, for the power check to use the same."""
    kw = dict(kw)
    row = mbsdf.chi2_walk(alpha, theta_i, **kw)
    while row["variance_ratio"] > MAX_PDF_VARIANCE_RATIO and kw["walks"] < MAX_CHI2_WALKS:
        kw |= {"walks": 4 * kw["walks"], "repeats": PDF_REPEATS}
        row = mbsdf.chi2_walk(alpha, theta_i, **kw)
    return row | {"walks": kw["walks"], "repeats": kw.get("repeats", 4)}, kw


class _ReadKeys(Mapping[str, Any]):
    """A read-only parameter mapping that records which keys a technique read (``[]``, ``get``, ``in``); iterating it
    (``dict(p)``, ``**p``, ``keys()``) counts as reading every key."""

    def __init__(self, params: Mapping[str, Any]) -> None:
        self._p = dict(params)
        self.read: set[str] = set()

    def __getitem__(self, key: str) -> Any:
        self.read.add(key)
        return self._p[key]

    def __contains__(self, key: object) -> bool:
        self.read.add(str(key))
        return key in self._p

    def __iter__(self) -> Iterator[str]:
        self.read.update(self._p)
        return iter(self._p)

    def __len__(self) -> int:
        return len(self._p)


# _furnace's memo: (technique name, its function's id, μ's, nodes, Mitsuba variant) → [(keys read, their values, W)]
_MemoEntry = tuple[frozenset[str], tuple[Any, ...], np.ndarray]
_FURNACE_MEMO: dict[tuple[str, int, tuple[float, ...], int, str], list[_MemoEntry]] = {}


def _param_values(params: Mapping[str, Any], keys: frozenset[str]) -> tuple[Any, ...]:
    return tuple((k, repr(params[k]) if k in params else None) for k in sorted(keys))


def _furnace(tech: Technique, params: dict[str, Any], mus: tuple[float, ...], nodes: int) -> np.ndarray:
    """W(μ_v) for each μ in ``mus`` (luminance), q through the registry (contract checked): one call over every μ
    (the quadrature tiled; q is per sample, so each μ's block is what a call of its own returns — the GL listings
    pay a shader compile per call), each μ's sum over its own block.

    Memoised: a technique is a deterministic function of the geometry and of the parameters it reads, so a call
    whose parameters agree with an earlier call's on every key that call read (recorded by :class:`_ReadKeys`; same
    technique, μ's and nodes) returns that call's W — the same number, not recomputed (e.g. Phong reads no α, so
    its grid over α is one evaluation)."""
    memo = _FURNACE_MEMO.setdefault((tech.name, id(tech.fn), tuple(mus), nodes, init().variant), [])
    for keys, values, out in memo:
        if _param_values(params, keys) == values:
            return out.copy()
    rec = _ReadKeys(params)
    out = _furnace_eval(tech, rec, mus, nodes)
    keys = frozenset(rec.read)
    memo.append((keys, _param_values(params, keys), out))
    return out.copy()


# _furnace_geometry's arrays per (μ's, nodes): the same for every technique and parameter set of a grid
_GEOMETRY: dict[tuple[tuple[float, ...], int], tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = {}


def _furnace_geometry(mus: tuple[float, ...], nodes: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(normals, lights, views, weights) of :func:`_furnace_eval`: the hemisphere quadrature
    (:func:`validate.scenes.brdf_scenes.hemisphere_quadrature`, nodes × 2·nodes) tiled once per μ_v, n = +z, v at
    azimuth 0. Built once per (μ's, nodes) and read-only: the grids call every technique thousands of times on the
    same arrays, and the brdf family converts read-only inputs it has seen to drjit once
    (``common._packed_directions``); the values are those formed per call before."""
    key = (tuple(mus), int(nodes))
    hit = _GEOMETRY.get(key)
    if hit is None:
        dirs, w = bs.hemisphere_quadrature(nodes, 2 * nodes)
        k = len(dirs)
        n = np.tile([0.0, 0.0, 1.0], (k * len(mus), 1))
        v = np.concatenate([np.tile([np.sqrt(1.0 - mu * mu), 0.0, mu], (k, 1)) for mu in mus])
        hit = _GEOMETRY[key] = (frozen_copy(n), frozen_copy(np.tile(dirs, (len(mus), 1))), frozen_copy(v),
                                frozen_copy(w))
    return hit


def _furnace_eval(tech: Technique, params: Mapping[str, Any], mus: tuple[float, ...], nodes: int) -> np.ndarray:
    """:func:`_furnace` without the memo."""
    n, l, v, w = _furnace_geometry(mus, nodes)
    k = len(w)
    q = family("brdf").call(tech, params, n, l, v)
    return np.asarray([float(np.sum(w * luminance(q[i * k:(i + 1) * k]))) for i in range(len(mus))])


def _f1(alpha: float, m: float = 1.0) -> dict[str, Any]:
    return {"alpha": alpha, "distribution": "ggx", "eta": 0.0, "k": 1.0, "albedo": 0.0, "metalness": m,
            "base_color": 1.0}


def _dielectric(alpha: float, f0: float) -> dict[str, Any]:
    eta = (1.0 + np.sqrt(f0)) / (1.0 - np.sqrt(f0))
    return {"alpha": alpha, "distribution": "ggx", "eta": float(eta), "k": 0.0, "albedo": 0.0, "metalness": 1.0,
            "base_color": f0}


def measure(tech: Technique, s: Settings) -> dict[str, Any]:
    """Furnace grids of one technique at n and n/2 nodes."""
    out: dict[str, Any] = {}
    for key, nodes in (("value", s.nodes), ("half", s.nodes // 2)):
        f0_1 = [_furnace(tech, _f1(a), s.mus, nodes).tolist() for a in s.alphas]
        out.setdefault("f0_1", {})[key] = f0_1
        if tech.meta.get("metalness"):  # metalness 1 is the F₀ = 1 grid (the same parameters): not evaluated twice
            out.setdefault("metal", {})[key] = [[list(row) for row in f0_1] if m == 1.0 else
                                                [_furnace(tech, _f1(a, m), s.mus, nodes).tolist() for a in s.alphas]
                                                for m in s.metalness]
        for f0 in s.f0s:
            out.setdefault(f"f0_{f0:g}", {})[key] = float(_furnace(tech, _dielectric(1.0, f0), (0.5,), nodes)[0])
    return out


Task = tuple[Any, ...]


def _tasks(s: Settings, techniques: list[Technique], seed: int) -> list[Task]:
    """Every independent piece of :func:`compute`, costliest first (measured on the full settings: the χ² cases'
    pdf walks, the numpy random walks, the technique grids, then the other BSDF checks); the numbers do not
    depend on the order (each task's seeds come from ``seed`` and the task)."""
    checks = bsdf_tasks(s, seed) if s.bsdf_checks and _bsdf_skipped() is None else []
    chi2 = [t for t in checks if t[0] == "chi2"]
    walks = [("walk", a, seed + i) for i, a in enumerate(s.walk_alphas)]
    return chi2 + walks + [("technique", t) for t in techniques] + [t for t in checks if t[0] != "chi2"]


def _run_task(task: Task, s: Settings) -> Any:
    """One task of :func:`_tasks`: a technique's grids and walk values, one reference walk, or one BSDF check."""
    if task[0] == "technique":
        t = task[1]
        grids = measure(t, s)
        return grids, [walk_techniques(t, a, s, {t.name: grids}) for a in s.walk_alphas]
    if task[0] == "walk":
        return walk_reference(task[1], s, task[2])
    return bsdf_task(task, s)


def compute(ctx: Context, s: Settings) -> Measurements:
    """Furnace grids, the walks, the walk BSDF's checks (independent tasks through ``ctx.map``), the published
    table."""
    m = Measurements(s, list(family("brdf")))
    tasks = _tasks(s, m.techniques, ctx.seed)
    done = ctx.map(lambda t: _run_task(t, s), tasks, "multiscatter: grids, walks, BSDF checks")
    by_kind: dict[str, list[tuple[Task, Any]]] = {}
    for t, r in zip(tasks, done, strict=True):
        by_kind.setdefault(t[0], []).append((t, r))
    m.w = {t[1].name: r[0] for t, r in by_kind.get("technique", [])}
    tech_walk = {t[1].name: r[1] for t, r in by_kind.get("technique", [])}
    m.walk = [r | {"techniques": {t.name: tech_walk[t.name][i] for t in m.techniques}}
              for i, (_, r) in enumerate(by_kind.get("walk", []))]
    if not s.bsdf_checks:
        m.bsdf = {}
    else:
        m.bsdf = _bsdf_skipped() or bsdf_collect([tr for k, trs in by_kind.items() if k not in ("technique", "walk")
                                                  for tr in trs])
    for r, mu, w in PUBLISHED_SS:
        m.published.append({"roughness": r, "alpha": r * r, "nov": mu, "published": w, "table": _e(r * r, mu),
                            "table_neighbour": _e((r * 1.1 if r < 1.0 else 0.9) ** 2, mu)})
    return m


def e_correlated(alpha: float, mu: float, nodes: int = 256) -> float:
    """Single-scattering GGX albedo with the height-correlated G₂ = 1/(1 + Λ_i + Λ_o) (F = 1), the first bounce of
    the random walk (Heitz et al. 2016 §4.3), by hemisphere quadrature."""
    d, w = bs.hemisphere_quadrature(nodes, 2 * nodes)
    v = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    h = d + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    lam = mw.lambda_ggx(d, alpha) + mw.lambda_ggx(v[None, :], alpha)
    return float(np.sum(w * ggx_d(h[:, 2], alpha) / (1.0 + lam) / (4.0 * mu)))


def _known_w(w: dict[str, Any], s: Settings, tech: str, alpha: float, f0: float) -> float | None:
    """A technique's W(μ_v = s.walk_mu) at (α, F₀) with s.nodes already in the furnace grids ``w`` (the same
    parameters, the same quadrature: the same number), else None."""
    grids = w.get(tech, {})
    if f0 >= 1.0 and alpha in s.alphas and s.walk_mu in s.mus and "f0_1" in grids:
        return float(grids["f0_1"]["value"][s.alphas.index(alpha)][s.mus.index(s.walk_mu)])
    if f0 < 1.0 and alpha == 1.0 and s.walk_mu == 0.5 and f0 in s.f0s and f"f0_{f0:g}" in grids:
        return float(grids[f"f0_{f0:g}"]["value"])
    return None


def walk_reference(alpha: float, s: Settings, seed: int) -> dict[str, Any]:
    """The random walk's albedo at μ_v = s.walk_mu for each F₀ (Schlick per bounce) and its first-bounce albedo
    against the height-correlated closed form (:func:`walk_compare` without the techniques)."""
    r = mw.walk(alpha, s.walk_mu, s.walk_f0s, s.walkers, seed % 2**31)
    return {"alpha": alpha, "mu": s.walk_mu, "f0s": list(s.walk_f0s), "albedo": r.albedo.tolist(),
            "albedo_se": r.albedo_se.tolist(), "single": r.single.tolist(), "single_se": r.single_se.tolist(),
            "mean_order": r.mean_order, "truncated": r.truncated, "e_correlated": e_correlated(alpha, s.walk_mu),
            "e_separable": _e(alpha, s.walk_mu)}


def walk_techniques(t: Technique, alpha: float, s: Settings, known: dict[str, Any] | None = None) -> list[float]:
    """A technique's W at μ_v = s.walk_mu for each of the walk's F₀ (η real, or metalness 1 with base colour F₀;
    F₀ = 1: η = 0, k = 1); values already in the furnace grids ``known`` (:func:`measure`) are reused."""
    vals = []
    for f0 in s.walk_f0s:
        v = _known_w(known or {}, s, t.name, alpha, f0)
        vals.append(v if v is not None else float(_furnace(t, _f1(alpha) if f0 >= 1.0 else _dielectric(alpha, f0),
                                                           (s.walk_mu,), s.nodes)[0]))
    return vals


def walk_compare(techs: list[Technique], alpha: float, s: Settings, seed: int,
                 known: dict[str, Any] | None = None) -> dict[str, Any]:
    """The random walk's albedo at μ_v = s.walk_mu for each F₀ (Schlick per bounce), its first-bounce albedo against
    the height-correlated closed form, and every technique's W at the same F₀ (:func:`walk_reference`,
    :func:`walk_techniques`)."""
    return walk_reference(alpha, s, seed) | {"techniques": {t.name: walk_techniques(t, alpha, s, known)
                                                            for t in techs}}


def _e(alpha: float, mu: float) -> float:
    """The single-scattering GGX albedo table E(μ) at α (F = 1)."""
    t = tables("ggx", round(alpha, 6))
    return float(t.lookup(t.e, np.array([mu]))[0])


def metric(m: Measurements, tech: str, key: str, scale: float = 1.0) -> dict[str, float]:
    """max |scale·W − 1| over the grid ``key`` ('f0_1' or 'metal'), ± |Δ| between n and n/2 nodes."""
    v = np.max(np.abs(scale * np.asarray(m.w[tech][key]["value"]) - 1.0))
    h = np.max(np.abs(scale * np.asarray(m.w[tech][key]["half"]) - 1.0))
    return {"value": float(v), "uncertainty": float(abs(v - h))}


def metrics(m: Measurements, tech: str) -> dict[str, dict[str, float]]:
    out = {"furnace_error.f0_1": metric(m, tech, "f0_1")}
    if "metal" in m.w[tech]:
        out["furnace_error.metalness"] = metric(m, tech, "metal")
    if m.walk:
        err = [(abs(w["techniques"][tech][k] - w["albedo"][k]), w["albedo_se"][k]) for w in m.walk
               for k in range(len(w["f0s"])) if tech in w["techniques"]]
        if err:
            v, u = max(err)
            out["walk_albedo_error"] = {"value": v, "uncertainty": u}
    for f0 in m.settings.f0s:
        d = m.w[tech][f"f0_{f0:g}"]
        out[f"albedo.f0_{f0:g}"] = {"value": d["value"], "uncertainty": abs(d["value"] - d["half"])}
    return out


def bsdf_tasks(s: Settings, seed: int) -> list[Task]:
    """The BSDF checks of :func:`bsdf_checks` as independent tasks, each with its power check (a χ² power check
    reuses its case's expected counts): ("chi2", k, α, θ_i, seed), ("reciprocity", k, α, F₀, seed),
    ("furnace", k, α, μ_i, seed), ("render", k, α, seed); the seeds are those of the serial loop."""
    seed = seed % 2**20
    chi2 = [("chi2", k, a, th, seed + k) for k, (a, th) in enumerate(s.chi2_cases)]
    # the costliest χ² case first: the sharpest lobe quadruples its pdf walks the most (see MAX_PDF_VARIANCE_RATIO)
    chi2.sort(key=lambda t: t[2])
    recip = [("reciprocity", k, a, f0, seed + 100 + k)
             for k, (a, f0) in enumerate((a, f0) for a in s.walk_alphas for f0 in s.recip_f0s)]
    furnace = [("furnace", k, a, mu, seed + 200 + k)
               for k, (a, mu) in enumerate((a, mu) for a in s.walk_alphas for mu in s.furnace_mus)]
    render = [("render", k, a, seed + 300 + k) for k, a in enumerate(s.walk_alphas)]
    return chi2 + furnace + recip + render


def bsdf_task(task: Task, s: Settings) -> dict[str, Any]:
    """One task of :func:`bsdf_tasks` → its rows (the check and its power check)."""
    kind = task[0]
    if kind == "chi2":
        _, _, a, th, sd = task
        kw = {"samples": s.chi2_samples, "seed": sd, "res": s.chi2_res, "ires": 6, "walks": s.chi2_walks,
              "test_count": len(s.chi2_cases), "significance": FAMILY_WISE}
        row, kw = chi2_case(a, th, kw)
        return {"chi2": row, "chi2_power": mbsdf.chi2_walk(a, th, **kw, **CHI2_POWER)}
    if kind == "reciprocity":
        _, _, a, f0, sd = task
        return {"reciprocity": mbsdf.reciprocity_walk(a, f0, 64, s.recip_lanes, sd),
                "reciprocity_power": mbsdf.reciprocity_walk(a, f0, 64, s.recip_lanes, sd, **RECIP_POWER)}
    if kind == "furnace":
        _, _, a, mu, sd = task
        return {"furnace": mbsdf.furnace_eval(a, mu, 1.0, s.furnace_directions, 8, sd),
                "furnace_power": mbsdf.furnace_eval(a, mu, 1.0, s.furnace_directions, 8, sd, **RECIP_POWER)}
    _, _, a, sd = task
    return {"render": mbsdf.render_furnace(a, s.render_spp, 32, sd),
            "render_power": mbsdf.render_furnace(a, s.render_spp, 32, sd, max_order=1),
            "single_scatter": {**mbsdf.single_scatter_vs_mitsuba(a, 20_000, sd + 100),
                               "power": mbsdf.single_scatter_vs_mitsuba(a, 20_000, sd + 100, 1.01)["max_rel_diff"]}}


def bsdf_collect(done: list[tuple[Task, dict[str, Any]]]) -> dict[str, Any]:
    """The rows of :func:`bsdf_task` results in the serial order (by kind, then index k)."""
    out: dict[str, Any] = {"chi2": [], "chi2_power": [], "reciprocity": [], "reciprocity_power": [], "furnace": [],
                           "furnace_power": [], "render": [], "render_power": [], "single_scatter": []}
    for kind in ("chi2", "reciprocity", "furnace", "render"):
        for _, rows in sorted((tr for tr in done if tr[0][0] == kind), key=lambda tr: tr[0][1]):
            for key, row in rows.items():
                out[key].append(row)
    return out


def bsdf_checks(s: Settings, seed: int) -> dict[str, Any]:
    """The random walk as a Mitsuba BSDF (``microsurface_walk``), checked with Mitsuba's own machinery: χ² of
    sample vs pdf (each case also with the perturbed sampler), reciprocity z-scores of the one-sided eval (also
    with the non-reciprocal perturbation), eval's white furnace, a path-traced white furnace, and the closed first
    order against ``roughconductor``. Needs a JIT variant (Mitsuba's χ² harness and the walks' vectorised loops).
    Serially here; :func:`compute` runs the same :func:`bsdf_tasks` through ``ctx.map``."""
    return _bsdf_skipped() or bsdf_collect([(t, bsdf_task(t, s)) for t in bsdf_tasks(s, seed)])


def _bsdf_skipped() -> dict[str, Any] | None:
    """``{"skipped": why}`` on a variant without the JIT the BSDF checks need, else None."""
    backend = init()
    return None if backend.is_vectorized else {
        "skipped": f"{backend.variant}: the BSDF checks need a JIT variant (llvm/cuda)"}


__all__ = ["CHI2_POWER", "FAMILY_WISE", "RECIP_POWER", "Measurements", "bsdf_checks", "bsdf_tasks", "chi2_case",
           "compute", "metric", "metrics", "walk_compare"]

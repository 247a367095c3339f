"""Numbers of the ``worstcase`` experiment: linearity, certificates, their power, the searches."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...local_models import irradiance
from ...local_models.irradiance import sh
from ...local_models.irradiance.windowed_sh import kernel_bound, kernel_mean
from ..base import Context
from .certificate import LINEARITY_TOLERANCE, Certificate, certificate, crosstalk, delta_map, linearity_defect
from .errors import registered, worst_normal
from .lighting import write_probe
from .search import SearchResult, SearchSettings, search
from .settings import Settings

NAME = "worstcase"
GAIN = 1.02  # the power perturbation of a declared threshold: a 2 % gain error, either sign
L2_SCALE = 0.9  # sh9's power perturbation: its l = 2 band × 0.9 (× 1.1 happens to keep the sup at 3/32, at x = 1)


@dataclass
class Measurements:
    settings: Settings
    linearity: dict[str, dict[str, float]] = field(default_factory=dict)
    certificates: dict[str, dict[str, Certificate]] = field(default_factory=dict)
    sh9_power: dict[str, dict[str, float]] = field(default_factory=dict)
    threshold_power: dict[str, float] = field(default_factory=dict)
    searches: dict[str, dict[str, SearchResult]] = field(default_factory=dict)
    probes: dict[str, str] = field(default_factory=dict)
    thresholds: dict[str, dict[str, Any]] = field(default_factory=dict)


def _names(wanted: tuple[str, ...] | None, plugins: bool = False) -> list[str]:
    """Registered techniques named in ``wanted`` (None: all), plus every plug-in when ``plugins``."""
    return [t.name for t in irradiance if wanted is None or t.name in wanted or plugins and not t.builtin]


def sh9_perturbed(weights: tuple[float, float, float]) -> Any:
    """SH9 with band weights w_l (the power perturbation; w = (1, 1, 1) is sh9's eq. 8 form)."""
    w = np.array([weights[sh.degree_of(k)] for k in range(9)])[:, None]

    def fn(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
        return sh.render_irradiance(w * sh.project_environment(radiance, 2), normals, 2)
    return fn


def compute_linearity(m: Measurements, names: list[str], seed: int) -> None:
    for name in names:
        fn = registered(name)
        d, x = linearity_defect(fn, seed), crosstalk(fn)
        m.linearity[name] = {"defect": d, "crosstalk": x,
                             "linear": bool(d < LINEARITY_TOLERANCE and x < LINEARITY_TOLERANCE)}


def compute_certificates(ctx: Context, m: Measurements, s: Settings) -> None:
    means = set(_names(s.means))
    for name, lin in m.linearity.items():
        if not lin["linear"]:
            continue
        metrics = ["flux_luminance.max"] + (["flux_luminance.mean"] if name in means else [])
        fn, memo = registered(name), {}  # one function and memo: the metrics share the coarse sweep's calls
        m.certificates[name] = {met: certificate(fn, name, met, s.coarse, s.levels, memo) for met in metrics}
        cert = m.certificates[name]["flux_luminance.max"]
        path, rel = ctx.figure_path(NAME, f"certificate_{name}.exr")  # the worst light: a unit-flux texel delta
        write_probe(path, delta_map(cert.levels[-1][0], cert.texel))
        m.probes[f"{name}:certificate"] = rel
        m.thresholds[name] = dict(irradiance[name].thresholds)
        restricted = irradiance[name].meta.get("environments")
        if m.thresholds[name] and not restricted:
            m.threshold_power[name] = threshold_power(name, m.certificates[name]["flux_luminance.max"], s)


def threshold_power(name: str, cert: Certificate, s: Settings) -> float:
    """The certificate's worst light re-evaluated with the technique × 1.02 and × 0.98: the larger error (a lower
    bound of the perturbed certificate, enough to show the declared threshold would fail)."""
    h = cert.levels[-1][0]
    from .lighting import texel_geometry

    d, _ = texel_geometry(h)
    j = int(np.argmax(d @ np.asarray(cert.direction)))
    return max(worst_normal(registered(name, g), delta_map(h, j), "flux_luminance.max")[0] for g in (GAIN, 2 - GAIN))


def compute_sh9_power(m: Measurements, s: Settings) -> None:
    """Certificates of sh9's perturbations, measured against the closed form (kernel_bound / kernel_mean)."""
    if "sh9" not in m.certificates:
        return
    for label, w in ((f"l2 x {L2_SCALE}", (1.0, 1.0, L2_SCALE)), (f"E x {GAIN}", (GAIN,) * 3)):
        fn, memo = sh9_perturbed(w), {}
        mx = certificate(fn, label, "flux_luminance.max", s.coarse, s.power_levels, memo)
        mean = certificate(fn, label, "flux_luminance.mean", s.coarse, 1, memo)
        m.sh9_power[label] = {"max": mx.value, "max_predicted": kernel_bound(w), "mean": mean.value,
                              "mean_predicted": kernel_mean(w), "max_uncertainty": mx.uncertainty}


def compute_searches(ctx: Context, m: Measurements, s: Settings) -> None:
    ss = SearchSettings(height=s.search_height, normals=s.search_normals, budget=s.budget, restarts=s.restarts,
                        seed=ctx.seed)
    for name in _names(s.searched, plugins=True):
        m.searches[name] = {"flux_luminance.max": search(name, ss, "flux_luminance.max")}
        if name in s.relative:
            m.searches[name]["relative.max"] = search(name, ss, "relative.max", with_random=False)
        m.thresholds.setdefault(name, dict(irradiance[name].thresholds))
        for metric, res in m.searches[name].items():
            path, rel = ctx.figure_path(NAME, f"worst_{name}_{metric.replace('.', '_')}.exr")
            write_probe(path, res.radiance)
            m.probes[f"{name}:{metric}"] = rel


def compute(ctx: Context, s: Settings) -> Measurements:
    m = Measurements(s)
    names = sorted(set(_names(s.linear, plugins=True)) | set(_names(s.searched, plugins=True)), key=_names(None).index)
    compute_linearity(m, names, ctx.seed)
    compute_certificates(ctx, m, s)
    compute_sh9_power(m, s)
    compute_searches(ctx, m, s)
    return m

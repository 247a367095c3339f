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
from .search import SearchResult, SearchSettings, has_ad, search
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


def linearity(name: str, seed: int) -> dict[str, Any]:
    """Linearity defect and channel crosstalk of one technique (:mod:`.certificate`), and whether both are below
    :data:`~.certificate.LINEARITY_TOLERANCE`."""
    fn = registered(name)
    d, x = linearity_defect(fn, seed), crosstalk(fn)
    return {"defect": d, "crosstalk": x, "linear": bool(d < LINEARITY_TOLERANCE and x < LINEARITY_TOLERANCE)}


def certificates(name: str, s: Settings) -> dict[str, Certificate]:
    """The certificates of a linear technique: ``flux_luminance.max`` (and ``.mean`` for :attr:`Settings.means`),
    one function and memo (the metrics share the coarse sweep's calls)."""
    metrics = ["flux_luminance.max"] + (["flux_luminance.mean"] if name in set(_names(s.means)) else [])
    fn, memo = registered(name), {}
    return {met: certificate(fn, name, met, s.coarse, s.levels, memo) for met in metrics}


def _has_threshold_power(name: str) -> bool:
    """A declared threshold checked against the certificate, on every environment (not a restricted set)."""
    return bool(irradiance[name].thresholds) and not irradiance[name].meta.get("environments")


def _record_certificates(ctx: Context, m: Measurements, name: str, certs: dict[str, Certificate],
                         power: float | None) -> None:
    """Store a technique's certificates, write its worst light (a unit-flux texel delta) as an EXR probe."""
    m.certificates[name] = certs
    cert = certs["flux_luminance.max"]
    path, rel = ctx.figure_path(NAME, f"certificate_{name}.exr")
    write_probe(path, delta_map(cert.levels[-1][0], cert.texel))
    m.probes[f"{name}:certificate"] = rel
    m.thresholds[name] = dict(irradiance[name].thresholds)
    if power is not None:
        m.threshold_power[name] = power


def threshold_power(name: str, cert: Certificate, s: Settings) -> float:
    """The certificate's worst light re-evaluated with the technique × 1.02 and × 0.98: the larger error (a lower
    bound of the perturbed certificate, enough to show the declared threshold would fail)."""
    h = cert.levels[-1][0]
    from .lighting import texel_geometry

    d, _ = texel_geometry(h)
    j = int(np.argmax(d @ np.asarray(cert.direction)))
    return max(worst_normal(registered(name, g), delta_map(h, j), "flux_luminance.max")[0] for g in (GAIN, 2 - GAIN))


def sh9_power(s: Settings) -> dict[str, dict[str, float]]:
    """Certificates of sh9's perturbations, measured against the closed form (kernel_bound / kernel_mean)."""
    out = {}
    for label, w in ((f"l2 x {L2_SCALE}", (1.0, 1.0, L2_SCALE)), (f"E x {GAIN}", (GAIN,) * 3)):
        fn, memo = sh9_perturbed(w), {}
        mx = certificate(fn, label, "flux_luminance.max", s.coarse, s.power_levels, memo)
        mean = certificate(fn, label, "flux_luminance.mean", s.coarse, 1, memo)
        out[label] = {"max": mx.value, "max_predicted": kernel_bound(w), "mean": mean.value,
                      "mean_predicted": kernel_mean(w), "max_uncertainty": mx.uncertainty}
    return out


def _search_settings(ctx: Context, s: Settings) -> SearchSettings:
    return SearchSettings(height=s.search_height, normals=s.search_normals, budget=s.budget, restarts=s.restarts,
                          seed=ctx.seed)


def _searches(s: Settings) -> list[tuple[str, str, bool]]:
    """(technique, metric, with random search) of every search, in the report's order."""
    out = []
    for name in _names(s.searched, plugins=True):
        out.append((name, "flux_luminance.max", True))
        if name in s.relative:
            out.append((name, "relative.max", False))
    return out


def _record_search(ctx: Context, m: Measurements, name: str, metric: str, res: SearchResult) -> None:
    """Store a search's result and write its worst lighting as an EXR probe."""
    m.searches.setdefault(name, {})[metric] = res
    m.thresholds.setdefault(name, dict(irradiance[name].thresholds))
    path, rel = ctx.figure_path(NAME, f"worst_{name}_{metric.replace('.', '_')}.exr")
    write_probe(path, res.radiance)
    m.probes[f"{name}:{metric}"] = rel


Task = tuple[Any, ...]


def _task(task: Task, s: Settings, ss: SearchSettings, seed: int) -> Any:
    """One independent piece of :func:`compute`, as a function of its task tuple alone (seeds from ``seed`` and
    the task): ``("technique", name)`` → (linearity, certificates or None, threshold power or None);
    ``("sh9_power",)`` → :func:`sh9_power`; ``("search", name, metric, with_random)`` → :class:`SearchResult`."""
    kind = task[0]
    if kind == "technique":
        name = task[1]
        lin = linearity(name, seed)
        if not lin["linear"]:
            return lin, None, None
        certs = certificates(name, s)
        power = threshold_power(name, certs["flux_luminance.max"], s) if _has_threshold_power(name) else None
        return lin, certs, power
    if kind == "sh9_power":
        return sh9_power(s)
    _, name, metric, with_random = task
    return search(name, ss, metric, with_random=with_random)


def _cost(task: Task) -> int:
    """Scheduling rank (lower first, costliest first on the workers; measured CPU on the full settings): SPSA
    searches through engines, then drjit-AD searches, then the certificates; the numbers do not depend on it."""
    if task[0] == "search":
        return 0 if not has_ad(task[1]) else 1
    return 2 if task[0] == "sh9_power" else 3


def compute(ctx: Context, s: Settings) -> Measurements:
    """Linearity and certificates per technique, sh9's perturbed certificates and the searches: independent tasks
    (``ctx.map``, costliest first), recorded in the serial order (the same dicts, keys and numbers)."""
    m = Measurements(s)
    names = sorted(set(_names(s.linear, plugins=True)) | set(_names(s.searched, plugins=True)), key=_names(None).index)
    ss = _search_settings(ctx, s)
    tasks: list[Task] = [("technique", n) for n in names] + ([("sh9_power",)] if "sh9" in names else [])
    tasks += [("search", *t) for t in _searches(s)]
    order = sorted(range(len(tasks)), key=lambda k: _cost(tasks[k]))
    seed = ctx.seed
    done = ctx.map(lambda t: _task(t, s, ss, seed), [tasks[k] for k in order], "worstcase: certificates, searches")
    results = dict(zip((tasks[k] for k in order), done, strict=True))
    for name in names:
        m.linearity[name] = results[("technique", name)][0]
    for name in names:
        lin, certs, power = results[("technique", name)]
        if certs is not None:
            _record_certificates(ctx, m, name, certs, power)
    if "sh9" in m.certificates:
        m.sh9_power = results[("sh9_power",)]
    for name, metric, with_random in _searches(s):
        _record_search(ctx, m, name, metric, results[("search", name, metric, with_random)])
    return m

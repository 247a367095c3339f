"""Findings and report sections of the ``worstcase`` experiment (figures of the worst lights)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...figures import plots
from ...local_models import irradiance
from ...scenes.latlong import direction_to_spherical
from ...stats import Measured
from ..base import Context, Figure, Section, Table
from ..formatting import pct
from ..techniques import technique_entry
from .compute import NAME, Measurements
from .lighting import LUMINANCE


def pct4(x: float) -> str:
    """A fraction as per cent, 4 significant digits."""
    return pct(x, 4)


def findings(m: Measurements) -> list[str]:
    out = []
    for name, cert in m.certificates.items():
        c = cert["flux_luminance.max"]
        th, ph = direction_to_spherical(np.asarray(c.direction))
        out.append(f"{name}: certificate max_n |E′ − E| / Φ ≤ {pct4(c.value)} ± {pct4(c.uncertainty)} for any "
                   f"non-negative lighting (worst light at θ = {np.degrees(th):.1f}°, φ = {np.degrees(ph):.1f}°; "
                   f"levels {', '.join(f'H={h}: {pct4(v)}' for h, v in c.levels)})")
    for name, res in m.searches.items():
        for metric, r in res.items():
            out.append(f"{name}: search ({r.method}) {metric} = {pct4(r.value)} ± {pct4(r.uncertainty)} "
                       f"(restarts {', '.join(pct4(v) for v in r.restart_values)}; random search "
                       f"{pct4(r.random_value)}; {r.evaluations} evaluations, {r.wall_s:.1f} s; probe "
                       f"{m.probes.get(name + ':' + metric, '')}); the lighting: {r.lighting}")
    for name, res in m.searches.items():
        r = res["flux_luminance.max"]
        if name in m.certificates and not r.method.startswith("drjit"):
            cert = m.certificates[name]["flux_luminance.max"].at(m.settings.search_height)
            out.append(f"{name}: the gradient-free search ({r.method}) reached {pct4(r.value / cert)} of the "
                       f"certificate {pct4(cert)} at H = {m.settings.search_height}")
    for name, lim in m.thresholds.items():
        r = m.searches.get(name, {}).get("flux_luminance.max")
        from ...local_models import irradiance

        env = irradiance[name].meta.get("environments")
        for metric, limit in lim.items():
            if env and r is not None:
                verdict = "exceeds" if r.value > limit else "stays within"
                out.append(f"{name}: the worst lighting found ({pct4(r.value)}) {verdict} its declared {metric} < "
                           f"{pct4(limit)}, which is declared for {', '.join(env)} only (not a claim here)")
    return out


def _figure(m: Measurements, ctx: Context, name: str) -> Figure:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure as MplFigure

    c = m.certificates[name]["flux_luminance.max"]
    normals, e = c.errors_over_normals
    th, ph = direction_to_spherical(normals)
    path, rel = ctx.figure_path(NAME, f"certificate_{name}.png")
    fig = MplFigure(figsize=(6, 3))  # no pyplot: no global figure state (an experiment may run beside this one)
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    sc = ax.scatter(np.degrees(ph), np.degrees(th), c=100 * e, s=6, cmap="magma")
    lt, lp = direction_to_spherical(np.asarray(c.direction))
    ax.plot(np.degrees(lp), np.degrees(lt), "c*", ms=12, label="worst light")
    ax.set_xlabel("normal φ (°)")
    ax.set_ylabel("normal θ (°)")
    ax.invert_yaxis()
    ax.legend(loc="lower right", fontsize=7)
    fig.colorbar(sc, ax=ax, label="|E′ − E| / Φ (%)")
    ax.set_title(f"{name}: error over normals, worst light")
    with plots.FIGURE_LOCK:
        fig.tight_layout()
        fig.savefig(path, dpi=90, pil_kwargs={"compress_level": plots.PNG_COMPRESS_LEVEL})
    return Figure(rel, f"{name}: |E′ − E| / Φ over normals for the certificate's worst light (a unit-flux delta)")


def sections(m: Measurements, ctx: Context) -> list[Section]:
    lin = Table(["technique", "linearity defect / Φ (–)", "channel crosstalk / Φ (–)", "linear?"],
                [[n, f"{v['defect']:.3g}", f"{v['crosstalk']:.3g}", "yes" if v["linear"] else "no"]
                 for n, v in m.linearity.items()], "f(aL₁ + bL₂) vs a f(L₁) + b f(L₂), random HDR maps + sun/sky")
    cert = Table(["technique", "certificate, max (%)", "± (%)", "levels (%)", "mean certificate (%)"],
                 [[n, pct4(c["flux_luminance.max"].value), pct4(c["flux_luminance.max"].uncertainty),
                   "; ".join(f"H={h}: {pct4(v)}" for h, v in c["flux_luminance.max"].levels),
                   pct4(c["flux_luminance.mean"].value) if "flux_luminance.mean" in c else "—"]
                  for n, c in m.certificates.items()], "sup over all non-negative lighting, flux-normalised")
    srch = Table(["technique", "metric", "method", "worst found (%)", "± 2H (%)", "restarts (%)", "random search (%)",
                  "probe"],
                 [[n, r.metric, r.method, pct4(r.value), pct4(r.uncertainty),
                   ", ".join(pct4(v) for v in r.restart_values),
                   pct4(r.random_value) if r.random_value == r.random_value else "—", m.probes.get(f"{n}:{met}", "")]
                  for n, res in m.searches.items() for met, r in res.items()], "differentiable / SPSA search")
    figs = [_figure(m, ctx, n) for n in m.certificates]
    return [Section("Worst case for any lighting", findings(m), figs, [lin, cert, srch])]


def data(m: Measurements) -> dict[str, Any]:
    """results.json data: linearity, certificates, power checks, searches and the probes written."""
    return {"linearity": m.linearity,
            "certificates": {n: {k: c.to_json() for k, c in v.items()} for n, v in m.certificates.items()},
            "sh9_power": m.sh9_power, "threshold_power": m.threshold_power,
            "searches": {n: {k: r.to_json() for k, r in v.items()} for n, v in m.searches.items()},
            "probes": m.probes,
            "worst_lighting": {n: lighting_map(r["flux_luminance.max"].radiance)
                               for n, r in m.searches.items() if "flux_luminance.max" in r}}


MAP_HEIGHT = 16  # rows of the worst lighting's thumbnail in results.json (2 × as many columns)


def lighting_map(radiance: np.ndarray, height: int = MAP_HEIGHT) -> dict[str, Any]:
    """The worst lighting found, for the report's thumbnail: its luminance on an equirect map (rows θ = 0 … π
    from +y, columns φ = 0 … 2π; :mod:`validate.scenes.latlong`), box-averaged down to ``height`` rows when the
    map's height is a multiple of it, divided by its largest texel and written to 3 significant digits."""
    lum = np.asarray(radiance, dtype=np.float64) @ np.asarray(LUMINANCE)
    h = lum.shape[0]
    if h > height and h % height == 0:
        k = h // height
        lum = lum.reshape(height, k, lum.shape[1] // k, k).mean(axis=(1, 3))
    top = float(lum.max()) if lum.size and np.isfinite(lum).all() else 0.0
    rel = lum / top if top > 0 else np.zeros_like(lum)
    return {"height": int(rel.shape[0]), "width": int(rel.shape[1]), "scale": "luminance / its largest texel",
            "luminance": [[float(f"{v:.3g}") for v in row] for row in rel]}


def techniques(m: Measurements) -> dict[str, Any]:
    """results.json entries: linearity defect, certificates and worst errors found, per technique (fractions of
    the flux; a certificate's and a search's uncertainty is the quadrature's, |e(2H) − e(H)|)."""
    out = {}
    for name, lin in m.linearity.items():
        metrics: dict[str, Measured] = {"linearity_defect": Measured(lin["defect"], unit="%")}
        for metric, c in m.certificates.get(name, {}).items():
            metrics[f"certificate.{metric}"] = Measured(c.value, c.uncertainty, unit="%", stat=_stat(metric))
        for metric, r in m.searches.get(name, {}).items():
            metrics[f"search.{metric}"] = Measured(r.value, r.uncertainty, unit="%", stat=_stat(metric))
        out[name] = technique_entry(irradiance[name], metrics, linear=lin["linear"])
    return out


def _stat(metric: str) -> str:
    """The statistic over normals a worst-case metric names (``flux_luminance.max`` → "max")."""
    return metric.rsplit(".", 1)[-1]

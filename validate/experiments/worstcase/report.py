"""Findings and report sections of the ``worstcase`` experiment (figures of the worst lights)."""

from __future__ import annotations

import numpy as np

from ...scenes.latlong import direction_to_spherical
from ..base import Context, Figure, Section, Table
from .compute import NAME, Measurements


def _pct(x: float) -> str:
    return f"{100 * x:.4g} %"


def findings(m: Measurements) -> list[str]:
    out = []
    for name, cert in m.certificates.items():
        c = cert["flux_luminance.max"]
        th, ph = direction_to_spherical(np.asarray(c.direction))
        out.append(f"{name}: certificate max_n |E′ − E| / Φ ≤ {_pct(c.value)} ± {_pct(c.uncertainty)} for any "
                   f"non-negative lighting (worst light at θ = {np.degrees(th):.1f}°, φ = {np.degrees(ph):.1f}°; "
                   f"levels {', '.join(f'H={h}: {_pct(v)}' for h, v in c.levels)})")
    for name, res in m.searches.items():
        for metric, r in res.items():
            out.append(f"{name}: search ({r.method}) {metric} = {_pct(r.value)} ± {_pct(r.uncertainty)} "
                       f"(restarts {', '.join(_pct(v) for v in r.restart_values)}; random search "
                       f"{_pct(r.random_value)}; {r.evaluations} evaluations, {r.wall_s:.1f} s; probe "
                       f"{m.probes.get(name + ':' + metric, '')}); the lighting: {r.lighting}")
    for name, res in m.searches.items():
        r = res["flux_luminance.max"]
        if name in m.certificates and not r.method.startswith("drjit"):
            cert = m.certificates[name]["flux_luminance.max"].at(m.settings.search_height)
            out.append(f"{name}: the gradient-free search ({r.method}) reached {_pct(r.value / cert)} of the "
                       f"certificate {_pct(cert)} at H = {m.settings.search_height}")
    for name, lim in m.thresholds.items():
        r = m.searches.get(name, {}).get("flux_luminance.max")
        from ...local_models import irradiance

        env = irradiance[name].meta.get("environments")
        for metric, limit in lim.items():
            if env and r is not None:
                verdict = "exceeds" if r.value > limit else "stays within"
                out.append(f"{name}: the worst lighting found ({_pct(r.value)}) {verdict} its declared {metric} < "
                           f"{_pct(limit)}, which is declared for {', '.join(env)} only (not a claim here)")
    return out


def _figure(m: Measurements, ctx: Context, name: str) -> Figure:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = m.certificates[name]["flux_luminance.max"]
    normals, e = c.errors_over_normals
    th, ph = direction_to_spherical(normals)
    path, rel = ctx.figure_path(NAME, f"certificate_{name}.png")
    fig, ax = plt.subplots(figsize=(6, 3))
    sc = ax.scatter(np.degrees(ph), np.degrees(th), c=100 * e, s=6, cmap="magma")
    lt, lp = direction_to_spherical(np.asarray(c.direction))
    ax.plot(np.degrees(lp), np.degrees(lt), "c*", ms=12, label="worst light")
    ax.set_xlabel("normal φ (°)")
    ax.set_ylabel("normal θ (°)")
    ax.invert_yaxis()
    ax.legend(loc="lower right", fontsize=7)
    fig.colorbar(sc, ax=ax, label="|E′ − E| / Φ (%)")
    ax.set_title(f"{name}: error over normals, worst light")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return Figure(rel, f"{name}: |E′ − E| / Φ over normals for the certificate's worst light (a unit-flux delta)")


def sections(m: Measurements, ctx: Context) -> list[Section]:
    lin = Table(["technique", "linearity defect / Φ", "channel crosstalk / Φ", "linear"],
                [[n, f"{v['defect']:.3g}", f"{v['crosstalk']:.3g}", "yes" if v["linear"] else "no"]
                 for n, v in m.linearity.items()], "f(aL₁ + bL₂) vs a f(L₁) + b f(L₂), random HDR maps + sun/sky")
    cert = Table(["technique", "certificate (max)", "±", "levels", "mean certificate"],
                 [[n, _pct(c["flux_luminance.max"].value), _pct(c["flux_luminance.max"].uncertainty),
                   "; ".join(f"H={h}: {_pct(v)}" for h, v in c["flux_luminance.max"].levels),
                   _pct(c["flux_luminance.mean"].value) if "flux_luminance.mean" in c else "—"]
                  for n, c in m.certificates.items()], "sup over all non-negative lighting, flux-normalised")
    srch = Table(["technique", "metric", "method", "worst found", "± (2H)", "restarts", "random search", "probe"],
                 [[n, r.metric, r.method, _pct(r.value), _pct(r.uncertainty),
                   ", ".join(_pct(v) for v in r.restart_values),
                   _pct(r.random_value) if r.random_value == r.random_value else "—", m.probes.get(f"{n}:{met}", "")]
                  for n, res in m.searches.items() for met, r in res.items()], "differentiable / SPSA search")
    figs = [_figure(m, ctx, n) for n in m.certificates]
    return [Section("Worst case for any lighting", findings(m), figs, [lin, cert, srch])]

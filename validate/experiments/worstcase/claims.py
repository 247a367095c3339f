"""Claims of the ``worstcase`` experiment, each with its power check."""

from __future__ import annotations

from ...local_models import irradiance
from ...metrics.irradiance_error import WORST_CASE_MAX, directional_worst_case_mean
from ..base import Claim
from .certificate import LINEARITY_TOLERANCE
from .compute import GAIN, L2_SCALE, Measurements

EXPECTED_NONLINEAR = ("zh3_hallucinated", "sh1_geomerics", "sh9_cmgen_auto", "babylon_sh")
# the certificate reproduces R&H's constants to: the 6-digit c1…c5 of eq. 12 (10⁻⁶ relative), float32 sums,
# the pattern search's last radius (< 10⁻⁵, .errors) and, for the mean, the 4096-normal Fibonacci mean
# (error ~ 1/N ≈ 2.5·10⁻⁴ of the mean's range 0…3/32, measured 2.5·10⁻⁶): 10⁻⁴ absolute.
RH_TOLERANCE = 1e-4
SEARCH_FRACTION = 0.99  # issue 22: the search reaches ≥ 99 % of the certificate from random starts
RH_SOURCE = "R&H JOSA 2001 / SIGGRAPH 2001: order-2 clamped cosine 3/32 + x/2 + 15x²/32, max error 3/32 Φ (x = 0)"


def linearity_claims(m: Measurements) -> list[Claim]:
    out = []
    for name, lin in m.linearity.items():
        if name == "sh9":
            c = Claim("worstcase.linearity.sh9", "sh9 is linear in the lighting (R&H eq. 8 is a linear map)",
                      "max |f(aL1+bL2) − a f(L1) − b f(L2)| / Φ", LINEARITY_TOLERANCE, lin["defect"], 0.0, "<", "",
                      "SH projection and evaluation are linear; float32 rounding ≤ 2e-6 Φ measured")
            out.append(c.with_power("the defect of a technique known nonlinear (zh3_hallucinated)",
                                    m.linearity.get("zh3_hallucinated", {"defect": float("nan")})["defect"]))
        if name in EXPECTED_NONLINEAR:
            c = Claim(f"worstcase.linearity.{name}", f"{name} is detected as nonlinear (not given a certificate)",
                      "linearity defect / Φ", LINEARITY_TOLERANCE, lin["defect"], 0.0, ">", "",
                      "nonlinear by construction: a per-map axis (ZH3), a power q^p with p from the map "
                      "(Geomerics), a per-map window (cmgen auto), a radiance clamp at 4096 (Babylon)")
            out.append(c.with_power("the defect of sh9 (linear)", m.linearity.get("sh9", {"defect": 0.0})["defect"]))
    return out


def sh9_claims(m: Measurements) -> list[Claim]:
    if "sh9" not in m.certificates:
        return []
    cert = m.certificates["sh9"]
    mx = cert["flux_luminance.max"]
    out = [Claim("worstcase.certificate.sh9.max", "sh9's certificate (sup over all non-negative lighting of "
                 "max_n |E′ − E| / Φ) equals 3/32", "|certificate − 3/32|", RH_TOLERANCE,
                 abs(mx.value - WORST_CASE_MAX), mx.uncertainty, "<", "", RH_SOURCE)]
    p = m.sh9_power.get(f"l2 x {L2_SCALE}")
    if p:
        out[-1].with_power(f"sh9 with its l = 2 band × {L2_SCALE}", abs(p["max"] - WORST_CASE_MAX))
    if "flux_luminance.mean" in cert:
        mean, target = cert["flux_luminance.mean"], directional_worst_case_mean()
        c = Claim("worstcase.certificate.sh9.mean", "sh9's mean-error certificate equals R&H's ½∫|K̃ − max(0, x)| dx",
                  "|certificate − 0.030674|", RH_TOLERANCE, abs(mean.value - target), 0.0, "<", "", RH_SOURCE)
        pg = m.sh9_power.get(f"l2 x {L2_SCALE}")
        out.append(c.with_power(f"sh9 with its l = 2 band × {L2_SCALE}", abs(pg["mean"] - target)) if pg else c)
    for label, p in m.sh9_power.items():
        c = Claim(f"worstcase.certificate.power.{label.replace(' ', '')}",
                  f"perturbing sh9 ({label}) moves the certificate by the closed-form amount",
                  "|measured − predicted certificate|", RH_TOLERANCE, abs(p["max"] - p["max_predicted"]),
                  p["max_uncertainty"], "<", "", "closed form sup|Σ w_l A_l (2l+1)/4π P_l − max(0, x)| "
                  "(validate.local_models.windowed_sh.kernel_bound)")
        out.append(c.with_power("the unperturbed certificate against the perturbed prediction",
                                abs(mx.value - p["max_predicted"])))
    return out


def threshold_claims(m: Measurements) -> list[Claim]:
    out = []
    for name, cert in m.certificates.items():
        for metric, limit in m.thresholds.get(name, {}).items():
            if irradiance[name].meta.get("environments") or not metric.endswith(".max"):
                continue
            c = Claim(f"worstcase.certificate.{name}.{metric}", f"{name}'s declared {metric} holds for every "
                      f"non-negative lighting (its certificate; worst light: probe "
                      f"{m.probes.get(name + ':certificate', '')})", metric, limit, cert["flux_luminance.max"].value,
                      cert["flux_luminance.max"].uncertainty, "<", "%", irradiance[name].source or "declared")
            if name in m.threshold_power:
                c.with_power(f"{name} × {GAIN} or × {2 - GAIN} (a 2 % gain error)", m.threshold_power[name])
            out.append(c)
    return out


def search_claims(m: Measurements) -> list[Claim]:
    out = []
    for name, res in m.searches.items():
        r = res["flux_luminance.max"]
        if name in m.certificates and r.method.startswith("drjit"):  # SPSA's ratio is a finding (report.py)
            cert = m.certificates[name]["flux_luminance.max"].at(m.settings.search_height)
            c = Claim(f"worstcase.search.{name}.reaches_certificate", f"the search on {name} reaches ≥ 99 % of its "
                      "certificate from random starts", "search / certificate", SEARCH_FRACTION, r.value / cert,
                      r.uncertainty / cert, ">", "%", "the certificate of the same map resolution (exact sup over "
                      "non-negative maps, validate.experiments.worstcase.certificate); 99 %: the search's target")
            out.append(c.with_power("random search, same budget, no gradients", r.random_value / cert))
        for metric, limit in m.thresholds.get(name, {}).items():
            # flux_luminance ≤ flux_rgb (a Y-weighted mean of the per-channel ratios), so the search's
            # flux_luminance value is a lower bound of a declared flux_rgb limit's metric
            if irradiance[name].meta.get("environments") or metric not in ("flux_rgb.max", "flux_luminance.max"):
                continue
            c = Claim(f"worstcase.search.{name}.{metric}", f"{name}'s declared {metric} holds on the worst lighting "
                      f"found (probe {m.probes.get(name + ':' + r.metric, '')})", metric, limit, r.value,
                      r.uncertainty, "<", "%", irradiance[name].source or "declared")
            out.append(c.with_power(f"{name} × {GAIN}", r.value * GAIN))
    return out


def claims(m: Measurements) -> list[Claim]:
    return linearity_claims(m) + sh9_claims(m) + threshold_claims(m) + search_claims(m)

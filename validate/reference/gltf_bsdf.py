"""glTF 2.0 metallic-roughness exactly as specified, as a Mitsuba 3 BSDF (``gltf_metallic_roughness``).

[1] Khronos, glTF 2.0 Specification, Appendix B "BRDF Implementation": B.2.1 (metal_brdf, dielectric_brdf, material
    = mix(dielectric_brdf, metal_brdf, metallic)), B.3.1 (fresnel_mix, conductor_fresnel with Schlick's F), B.3.2
    (specular_brdf = V·D: Trowbridge–Reitz / GGX D with α = roughness², Smith height-correlated V), B.3.4
    (diffuse_brdf = baseColor/π), B.3.5 (ior 1.5 → F₀ = ((1 − ior)/(1 + ior))² = 0.04).
[2] E. Heitz, "Understanding the masking-shadowing function in microfacet-based BRDFs", JCGT 3(2) 2014: the
    height-correlated G₂ = 1/(1 + Λ(ω_i) + Λ(ω_o)), V = G₂/(4 μ_i μ_o) (the form B.3.2 writes out).
[3] W. Jakob et al., Mitsuba 3: ``MicrofacetDistribution`` (GGX visible-normal sampling, its pdf) and
    ``mitsuba.chi2`` (``ChiSquareTest``, ``BSDFAdapter``).

Local frame n = +z, ω_i = ``si.wi`` (toward the viewer, V), ω_o (toward the light, L), H = normalise(ω_i + ω_o),
μ = cos θ. With α = roughness² (clamped to ``ALPHA_MIN``):

    D(H)   = α² / (π ((N·H)²(α² − 1) + 1)²)
    V      = ½ / ((N·L) √((N·V)²(1 − α²) + α²) + (N·V) √((N·L)²(1 − α²) + α²))            [1 B.3.2, 2]
    specular_brdf = V D
    F(f₀)  = f₀ + (1 − f₀)(1 − |V·H|)⁵                                                         [1 B.3.1]
    dielectric = (1 − F(0.04)) baseColor/π + F(0.04) V D
    metal      = F(baseColor) V D
    f      = (1 − metallic) dielectric + metallic metal

``eval`` returns f μ_o (Mitsuba's convention). ``sample``: a one-sample mixture of a cosine-weighted lobe
(probability p_d = ½ (1 − metallic)) and GGX visible normals for ω_i reflected about them (1 − p_d) [3], with

    pdf(ω_o) = p_d μ_o/π + (1 − p_d) D_{ω_i}(H)/(4 |ω_i·H|),   D_{ω_i}(H) = G₁(ω_i) max(0, ω_i·H) D(H)/μ_i,

and weight f μ_o / pdf. ``pdf`` returns the same mixture density.

Properties: ``base_r``, ``base_g``, ``base_b`` (baseColor, linear, each in [0, 1]), ``metallic`` ∈ [0, 1],
``roughness`` ∈ [0, 1]; power-check perturbations only, never in a reference: ``dielectric_f0`` (default 0.04 =
ior 1.5), ``sample_alpha_scale`` (α × s in ``sample`` but not in ``eval``/``pdf``: a sampler that disagrees
with its density).
"""

from __future__ import annotations

import math
from typing import Any

from ..backend import init
from ..errors import ValidateError

PLUGIN = "gltf_metallic_roughness"
DIELECTRIC_F0 = 0.04  # [1 B.3.5]: ior 1.5 → ((1 − 1.5)/(1 + 1.5))²
ALPHA_MIN = 1e-4  # as validate.scenes.render_scenes.mitsuba_bsdf clamps α = roughness² (a mirror is a delta)
_REGISTERED = False


# ---------------------------------------------------------------- the formulas (drjit, any variant)

def ggx_d(nh: Any, alpha: Any) -> Any:
    """Trowbridge–Reitz / GGX D(H) = α²/(π ((N·H)²(α² − 1) + 1)²) for N·H > 0 [1 B.3.2]."""
    import drjit as dr

    t = nh * nh * (alpha * alpha - 1.0) + 1.0
    return dr.select(nh > 0.0, alpha * alpha / (dr.pi * t * t), 0.0)


def smith_v_height_correlated(nl: Any, nv: Any, alpha: Any) -> Any:
    """V = ½ / (N·L √((N·V)²(1 − α²) + α²) + N·V √((N·L)²(1 − α²) + α²)) [1 B.3.2], = G₂/(4 μ_i μ_o) [2]."""
    import drjit as dr

    a2 = alpha * alpha
    den = nl * dr.sqrt(nv * nv * (1.0 - a2) + a2) + nv * dr.sqrt(nl * nl * (1.0 - a2) + a2)
    return dr.select((nl > 0.0) & (nv > 0.0), 0.5 / dr.maximum(den, 1e-30), 0.0)


def schlick_f(f0: Any, vh: Any) -> Any:
    """F = f₀ + (1 − f₀)(1 − |V·H|)⁵ [1 B.3.1]."""
    import drjit as dr

    x = 1.0 - dr.clip(dr.abs(vh), 0.0, 1.0)
    x2 = x * x
    return f0 + (1.0 - f0) * x2 * x2 * x


def gltf_brdf_cos(wi: Any, wo: Any, base: Any, metallic: Any, alpha: Any, f0_dielectric: Any = DIELECTRIC_F0) -> Any:
    """f(ω_i, ω_o) μ_o of the module docstring (a Spectrum when ``base`` is one); 0 unless both above the surface."""
    import drjit as dr

    h = dr.normalize(wi + wo)
    vh = dr.dot(wi, h)
    spec = smith_v_height_correlated(wo.z, wi.z, alpha) * ggx_d(h.z, alpha)
    fd = schlick_f(f0_dielectric, vh)
    dielectric = (1.0 - fd) * base * dr.inv_pi + fd * spec
    metal = schlick_f(base, vh) * spec
    f = (1.0 - metallic) * dielectric + metallic * metal
    return dr.select((wi.z > 0.0) & (wo.z > 0.0), f * wo.z, 0.0)


def diffuse_probability(metallic: float) -> float:
    """p_d = ½ (1 − metallic): the cosine lobe's share of ``sample`` (module docstring)."""
    return 0.5 * (1.0 - metallic)


def mixture_pdf(wi: Any, wo: Any, alpha: Any, p_d: float) -> Any:
    """p_d μ_o/π + (1 − p_d) D_{ω_i}(H)/(4 |ω_i·H|) with Mitsuba's visible-normal GGX density [3]."""
    import drjit as dr
    import mitsuba as mi

    md = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, alpha, True)
    h = dr.normalize(wi + wo)
    vh = dr.dot(wi, h)
    spec = md.pdf(wi, h) / (4.0 * dr.maximum(dr.abs(vh), 1e-30))
    p = p_d * wo.z * dr.inv_pi + (1.0 - p_d) * dr.select(vh > 0.0, spec, 0.0)
    return dr.select((wi.z > 0.0) & (wo.z > 0.0), p, 0.0)


# ---------------------------------------------------------------- the plug-in

def _props(props: Any) -> dict[str, Any]:
    """The plug-in's properties, checked (one-line ValidateError naming the accepted ranges)."""
    base = [float(props.get(f"base_{c}", 1.0)) for c in "rgb"]
    p = {"base_color": base, "metallic": float(props.get("metallic", 0.0)),
         "roughness": float(props.get("roughness", 0.5)),
         "dielectric_f0": float(props.get("dielectric_f0", DIELECTRIC_F0)),
         "sample_alpha_scale": float(props.get("sample_alpha_scale", 1.0))}
    if not (len(base) == 3 and all(0.0 <= b <= 1.0 for b in base) and 0.0 <= p["metallic"] <= 1.0
            and 0.0 <= p["roughness"] <= 1.0 and 0.0 <= p["dielectric_f0"] <= 1.0
            and math.isfinite(p["sample_alpha_scale"]) and p["sample_alpha_scale"] > 0.0):
        raise ValidateError(f"{PLUGIN}: base_color={base}, metallic={p['metallic']}, roughness={p['roughness']}, "
                            f"dielectric_f0={p['dielectric_f0']}: expected base_color of 3 values in [0, 1], "
                            "metallic, roughness and dielectric_f0 in [0, 1], sample_alpha_scale > 0")
    p["alpha"] = max(p["roughness"] ** 2, ALPHA_MIN)
    return p


def register() -> str:
    """Register ``gltf_metallic_roughness`` with Mitsuba (once per process) and return its name."""
    global _REGISTERED
    init()
    if _REGISTERED:
        return PLUGIN
    import mitsuba as mi

    mi.register_bsdf(PLUGIN, lambda props: _plugin_class()(props))
    _REGISTERED = True
    return PLUGIN


def _plugin_class() -> type:
    import drjit as dr
    import mitsuba as mi

    class GltfMetallicRoughness(mi.BSDF):
        """glTF 2.0 metallic-roughness (module docstring)."""

        def __init__(self, props: Any) -> None:
            super().__init__(props)
            self.p = _props(props)
            self.p_d = diffuse_probability(self.p["metallic"])
            flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            if self.p_d > 0.0:
                flags = flags | mi.BSDFFlags.DiffuseReflection
            self.m_flags = flags
            self.m_components = [flags]

        def _base(self) -> Any:
            return mi.Spectrum(mi.Color3f(*self.p["base_color"])) if dr.is_array_v(mi.Spectrum) else \
                mi.Spectrum(*self.p["base_color"])

        def _active(self, si: Any, active: Any) -> Any:
            return active & (si.wi.z > 0.0)

        def sample(self, ctx: Any, si: Any, sample1: Any, sample2: Any, active: Any = True) -> Any:
            wi = si.wi
            md = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, self.p["alpha"] * self.p["sample_alpha_scale"],
                                           True)
            m, _ = md.sample(wi, sample2)
            spec = mi.reflect(wi, m)
            diff = mi.warp.square_to_cosine_hemisphere(sample2)
            wo = dr.select(sample1 < self.p_d, diff, spec)
            pdf = mixture_pdf(wi, wo, self.p["alpha"], self.p_d)
            ok = self._active(si, active) & (wo.z > 0.0) & (pdf > 0.0)
            f = gltf_brdf_cos(wi, wo, self._base(), self.p["metallic"], self.p["alpha"], self.p["dielectric_f0"])
            return reflection_sample(wo, pdf, ok, f)

        def eval(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            f = gltf_brdf_cos(si.wi, wo, self._base(), self.p["metallic"], self.p["alpha"], self.p["dielectric_f0"])
            return dr.select(self._active(si, active), f, mi.Spectrum(0.0))

        def pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            return dr.select(self._active(si, active), mixture_pdf(si.wi, wo, self.p["alpha"], self.p_d), 0.0)

        def eval_pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def traverse(self, callback: Any) -> None:
            return None

        def to_string(self) -> str:
            return f"GltfMetallicRoughness[{', '.join(f'{k}={v}' for k, v in self.p.items())}]"

    return GltfMetallicRoughness



def reflection_sample(wo: Any, pdf: Any, ok: Any, f: Any) -> tuple[Any, Any]:
    """Mitsuba's ``(BSDFSample3f, weight)`` of a sampled reflection: direction ``wo`` with density ``pdf``,
    ``f`` = f_r·cos θ_o, weight f/pdf; zero where ``ok`` is false (the glTF plug-ins here and in gltf_truth)."""
    import drjit as dr
    import mitsuba as mi

    bs = dr.zeros(mi.BSDFSample3f)
    bs.wo = wo
    bs.pdf = dr.select(ok, pdf, 0.0)
    bs.eta = 1.0
    bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
    bs.sampled_component = mi.UInt32(0)
    return bs, dr.select(ok, f / dr.maximum(pdf, 1e-30), mi.Spectrum(0.0))

def bsdf_dict(base_color: tuple[float, float, float] = (1.0, 1.0, 1.0), metallic: float = 0.0,
              roughness: float = 0.5, **extra: Any) -> dict[str, Any]:
    """The plug-in's ``load_dict`` entry (registers it; bad properties → one-line ValidateError)."""
    d = {"type": register(), **{f"base_{c}": float(v) for c, v in zip("rgb", base_color, strict=True)},
         "metallic": float(metallic), "roughness": float(roughness), **extra}
    _props(d)
    return d


# ---------------------------------------------------------------- checks of the plug-in (χ², albedo, Mitsuba's GGX)

CHI2_RES, CHI2_IRES = 61, 6  # Mitsuba's harness grid: at res 31 / ires 4 its own roughconductor (α = 0.0625,
# θ_i = 30°) is rejected (p = 6.7e-5, the trapezoid rule misses the lobe); at 61 / 6 it is accepted (p = 0.73)


def _direction(mu: float) -> list[float]:
    return [math.sqrt(max(1.0 - mu * mu, 0.0)), 0.0, mu]


def chi2_gltf(metallic: float, roughness: float, mu_i: float, samples: int, seed: int, significance: float = 0.01,
              test_count: int = 1, **extra: Any) -> dict[str, Any]:
    """χ² goodness of fit of ``sample`` against ``pdf`` (Mitsuba's ``ChiSquareTest`` on ``BSDFAdapter`` [3]:
    Šidák over ``test_count``, cells pooled to ≥ 5 expected, its sanity checks) at (metallic, roughness, μ_i),
    baseColor 1. ``extra``: the power checks' perturbations (``sample_alpha_scale``)."""
    import mitsuba as mi
    from mitsuba import chi2

    d = bsdf_dict((1.0, 1.0, 1.0), metallic, roughness, **extra)
    sf, pf = chi2.BSDFAdapter(PLUGIN, d, wi=mi.ScalarVector3f(*_direction(mu_i)))
    test = chi2.ChiSquareTest(domain=chi2.SphericalDomain(), sample_func=sf, pdf_func=pf, sample_dim=3,
                              sample_count=samples, res=CHI2_RES, ires=CHI2_IRES, seed=seed)
    ok = test.run(significance_level=significance, test_count=test_count, quiet=True)
    return {"metallic": metallic, "roughness": roughness, "mu_i": mu_i, "samples": samples, "accepts": bool(ok),
            "p_value": float(test.p_value), "sanity_fail": bool(test.fail), "perturbation": dict(extra)}


def albedo_sampled(base: tuple[float, float, float], metallic: float, roughness: float, mu_i: float, n: int,
                   seed: int, **extra: Any) -> tuple[list[float], list[float]]:
    """Directional albedo A(μ_i) = ∫ f μ_o dω_o = E[weight] through the plug-in's own ``sample`` (weight =
    ``eval``/``pdf``) → per channel (mean, standard error) over ``n`` samples (numpy's PCG64, ``seed``)."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    b = mi.load_dict(bsdf_dict(base, metallic, roughness, **extra))
    rng = np.random.default_rng(seed)
    u = rng.random((3, n)).astype(np.float32)
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(*_direction(mu_i))
    _, w = b.sample(mi.BSDFContext(), si, mi.Float(u[0]), mi.Point2f(mi.Float(u[1]), mi.Float(u[2])))
    x = np.stack([np.asarray(w[k], dtype=np.float64) for k in range(3)])
    return x.mean(1).tolist(), (x.std(1, ddof=1) / math.sqrt(n)).tolist()


def _np_brdf_terms(wi: Any, wo: Any, h: Any, alpha: float, f0d: float, base: Any, metallic: float) -> tuple[Any, Any]:
    """numpy float64, written apart from the drjit code: (diffuse part f_d μ_o, specular part f_s μ_o), (N, 3)."""
    import numpy as np

    nl, nv, nh, vh = wo[:, 2], wi[:, 2], h[:, 2], np.abs((wi * h).sum(-1))
    a2 = alpha * alpha
    d = a2 / (np.pi * (nh * nh * (a2 - 1.0) + 1.0) ** 2)
    v = 0.5 / (nl * np.sqrt(nv * nv * (1.0 - a2) + a2) + nv * np.sqrt(nl * nl * (1.0 - a2) + a2))
    s5 = ((1.0 - vh) ** 5)[:, None]
    fd = f0d + (1.0 - f0d) * s5
    fm = base[None, :] + (1.0 - base[None, :]) * s5
    ok = ((nl > 0) & (nv > 0))[:, None]
    diffuse = (1.0 - metallic) * (1.0 - fd) * base[None, :] / np.pi
    spec = ((1.0 - metallic) * fd + metallic * fm) * (v * d)[:, None]
    return np.where(ok, diffuse * nl[:, None], 0.0), np.where(ok, spec * nl[:, None], 0.0)


def albedo_quadrature(base: tuple[float, float, float], metallic: float, roughness: float, mu_i: float,
                      dielectric_f0: float = DIELECTRIC_F0, nodes: int = 192) -> list[float]:
    """A(μ_i) of the module docstring's formulas by Gauss–Legendre quadrature in float64 (numpy, independent of the
    plug-in): the diffuse part over ω_o = (μ_o, φ_o) (smooth); the specular part over the half vector with the GGX
    CDF as variable, tan θ_h = α √(u/(1 − u)) (D cos θ_h dω_h = du dφ/2π), and dω_o = 4 |ω_i·H| dω_h — so the lobe
    is resolved at every roughness. ``nodes`` per dimension."""
    import numpy as np

    alpha = max(roughness**2, ALPHA_MIN)
    b = np.asarray(base, np.float64)
    wi1 = np.asarray(_direction(mu_i), np.float64)
    x, w = np.polynomial.legendre.leggauss(nodes)
    t, wt = 0.5 * (x + 1.0), 0.5 * w  # [0, 1]
    phi, wphi = 2.0 * np.pi * t, 2.0 * np.pi * wt
    # diffuse part: ω_o over the hemisphere, dω = dμ dφ
    mu, ph = np.meshgrid(t, phi, indexing="ij")
    ww = np.outer(wt, wphi).ravel()
    so = np.sqrt(1.0 - mu * mu)
    wo = np.stack([so * np.cos(ph), so * np.sin(ph), mu], -1).reshape(-1, 3)
    wi = np.broadcast_to(wi1, wo.shape)
    h = wi + wo
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    diffuse, _ = _np_brdf_terms(wi, wo, h, alpha, dielectric_f0, b, metallic)
    a_d = (diffuse * ww[:, None]).sum(0)
    # specular part: H from the GGX CDF u, ω_o = reflect(ω_i, H)
    u, ph = np.meshgrid(t, phi, indexing="ij")
    ww = np.outer(wt, wphi).ravel()
    th = np.arctan(alpha * np.sqrt(u / (1.0 - u)))
    h = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], -1).reshape(-1, 3)
    wi = np.broadcast_to(wi1, h.shape)
    vh = (wi * h).sum(-1)
    wo = 2.0 * vh[:, None] * h - wi
    a2 = alpha * alpha
    dh = a2 / (np.pi * (h[:, 2] ** 2 * (a2 - 1.0) + 1.0) ** 2)
    jac = 4.0 * np.abs(vh) / (2.0 * np.pi * dh * h[:, 2])  # dω_o per du dφ
    _, spec = _np_brdf_terms(wi, wo, h, alpha, dielectric_f0, b, metallic)
    spec = np.where((vh > 0)[:, None], spec, 0.0)
    a_s = (spec * (jac * ww)[:, None]).sum(0)
    return (a_d + a_s).tolist()


def metal_vs_roughconductor(roughness: float, n: int, seed: int) -> dict[str, float]:
    """metallic = 1, baseColor = 1 (F = 1) against Mitsuba's own ``roughconductor`` (GGX, η = 0, k = 1: F = 1) on
    ``n`` random direction pairs. Mitsuba's is separable, G₁(ω_i)G₁(ω_o); glTF's V is height-correlated, G₂ =
    1/(1/G₁(ω_i) + 1/G₁(ω_o) − 1) [2]; so f_glTF = f_Mitsuba G₂/(G₁G₁) exactly, with G₁ from Mitsuba's own
    ``MicrofacetDistribution`` → max relative difference (``max_rel_diff``) and, for the power check, the same without
    the factor (``separable_max_rel_diff``: the suite's reference (i) roughconductor taken for glTF's)."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    init()
    alpha = max(roughness**2, ALPHA_MIN)
    rng = np.random.default_rng(seed)

    def hemi() -> Any:
        u1, u2 = rng.random(n) * 0.97 + 0.02, rng.random(n)
        st = np.sqrt(1.0 - u1 * u1)
        return mi.Vector3f(np.ascontiguousarray(np.stack([st * np.cos(2 * np.pi * u2), st * np.sin(2 * np.pi * u2),
                                                          u1]), dtype=np.float32))

    wi, wo = hemi(), hemi()
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = wi
    rc = mi.load_dict({"type": "roughconductor", "distribution": "ggx", "alpha": alpha, "eta": 0.0, "k": 1.0})
    mine = mi.load_dict(bsdf_dict((1.0, 1.0, 1.0), 1.0, roughness))
    f_rc = np.asarray(rc.eval(mi.BSDFContext(), si, wo)[0], dtype=np.float64)
    f_me = np.asarray(mine.eval(mi.BSDFContext(), si, wo)[0], dtype=np.float64)
    md = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, alpha, True)
    h = dr.normalize(wi + wo)
    g1i, g1o = (np.asarray(md.smith_g1(w, h), dtype=np.float64) for w in (wi, wo))
    ref = f_rc / (g1i * g1o) / (1.0 / g1i + 1.0 / g1o - 1.0)
    ok = ref > 1e-6 * ref.max()
    return {"roughness": roughness, "pairs": int(ok.sum()),
            "max_rel_diff": float((np.abs(f_me - ref) / ref)[ok].max()),
            "separable_max_rel_diff": float((np.abs(f_me - f_rc) / np.maximum(f_rc, 1e-30))[ok].max())}


__all__ = ["PLUGIN", "DIELECTRIC_F0", "register", "bsdf_dict", "gltf_brdf_cos", "mixture_pdf", "ggx_d",
           "smith_v_height_correlated", "schlick_f", "diffuse_probability", "chi2_gltf", "albedo_sampled",
           "albedo_quadrature", "metal_vs_roughconductor"]

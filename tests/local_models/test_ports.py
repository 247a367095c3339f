"""The techniques ported from numpy to drjit (issue 22 item 3) equal their numpy originals, on every drjit backend.

Each case runs the ported code on ``scalar`` (``drjit.scalar`` dynamic arrays, what ``scalar_rgb`` computes with),
``llvm`` (``llvm_ad_rgb``) and ``cuda`` (``cuda_ad_rgb``; skipped, with the reason, without a CUDA device), in its
family's dtype (:mod:`validate.local_models.precision`), and compares it with the numpy float64 code it replaced
(kept here, frozen, as the oracle: :func:`_np_*`) within the bound stated per case:

* float64 (arealight family): 1e-12 of the largest value (a few tens of operations × 2⁻⁵³ ≈ 1.1e-16, with the
  legendre recurrence's growth to l = 8; measured ≤ 2.5e-15); cap_exact against the closed form in numpy float64
  (its original was the same formula in float32 drjit);
* float32 (irradiance, shadow): ZH3 and Geomerics' L1 ≤ 1e-6 of max|E| (≤ 9 terms, u = 6e-8: 16 u Σ|terms|,
  Higham §4.2; measured 1.6e-7); ESM ≤ 2e-5 absolute (the exponent 80 (d − t) carries 80 u of absolute error;
  measured 1.8e-6); VSM ≤ 2e-4 absolute: σ² = E[d²] − E[d]² cancels to ~u in float32, floored at MIN_VARIANCE
  = 16 u (the module's own reasoning), measured 1.5e-5 on these 2000 footprints (13× margin); MSM ≤ 1e-2
  absolute: the Hankel system of α = 3e-5-biased moments has condition number ~1/α, so float32 moments move G by
  ~u/α ≈ 2e-3 (measured 2.06e-3: [1]'s design point for 32-bit moments; 5× margin);
* float32 (specular_arealight): representative point, sphere and tube, ≤ 1e-4 of max L_o: GGX D's
  q = (n·h)²(α² − 1) + 1 → α² at the peak, so a rounding u of (n·h)² moves D by 2u/α² relative (2.4e-5 at
  α = 0.1); measured 1.6e-5 (sphere) and 2.2e-5 (tube) in float32, 1.3e-13 forced to float64;
* float32 (brdf: classic_brdfs, ganovelli_cook_torrance), relative to max|f_r cos| over three parameter sets
  (dielectric; coloured conductor under GGX α = 0.1; η = 0.7 with total internal reflection) × 3000 random
  (n, l, v): the cosines are float32 dot products (absolute error ≈ 3u, u = 6e-8), and each formula amplifies them
  by its condition number. Lambert, Oren–Nayar (both): ≤ 1e-6, 2e-6 (≈ 10 u; measured 2.8e-7, 6.6e-7); the
  (r·v)^s, (n·h)^s lobes: s·rel(x) with s ≤ 200 → 200 · 4u = 4.8e-5, bound 5e-5 (measured 2.1e-5); Cook–Torrance
  (all four): Beckmann's exp(−tan²θ_h/m²) turns the exponent's relative error into D's, tan²θ_h/m² up to ~30 at
  the lobe's edge for m = 0.1 → 30 · 16u ≈ 3e-5, bound 5e-5 (measured 1.9e-5); Minnaert with K = 0.7:
  (n·v)^(K−1) amplifies n·v's 3u absolute error by (1 − K)/(n·v), and the largest value of the sample sits at its
  smallest n·v (≈ 1e-4): 0.3 · 3u / 1e-4 ≈ 5e-4, bound 2e-3 (measured 5.4e-4);
* float32 (brdf: brdf_multiscatter, GGX α = 0.3 conductor and Beckmann α = 0.7 dielectric, metalness 0.5 and 1):
  the microfacet term's 5e-5 above; the tables' linear interpolation in drjit (63 segments summed) adds
  ≤ 63 u · TV(E) ≈ 4e-6 (TV(E) ≤ 1); measured ≤ 5.0e-6 (scalar), 2.4e-6 (llvm).

* float32 (specular_arealight: ltc), relative to max L_o over 4 shapes × α ∈ {0.1, 0.4, 0.9} × 400 receivers: a
  transformed vertex's direction carries ε ≤ (8 + 3κ)u (p and the light rounded, one subtraction, the frame's
  3-term dot products, then M⁻¹ of condition number κ ≤ 110 over the table rows of α ≥ 0.09 (measured), with
  the table coordinate x = ‖n − v‖/√2 read to u, not √(1 − μ) to √u); the clamped-cosine integral F over a
  polygon of angular radius ρ moves by ≤ 2ε/ρ of itself (D_o ≤ 1/π on a boundary of length ≤ 2πρ, over an
  area ≈ πρ²); ρ ≥ 0.065 rad here (the 0.3 m sphere 4.6 m away, α = 0.9, κ ≈ 2: 2 · 14u/0.065 = 2.6e-5) and
  the sharp rows are stretched by M⁻¹ (α = 0.1: ρ ≳ 0.65, 2 · 338u/0.65 = 6.2e-5): bound 1e-4; measured 1.4e-6
  (4.5e-6 per light); the edge terms use atan2(‖a × b‖, a·b), exact to a few u for short edges, where acos(a·b)
  loses √u. Forced to float64 ≤ 1e-10 (the same formula; the numpy walk of the clipped slots and the drjit
  exit/entry pairing agree to 1e-12 on random, also non-convex, polygons);
* float32 (uberlight: uberlight_fore_june_printed), relative to max L_o over 2000 receivers on both branches:
  the shading is the same drjit float32 code in both; the falloff adds (d₀/d)^α and M exp(s (d₀/d)^β) in float32:
  d to 3u, the ratio to 4u, pow to α·4u + 2u (x^a = exp(a ln x): |a ln x| u), exp(s t) to |s t|·(β·4u) + 2u
  with |s| = ln 3, β = α/ln 3, t ≤ (3.3/2.5)^β: ≲ 20u = 1.2e-6; bound 1e-5; measured 2.1e-7;
* float32 (specular: phong_prefiltered, phong_prefiltered_s at s = 10, 100, k_s = 0.8), relative to max L_o over
  1000 random (n, v): r = 2(n·v)n − v in float32 is within 8u per component of the float64 one; the lookup moves
  by the texel coordinate's error times the largest neighbour difference ΔP, 8u k_s (2NΔP + P) (half of
  glsl_split_sum_ggx's 16u bound, test_glsl_techniques.py, with S = k_s), plus the two sparse maps' float32
  difference (the same texels summed over other candidate sets) ≤ 16u k_s P: at s = 100 (N = 128, this map's 30×
  bright patch) 1.4e-4 = 8e-6 of max L_o (computed in :func:`test_phong_prefiltered_equals_its_glsl_form`);
  bound 1e-5, measured 5.8e-7. The map stays the float32 numpy prefilter (per-environment set-up), built on the
  footprint of the drjit r. Against the GLSL form (llvmpipe): ≤ 16u k_s (2NΔP + 2P), measured 3.8e-7 of max L_o.

The numbers these bounds are checked against are printed in each assertion message. Two more checks on the ports:
phong_prefiltered against the same shading as a fragment shader in the suite's GLSL harness (the only one of the
three with a GLSL form: no LTC shader exists here, and Fore June's listing codes the *listing's* near branch on the
depth, not eq. 20.47 as printed), and drjit's kernel cache: a second call with new numbers, of the same or a new
size, compiles no kernel (on main's code each of the six techniques checked compiles one per call; so did the brdf,
point-light and tube techniques of :func:`_brdf_light_recompile_cases` before their numbers were made opaque).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

import validate.local_models as lm
from validate.geometry import perp, unit
from validate.local_models import precision
from validate.local_models.arealight import disc_sh, sphere_cap
from validate.local_models.brdf import brdf_multiscatter as ms
from validate.local_models.brdf import common as bc
from validate.local_models.irradiance import sh, windowed_sh, zh3
from validate.local_models.shadow import shadow_esm, shadow_msm, shadow_vsm
from validate.local_models.shadow.shadow_map import FilterFootprint, footprint_dr
from validate.local_models.specular import prefiltered_specular as ps
from validate.local_models.specular.common import reflect
from validate.local_models.specular_arealight import ltc as ltc_mod
from validate.local_models.uberlight import common as uc
from validate.scenes.area_lights import tube_geometry


def _has_cuda() -> bool:
    import drjit as dr

    try:
        return bool(dr.has_backend(dr.JitBackend.CUDA))
    except Exception:  # noqa: BLE001 (no driver: the backend is absent)
        return False


BACKENDS = [pytest.param("scalar"), pytest.param("llvm"),
            pytest.param("cuda", marks=pytest.mark.skipif(not _has_cuda(), reason="no CUDA device/driver here"))]


# -- the numpy originals (frozen copies of the code the ports replaced) ---------------------------------------
def _np_point(light: dict, points: np.ndarray, normals: np.ndarray, constant_r2: bool) -> np.ndarray:
    g = sphere_cap.light_geometry(light, points, normals)
    intensity = np.pi * g["radius"] ** 2 * g["radiance"] * np.maximum(g["cos_psi"], 0.0)
    a = g["radius"] ** 2 if constant_r2 else 0.0
    return intensity * np.maximum(g["cos_theta"], 0.0) / (a + g["distance"] ** 2)


def _np_sh(light: dict, points: np.ndarray, normals: np.ndarray, lmax: int) -> np.ndarray:
    g = sphere_cap.light_geometry(light, points, normals)
    z = disc_sh.zonal_cap(np.arcsin(np.sqrt(g["sin2_sigma"])), lmax)
    p = disc_sh.legendre(g["cos_theta"], lmax)
    e = sum(sh.clamped_cosine_al(l) * math.sqrt((2 * l + 1) / (4 * math.pi)) * z[l] * p[l] for l in range(lmax + 1))
    return e * g["radiance"] * np.maximum(g["cos_psi"], 0.0)


def _np_cap(light: dict, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """The horizon-clipped cap (sphere_cap's docstring, Snyder 1996; Lagarde & de Rousiers 2014) in numpy float64."""
    g = sphere_cap.light_geometry(light, points, normals)
    c, s2 = g["cos_theta"], g["sin2_sigma"]
    s = np.sqrt(np.maximum(1.0 - c * c, 0.0))
    x = np.sqrt(1.0 / s2 - 1.0)
    y = np.clip(-x * c / np.maximum(s, 1e-12), -1.0, 1.0)
    sq = s * np.sqrt(np.maximum(1.0 - y * y, 0.0))
    clip = np.maximum((c * np.arccos(y) - x * sq) * s2 + np.arctan(sq / x), 0.0)
    e = np.where(c * c > s2, np.pi * s2 * np.maximum(c, 0.0), clip)
    return e * g["radiance"] * np.maximum(g["cos_psi"], 0.0)


def _np_zh3(coeffs: np.ndarray, axis: np.ndarray, z2: np.ndarray, normals: np.ndarray) -> np.ndarray:
    y = sh.eval_basis_numpy(normals, 1)
    a = np.array([sh.clamped_cosine_al(sh.degree_of(k)) for k in range(4)])
    t = normals @ axis
    return y @ (a[:, None] * coeffs[:4]) + zh3.A2 * zh3.Y20_NORM * (3.0 * t * t - 1.0)[:, None] * z2[None, :]


def _np_geomerics(coeffs4: np.ndarray, normals: np.ndarray) -> np.ndarray:
    r0 = math.pi * 0.5 * math.sqrt(1.0 / math.pi) * coeffs4[0]
    half_a1 = 0.5 * (2.0 * math.pi / 3.0) * 0.5 * math.sqrt(3.0 / math.pi)
    r1 = half_a1 * np.stack([coeffs4[3], coeffs4[1], coeffs4[2]], axis=-1)
    out = np.empty((len(normals), 3))
    for c in range(3):
        length = float(np.linalg.norm(r1[c]))
        rho = min(length / float(r0[c]), 1.0)
        q = 0.5 * (1.0 + normals @ (r1[c] / length))
        p = 1.0 + 2.0 * rho
        a = (1.0 - rho) / (1.0 + rho)
        out[:, c] = r0[c] * (a + (1.0 - a) * (p + 1.0) * np.power(np.maximum(q, 0.0), p))
    return out


def _np_vsm(b1: np.ndarray, b2: np.ndarray, t: np.ndarray) -> np.ndarray:
    var = np.maximum(b2 - b1 * b1, shadow_vsm.MIN_VARIANCE)
    p = var / (var + (t - b1) ** 2)
    return np.where(t <= b1, 1.0, np.clip(p, 0.0, 1.0))


def _np_msm(b: np.ndarray, z_f: np.ndarray, alpha: float = shadow_msm.ALPHA) -> np.ndarray:
    b = (1.0 - alpha) * b + alpha * 0.5
    b1, b2, b3, b4 = b.T
    one = np.ones_like(b1)
    hankel = np.stack([np.stack([one, b1, b2], -1), np.stack([b1, b2, b3], -1), np.stack([b2, b3, b4], -1)], -2)
    c = np.linalg.solve(hankel, np.stack([one, z_f, z_f * z_f], -1)[..., None])[..., 0]
    c1, c2, c3 = c.T
    disc = np.sqrt(np.maximum(c2 * c2 - 4 * c3 * c1, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        r1, r2 = (-c2 - disc) / (2 * c3), (-c2 + disc) / (2 * c3)
        z2, z3 = np.minimum(r1, r2), np.maximum(r1, r2)
        mid = (z_f * z3 - b1 * (z_f + z3) + b2) / ((z3 - z2) * (z_f - z2))
        far = 1 - (z2 * z3 - b1 * (z2 + z3) + b2) / ((z_f - z2) * (z_f - z3))
    g = np.where(z_f <= z2, 0.0, np.where(z_f <= z3, mid, far))
    return np.clip(np.nan_to_num(g, nan=0.0), 0.0, 1.0)


def _np_ggx_point(alpha: float, f0: np.ndarray, n: np.ndarray, l: np.ndarray, v: np.ndarray,
                  e_scaled: np.ndarray) -> np.ndarray:
    g = bc.Geometry(n, l, v)
    spec = (bc.ggx_d(g.ch, alpha) * bc.smith_g1(g.cl, alpha, "ggx") * bc.smith_g1(g.cv, alpha, "ggx")
            / (4.0 * np.maximum(g.cv, 1e-12)))
    return g.finish(bc.fresnel_schlick(g.vh, f0) * (spec * e_scaled)[:, None])


def _np_rep_sphere(light: dict, alpha: float, f0: np.ndarray, points: np.ndarray, normals: np.ndarray,
                   views: np.ndarray) -> np.ndarray:
    n, v, radius = unit(normals), unit(views), float(light["radius"])
    to_c = np.asarray(light["center"], dtype=np.float64) - points
    dist = np.linalg.norm(to_c, axis=-1)
    r = 2.0 * np.sum(n * v, -1, keepdims=True) * n - v
    c2r = np.sum(to_c * r, -1, keepdims=True) * r - to_c
    t = np.clip(radius / np.maximum(np.linalg.norm(c2r, axis=-1, keepdims=True), 1e-300), 0.0, 1.0)
    l = unit(to_c + c2r * t)
    e = float(light["radiance"]) * np.pi * radius ** 2 / dist ** 2
    return _np_ggx_point(alpha, f0, n, l, v, e * (alpha / np.clip(alpha + radius / (2.0 * dist), 0.0, 1.0)) ** 2)


def _np_rep_tube(light: dict, alpha: float, f0: np.ndarray, p: np.ndarray, normals: np.ndarray,
                 views: np.ndarray) -> np.ndarray:
    c, ax = np.asarray(light["center"], dtype=np.float64), unit(np.asarray(light["axis"], dtype=np.float64))
    length, radius = float(light["length"]), float(light["radius"])
    n, v = unit(normals), unit(views)
    r = 2.0 * np.sum(n * v, -1, keepdims=True) * n - v
    l0, ld = c - 0.5 * length * ax - p, length * ax
    rl0, rld = np.sum(r * l0, -1), r @ ld
    den = length ** 2 - rld ** 2
    t = np.where(den > 1e-12 * length ** 2, (rl0 * rld - l0 @ ld) / np.where(den > 0.0, den, 1.0), 0.5)
    lt = l0 + np.clip(t, 0.0, 1.0)[:, None] * ld
    c2r = np.sum(lt * r, -1, keepdims=True) * r - lt
    s = np.clip(radius / np.maximum(np.linalg.norm(c2r, axis=-1, keepdims=True), 1e-300), 0.0, 1.0)
    l = unit(lt + c2r * s)
    dist = np.linalg.norm(c - p, axis=-1)
    q = p - c
    s_p = q @ ax
    h = np.maximum(np.linalg.norm(q - s_p[:, None] * ax, axis=-1), 1e-300)
    s0, s1 = -0.5 * length - s_p, 0.5 * length - s_p
    r0, r1 = np.hypot(h, s0), np.hypot(h, s1)
    omega = 2.0 * radius * (s1 * r0 - s0 * r1) / (h * r0 * r1) + 0.5 * np.pi * radius ** 2 * (1 / r0 ** 2 + 1 / r1 ** 2)
    a_line = np.clip(alpha + 0.5 * np.clip(length / dist, 0.0, 1.0), 0.0, 1.0)
    a_sph = np.clip(alpha + radius / (2.0 * dist), 0.0, 1.0)
    e = float(light["radiance"]) * omega * (alpha / a_line) * (alpha / a_sph) ** 2
    return _np_ggx_point(alpha, f0, n, l, v, e)


def _np_classic(name: str, p: dict, normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    """classic_brdfs' and ganovelli_cook_torrance's techniques as they were in numpy float64."""
    g, who = bc.Geometry(normals, lights, views), "oracle"
    alb, ks = bc.param(p, "albedo", who), bc.param(p, "ks", who)
    diffuse = alb / np.pi * bc.column(g.cl)
    if name in ("phong", "blinn_phong"):
        s = p["phong_exponent" if name == "phong" else "exponent"]
        spec = np.power(np.maximum(g.rv, 0.0), s) if name == "phong" else np.power(g.ch, s)
        return g.finish((alb * bc.column(g.cl) + ks * bc.column(spec)) / np.pi)
    if name in ("phong_normalized", "blinn_phong_normalized"):
        s = p["phong_exponent" if name == "phong_normalized" else "exponent"]
        lobe = ((s + 2.0) / (2.0 * np.pi) * np.power(np.maximum(g.rv, 0.0), s) if name == "phong_normalized"
                else (s + 8.0) / (8.0 * np.pi) * np.power(g.ch, s))
        return g.finish((alb / np.pi + ks * bc.column(lobe)) * bc.column(g.cl))
    if name == "cook_torrance_printed":
        return g.finish(diffuse + bc.cook_torrance_printed_terms(p, g))
    if name == "cook_torrance":
        return g.finish(diffuse + bc.microfacet_specular(p, g))
    al, be = bc.alpha_beta(g)
    if name == "oren_nayar":
        a, b = bc.oren_nayar_ab(p["sigma"])
        shape = a + b * np.maximum(g.cos_dphi, 0.0) * np.sin(al) * np.tan(np.minimum(be, np.pi / 2 - 1e-9))
        return g.finish(alb / np.pi * bc.column(shape * g.cl))
    if name == "oren_nayar_full":
        l1, l2 = bc.oren_nayar_full_terms(p["sigma"], alb, g)
        return g.finish(l1 + l2)
    if name == "minnaert":
        shape = np.power(np.maximum(g.cl * g.cv, 1e-300), p["minnaert_k"] - 1.0)
        return g.finish(alb / np.pi * bc.column(shape * g.cl))
    if name.startswith("cook_torrance_ganovelli"):
        with_nl = name.endswith("_nl")
        f = bc.fresnel_schlick(g.cl, bc.fresnel_f0(bc.param(p, "eta", who), bc.param(p, "k", who)))
        d = bc.beckmann_d(g.ch, p["alpha"], normalised=False)
        vh = np.maximum(g.vh, 1e-12)
        gg = np.minimum(1.0, np.minimum(2.0 * g.ch * g.cv / vh, g.ch * g.cl / vh))
        sp = d * gg / np.maximum(g.cl * g.cv, 1e-12) * (g.cl if with_nl else 1.0)
        return g.finish(diffuse + f * (sp / np.pi)[:, None])
    return g.finish(diffuse)  # lambert


def _np_multiscatter(name: str, p: dict, normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    """brdf_multiscatter's techniques as they were in numpy float64 (tables, F_avg: the module's own set-up)."""
    g, who = bc.Geometry(normals, lights, views), "oracle"
    alpha, dist = round(float(p["alpha"]), 6), p["distribution"]
    t = ms.tables(dist, alpha)
    col = bc.column
    diffuse = bc.param(p, "albedo", who) / np.pi * col(g.cl)
    single = bc.microfacet_specular(p, g, who)
    f0 = bc.fresnel_f0(bc.param(p, "eta", who), bc.param(p, "k", who))

    def fms_ems(f0_: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ems = 1.0 - col(t.lookup(t.e, g.cv))
        fss_ess = f0_ * col(t.lookup(t.a, g.cv)) + col(t.lookup(t.b, g.cv))
        f_avg = f0_ + (1.0 - f0_) / 21.0
        return fss_ess, ems * fss_ess * f_avg / (1.0 - ems * f_avg)

    def schlick_single(f0_: np.ndarray) -> np.ndarray:
        d_only = bc.microfacet_specular({"alpha": alpha, "distribution": dist, "eta": 0.0, "k": 1.0}, g, who)
        return d_only * bc.fresnel_schlick(g.vh, f0_)

    if name == "ggx_kulla_conty":
        f_avg, ea = ms.f_avg_exact(bc.param(p, "eta", who), bc.param(p, "k", who)), t.e_avg
        lobe = (1.0 - t.lookup(t.e, g.cv)) * (1.0 - t.lookup(t.e, g.cl)) / (np.pi * (1.0 - ea)) * np.maximum(g.cl, 0)
        return g.finish(diffuse + single + col(lobe) * (f_avg ** 2 * ea / (1.0 - f_avg * (1.0 - ea))))
    if name == "ggx_fdez_aguera":
        return g.finish(diffuse + single + fms_ems(f0)[1] / np.pi * col(g.cl))
    if name == "ggx_turquin":
        return g.finish(diffuse + single * (1.0 + f0 * col(1.0 / np.maximum(t.lookup(t.e, g.cv), 1e-6) - 1.0)))
    m, cos_l = float(p.get("metalness", 1.0)), col(g.cl)
    base = np.broadcast_to(np.asarray(p.get("base_color", f0)), (3,))
    if name == "ggx_metalness_blended_f0_bug":
        fb = (1.0 - m) * ms.DIELECTRIC_F0 + m * base
        ss_e, ms_e = fms_ems(fb)
        diffuse = base * (1.0 - m) * (1.0 - ss_e - ms_e) / np.pi * cos_l
        return g.finish(schlick_single(fb) + ms_e / np.pi * cos_l + diffuse)
    d0 = np.full(3, ms.DIELECTRIC_F0)
    d_ss, d_ms = fms_ems(d0)
    dielectric = schlick_single(d0) + d_ms / np.pi * cos_l + base * (1.0 - d_ss - d_ms) / np.pi * cos_l
    metal = schlick_single(base) + fms_ems(base)[1] / np.pi * cos_l
    return g.finish((1.0 - m) * dielectric + m * metal)


# -- ltc: the numpy original (frozen copy of specular_arealight/ltc.py's evaluation before the port) ---------
def _np_ltc_polygon(light: dict, points: np.ndarray) -> np.ndarray:
    shape = light.get("shape")
    c = np.asarray(light.get("center", (0.0, 0.0, 0.0)), dtype=np.float64)
    n_pts = len(points)
    if shape == "rectangle":
        nrm = unit(light["normal"])
        t = unit(light.get("tangent", perp(nrm)))
        t = unit(t - nrm * np.dot(t, nrm))
        b = np.cross(nrm, t)
        w, h = (float(x) for x in light["size"])
        corners = [c + 0.5 * (sx * w * t + sy * h * b) for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        return np.broadcast_to(np.array(corners), (n_pts, 4, 3))
    if shape in ("disc", "sphere"):
        r, sides = float(light["radius"]), ltc_mod.DISC_SIDES
        ang = 2.0 * np.pi * np.arange(sides) / sides
        scale = r * np.sqrt(2.0 * np.pi / (sides * np.sin(2.0 * np.pi / sides)))
        if shape == "disc":
            nrm = np.broadcast_to(unit(light["normal"]), (n_pts, 3))
        else:
            to_p = points - c
            d = np.linalg.norm(to_p, axis=-1, keepdims=True)
            nrm = to_p / d
            scale = scale * d / np.sqrt(d * d - r * r)
        t = perp(nrm)
        b = np.cross(nrm, t)
        sc = np.asarray(scale, dtype=np.float64).reshape(-1, 1, 1) if np.ndim(scale) else scale
        return c + sc * (np.cos(ang)[None, :, None] * t[:, None, :] + np.sin(ang)[None, :, None] * b[:, None, :])
    c, ax, length, r = tube_geometry(light, "oracle")
    q = np.asarray(points, dtype=np.float64) - c
    qp = q - (q @ ax)[:, None] * ax
    h = np.linalg.norm(qp, axis=-1, keepdims=True)
    b = unit(np.cross(qp / h, ax))
    rr = r * h / np.sqrt(h * h - r * r)
    th = np.linspace(-0.5 * np.pi, 0.5 * np.pi, ltc_mod.TUBE_ARC_SIDES + 1)
    ends = []
    for sign in (1.0, -1.0):
        centre = c + sign * 0.5 * length * ax
        arc = sign * (np.cos(th)[None, :, None] * ax + np.sin(th)[None, :, None] * b[:, None, :])
        ends.append(centre + rr[:, :, None] * arc)
    return np.concatenate(ends, axis=1)


def _np_clipped_form_factor(poly: np.ndarray) -> np.ndarray:
    n, k, _ = poly.shape
    cur, nxt = poly, np.roll(poly, -1, axis=1)
    zc, zn = cur[..., 2], nxt[..., 2]
    t = np.where(np.abs(zc - zn) > 1e-300, zc / np.where(np.abs(zc - zn) > 1e-300, zc - zn, 1.0), 0.0)
    cross_pt = cur + t[..., None] * (nxt - cur)
    cross_pt[..., 2] = 0.0
    slots = np.empty((n, 2 * k, 3))
    valid = np.empty((n, 2 * k), dtype=bool)
    slots[:, 0::2], slots[:, 1::2] = cur, cross_pt
    valid[:, 0::2], valid[:, 1::2] = zc >= 0.0, (zc >= 0.0) != (zn >= 0.0)
    slots = unit(slots)
    idx = np.broadcast_to(np.arange(2 * k), (n, 2 * k))
    nxt_idx = np.full((n, 2 * k), -1)
    for off in range(2 * k - 1, 0, -1):
        cand = (idx + off) % (2 * k)
        nxt_idx = np.where(np.take_along_axis(valid, cand, 1), cand, nxt_idx)
    a = slots
    b = np.take_along_axis(slots, np.maximum(nxt_idx, 0)[..., None], 1)
    cosang = np.clip(np.sum(a * b, -1), -1.0, 1.0)
    cr = np.cross(a, b)
    crn = np.linalg.norm(cr, axis=-1)
    term = np.where(crn > 1e-12, np.arccos(cosang) * cr[..., 2] / np.maximum(crn, 1e-300), 0.0)
    use = valid & (nxt_idx >= 0) & (np.sum(valid, axis=1, keepdims=True) >= 3)
    return np.abs(np.sum(np.where(use, term, 0.0), axis=1)) / (2.0 * np.pi)


def _np_ltc(light: dict, alpha: float, f0: np.ndarray, points: np.ndarray, normals: np.ndarray,
            views: np.ndarray) -> np.ndarray:
    tab = ltc_mod.load_table()
    frames, mu = ltc_mod.local_frames(normals, views)
    m_inv, norm, fres = tab.lookup(alpha, np.clip(mu, 0.0, 1.0))
    poly = _np_ltc_polygon(light, points) - points[:, None, :]
    local = np.einsum("nij,nkj->nki", frames, poly)
    front = np.sum((np.asarray(light.get("center"), dtype=np.float64) - points)
                   * np.asarray(light.get("normal", (0.0, 0.0, 0.0)), dtype=np.float64), -1) < 0.0
    if light.get("shape") in ("sphere", "tube"):
        front = np.ones(len(points), dtype=bool)
    ff = np.where(front & (mu > 0.0), _np_clipped_form_factor(np.einsum("nij,nkj->nki", m_inv, local)), 0.0)
    return float(light.get("radiance", 1.0)) * ff[:, None] * (f0[None, :] * norm[:, None]
                                                              + (1.0 - f0[None, :]) * fres[:, None])


def _np_fore_june_printed(light: dict, points: np.ndarray, normals: np.ndarray, views: np.ndarray,
                          material: dict) -> np.ndarray:
    """uberlight_fore_june_printed with its falloff in numpy float64 (eq. 20.47 as printed; shade as it is)."""
    i0, d0, alpha, m = (float(light[k]) for k in ("intensity", "d0", "alpha", "max_intensity"))
    k = i0 / d0 ** alpha
    s = math.log(k / m)
    beta = -alpha / s
    d = np.maximum(np.linalg.norm(points - np.asarray(light["position"]), axis=1), 1e-300)
    f = np.where(d < d0, m * np.exp(s * (d0 / d) ** beta), k * (d0 / d) ** alpha) / i0
    return uc.shade(light, points, normals, views, material, None, f)


def _np_phong_prefiltered(radiance: np.ndarray, s: float, ks: float, normals: np.ndarray,
                          views: np.ndarray) -> np.ndarray:
    """phong_prefiltered(_s) as it was: r = 2(n·v)n − v in numpy float64, the map sparse on that r, looked up there."""
    r = reflect(normals, views)
    return ks * ps.prefilter_phong_cube(radiance, s, needed=r).lookup(r)


# -- inputs ---------------------------------------------------------------------------------------------------
def _receivers(n: int = 200, seed: int = 7) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-2.0, 2.0, (n, 3))
    pts[:, 1] = rng.uniform(-1.0, 0.5, n)
    nrm = rng.normal(size=(n, 3))
    return pts, nrm / np.linalg.norm(nrm, axis=1, keepdims=True)


LIGHTS = [{"shape": s, "center": (0.1, 2.5, -0.2), "normal": (0.0, -1.0, 0.0), "radius": r, "radiance": 3.0}
          for s, r in (("sphere", 0.6), ("disc", 0.8), ("sphere", 0.02))]


def _footprints(n: int = 2000) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Random 36-texel depth distributions (1–3 occluder depths), weights, receiver depths and moments."""
    rng = np.random.default_rng(11)
    levels = rng.uniform(0.05, 0.95, (n, 3))
    d = np.clip(np.take_along_axis(levels, rng.integers(0, 3, (n, 36)), axis=1) + rng.normal(0, 0.002, (n, 36)), 0, 1)
    w = rng.uniform(0.1, 1.0, (n, 36))
    w /= w.sum(axis=1, keepdims=True)
    t = rng.uniform(0.0, 1.0, n)
    b = np.stack([(w * d**k).sum(axis=1) for k in range(1, 5)], axis=1)
    return d, w, t, b


def _l1_coeffs() -> np.ndarray:
    rng = np.random.default_rng(3)
    c = np.zeros((9, 3))
    c[0] = 1.0
    c[1:4] = rng.uniform(-0.4, 0.4, (3, 3))
    c[4:9] = rng.uniform(-0.1, 0.1, (5, 3))
    return c


BRDF_PARAMS = [  # a dielectric (the precision test's), a coloured conductor under GGX, a dielectric with η < 1 (TIR)
    {"albedo": 0.6, "ks": 0.3, "exponent": 20.0, "phong_exponent": 20.0, "alpha": 0.3, "eta": 1.5, "k": 0.0,
     "sigma": 0.3, "minnaert_k": 1.2},
    {"albedo": (0.2, 0.5, 0.7), "ks": (0.5, 0.3, 0.1), "exponent": 80.0, "phong_exponent": 5.0, "alpha": 0.1,
     "distribution": "ggx", "eta": (0.2, 0.9, 1.1), "k": (3.9, 2.4, 2.2), "sigma": 0.6, "minnaert_k": 0.7},
    {"albedo": 0.8, "ks": 1.0, "exponent": 200.0, "phong_exponent": 200.0, "alpha": 0.6, "eta": 0.7, "k": 0.0,
     "sigma": 1.0, "minnaert_k": 2.0},
]


def _brdf_directions(n: int = 3000, seed: int = 21) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random normals, lights, views (half of the pairs below a horizon: zero in both)."""
    rng = np.random.default_rng(seed)
    return tuple(unit(rng.normal(size=(n, 3))) for _ in range(3))  # type: ignore[return-value]


def _brdf_case(name: str, ref: Callable[..., np.ndarray],
               params: list[dict] | None = None) -> Callable[[], tuple[np.ndarray, np.ndarray]]:
    def run() -> tuple[np.ndarray, np.ndarray]:
        n, l, v = _brdf_directions()
        fam = lm.FAMILIES["brdf"]
        got = np.concatenate([fam.call(name, p, n, l, v) for p in params or BRDF_PARAMS])
        return got, np.concatenate([ref(name, p, n, l, v) for p in params or BRDF_PARAMS])
    return run


# brdf (float32): relative to max|f_r cos| over BRDF_PARAMS × 3000 random (n, l, v); see the module docstring
BRDF_BOUNDS = {"lambert": 1e-6, "oren_nayar": 2e-6, "oren_nayar_full": 2e-6, "minnaert": 2e-3,
               **dict.fromkeys(("phong", "blinn_phong", "phong_normalized", "blinn_phong_normalized"), 5e-5),
               **dict.fromkeys(("cook_torrance", "cook_torrance_printed", "cook_torrance_ganovelli",
                                "cook_torrance_ganovelli_nl"), 5e-5)}
MULTISCATTER_BOUNDS = dict.fromkeys(("ggx_kulla_conty", "ggx_fdez_aguera", "ggx_turquin", "ggx_metalness_fdez_aguera",
                                     "ggx_metalness_blended_f0_bug"), 5e-5)
MULTISCATTER_PARAMS = [  # GGX and Beckmann, a conductor and a dielectric; the metalness pair at m = 0.5 and 1
    {"albedo": 0.3, "alpha": 0.3, "distribution": "ggx", "eta": (0.2, 0.9, 1.1), "k": (3.9, 2.4, 2.2),
     "metalness": 0.5, "base_color": (0.9, 0.6, 0.3)},
    {"albedo": (0.1, 0.4, 0.2), "alpha": 0.7, "distribution": "beckmann", "eta": 1.5, "k": 0.0, "metalness": 1.0},
]


# -- cases: name → (port, numpy original, bound, kind) ------------------------------------------------------
def _arealight_case(name: str, ref: Callable[..., np.ndarray], bound: float):  # noqa: ANN202
    def run() -> tuple[np.ndarray, np.ndarray]:
        pts, nrm = _receivers()
        got = np.concatenate([lm.FAMILIES["arealight"].call(name, light, pts, nrm) for light in LIGHTS])
        want = np.concatenate([ref(light, pts, nrm) for light in LIGHTS])
        return got, want
    return run, bound, "relative"


def _zh3() -> tuple[np.ndarray, np.ndarray]:
    c, n = _l1_coeffs(), _receivers()[1]
    a = zh3.zonal_axis(c)
    z2 = zh3.stored_z2(c, a)
    with precision.computing_in(lm.FAMILIES["irradiance"].precision):
        got = zh3.render_zh3(c, a, z2, n)
    return got, _np_zh3(c, a, z2, n)


def _geomerics() -> tuple[np.ndarray, np.ndarray]:
    c, n = _l1_coeffs()[:4], _receivers()[1]
    with precision.computing_in(lm.FAMILIES["irradiance"].precision):
        got = windowed_sh.geomerics_l1(c, n)
    return got, _np_geomerics(c, n)


def _shadow(kind: str) -> Callable[[], tuple[np.ndarray, np.ndarray]]:
    def run() -> tuple[np.ndarray, np.ndarray]:
        d, w, t, b = _footprints()
        with precision.computing_in(lm.FAMILIES["shadow"].precision):
            if kind == "vsm":
                return shadow_vsm.vsm_visibility(b[:, 0], b[:, 1], t), _np_vsm(b[:, 0], b[:, 1], t)
            if kind == "msm":
                return shadow_msm.hamburger_4msm(b, t), _np_msm(b, t)
            import drjit as dr

            fp = footprint_dr(FilterFootprint(d, w, t))
            v = precision.to_np(dr.clip(fp.filtered(dr.exp(shadow_esm.C * (fp.depth - fp.receiver_per_tap))), 0, 1))
        return v, np.clip((w * np.exp(shadow_esm.C * (d - t[:, None]))).sum(axis=1), 0.0, 1.0)
    return run


def _specular_case(name: str, shape: str) -> Callable[[], tuple[np.ndarray, np.ndarray]]:
    def run() -> tuple[np.ndarray, np.ndarray]:
        pts, nrm = _receivers(400, seed=9)
        rng = np.random.default_rng(13)
        views = unit(nrm + rng.normal(0.0, 0.6, nrm.shape))
        light = {"shape": shape, "center": (0.1, 2.5, -0.2), "radius": 0.3, "radiance": 2.0,
                 "axis": (1.0, 0.0, 0.2), "length": 1.5}
        got, want = [], []
        for alpha in (0.1, 0.4, 0.9):
            brdf = {"alpha": alpha, "f0": (0.9, 0.6, 0.3)}
            got.append(lm.FAMILIES["specular_arealight"].call(name, light, brdf, pts, nrm, views))
            ref = _np_rep_sphere if shape == "sphere" else _np_rep_tube
            want.append(ref(light, alpha, np.array(brdf["f0"]), pts, nrm, views))
        return np.concatenate(got), np.concatenate(want)
    return run


def _ltc_case() -> tuple[np.ndarray, np.ndarray]:
    """ltc on the four shapes (a rectangle and a disc facing down, one-sided; a sphere; a tube) × α = 0.1, 0.4,
    0.9 × 400 random receivers (some behind the lights, some with n·v ≤ 0, polygons crossing the horizon)."""
    pts, nrm = _receivers(400, seed=9)
    views = unit(nrm + np.random.default_rng(13).normal(0.0, 0.6, nrm.shape))
    got, want = [], []
    for light in LTC_LIGHTS:
        for alpha in (0.1, 0.4, 0.9):
            brdf = {"alpha": alpha, "f0": (0.9, 0.6, 0.3)}
            got.append(lm.FAMILIES["specular_arealight"].call("ltc", light, brdf, pts, nrm, views))
            want.append(_np_ltc(light, alpha, np.array(brdf["f0"]), pts, nrm, views))
    return np.concatenate(got), np.concatenate(want)


LTC_LIGHTS = [
    {"shape": "rectangle", "center": (0.1, 2.5, -0.2), "normal": (0.0, -1.0, 0.0), "size": (1.2, 0.7),
     "tangent": (1.0, 0.0, 0.3), "radiance": 2.0},
    {"shape": "disc", "center": (0.1, 2.5, -0.2), "normal": (0.0, -1.0, 0.0), "radius": 0.5, "radiance": 2.0},
    {"shape": "sphere", "center": (0.1, 2.5, -0.2), "radius": 0.3, "radiance": 2.0},
    {"shape": "tube", "center": (0.1, 2.5, -0.2), "radius": 0.3, "radiance": 2.0, "axis": (1.0, 0.0, 0.2),
     "length": 1.5},
]


def _uberlight_light() -> dict:
    """A projector at (0, 3, 0) looking down, soft superellipse and distance edges, Fore June's d₀ = 3.3 m (the
    receivers lie 2.5–4.8 m away: both branches), α = 2, M = 3 K."""
    i0, d0, alpha = 5.0, 3.3, 2.0
    return {"position": (0.0, 3.0, 0.0), "axes": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, -1.0, 0.0)),
            "intensity": i0, "width": 0.8, "height": 0.6, "width_edge": 0.2, "height_edge": 0.15, "roundness": 1.3,
            "near": 0.5, "far": 10.0, "near_edge": 0.3, "far_edge": 2.0, "d0": d0, "alpha": alpha,
            "max_intensity": 3.0 * i0 / d0 ** alpha}


def _fore_june_case() -> tuple[np.ndarray, np.ndarray]:
    pts, nrm = _receivers(2000, seed=5)
    views = unit(nrm + np.random.default_rng(6).normal(0.0, 0.5, nrm.shape))
    mat = {"albedo": 0.7, "ks": 0.3, "specular_exponent": 20.0}
    light = _uberlight_light()
    got = lm.FAMILIES["uberlight"].call("uberlight_fore_june_printed", light, pts, nrm, views, mat)
    near = np.linalg.norm(pts - np.asarray(light["position"]), axis=1) < light["d0"]
    assert min(np.sum(near & (got > 0)), np.sum(~near & (got > 0))) > 100  # both branches lit
    return got, _np_fore_june_printed(light, pts, nrm, views, mat)


def _phong_env() -> np.ndarray:
    rng = np.random.default_rng(31)
    rad = rng.uniform(0.2, 1.0, (32, 64, 3))
    rad[6:9, 20:24] += 30.0  # a small bright source: the lobes see real gradients
    return rad


def _phong_case() -> tuple[np.ndarray, np.ndarray]:
    """phong_prefiltered (map exponent s + 1) and phong_prefiltered_s at s = 10, 100 on 1000 random (n, v) with
    n·v > 0 (face sizes 32 and 128)."""
    n, v = _brdf_directions(1000, seed=8)[:2]
    v = np.where(np.sum(n * v, axis=1, keepdims=True) < 0, -v, v)
    rad, fam = _phong_env(), lm.FAMILIES["specular"]
    got, want = [], []
    for s in (10.0, 100.0):
        brdf = {"model": "phong", "exponent": s, "reflectance": 0.8}
        for name, sm in (("phong_prefiltered", s + 1.0), ("phong_prefiltered_s", s)):
            got.append(fam.call(name, rad, brdf, n, v))
            want.append(_np_phong_prefiltered(rad, sm, 0.8, n, v))
    return np.concatenate(got), np.concatenate(want)


CASES = {
    "cap_exact": _arealight_case("cap_exact", _np_cap, 1e-12),
    "sh_order2": _arealight_case("sh_order2", lambda *a: _np_sh(*a, 2), 1e-12),
    "sh_order4": _arealight_case("sh_order4", lambda *a: _np_sh(*a, 4), 1e-12),
    "sh_order8": _arealight_case("sh_order8", lambda *a: _np_sh(*a, 8), 1e-12),
    "inverse_square": _arealight_case("inverse_square", lambda *a: _np_point(*a, False), 1e-12),
    "opengl_r2": _arealight_case("opengl_r2", lambda *a: _np_point(*a, True), 1e-12),
    "zh3": (_zh3, 1e-6, "relative"),
    "geomerics_l1": (_geomerics, 1e-6, "relative"),
    "representative_point": (_specular_case("representative_point", "sphere"), 1e-4, "relative"),
    "representative_point_tube": (_specular_case("representative_point_tube", "tube"), 1e-4, "relative"),
    "esm": (_shadow("esm"), 2e-5, "absolute"),
    "vsm": (_shadow("vsm"), 2e-4, "absolute"),
    "msm": (_shadow("msm"), 1e-2, "absolute"),
    "ltc": (_ltc_case, 1e-4, "relative"),
    "uberlight_fore_june_printed": (_fore_june_case, 1e-5, "relative"),
    "phong_prefiltered": (_phong_case, 1e-5, "relative"),
    **{name: (_brdf_case(name, _np_classic), bound, "relative") for name, bound in BRDF_BOUNDS.items()},
    **{name: (_brdf_case(name, _np_multiscatter, MULTISCATTER_PARAMS), bound, "relative")
       for name, bound in MULTISCATTER_BOUNDS.items()},
}


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("case", list(CASES))
def test_port_equals_its_numpy_original(case: str, backend: str) -> None:
    run, bound, kind = CASES[case]
    with precision.computing_in(backend=backend):
        got, want = run()
    assert got.shape == want.shape and np.all(np.isfinite(got))
    err = np.abs(got - want).max() / (np.abs(want).max() if kind == "relative" else 1.0)
    assert err <= bound, f"{case} on {backend}: {kind} difference {err:.3g} > {bound:g}"
    print(f"{case} {backend}: {kind} difference {err:.3g} (bound {bound:g})")


@pytest.mark.parametrize("case", ["ltc", "uberlight_fore_june_printed", "phong_prefiltered"])
def test_port_forced_to_float64_is_its_numpy_original(case: str) -> None:
    """The ports computed in float64 (llvm) equal their numpy originals to 1e-10 of the largest value (≈ 10⁶ u of
    float64: a few hundred operations, the LTC polygon's 66 edges, pow/exp): the float32 differences above are
    rounding, not a different formula. (phong: the map itself is float32 in both, only r differs.)"""
    run, _, _ = CASES[case]
    with precision.computing_in("float64", backend="llvm"):
        got, want = run()
    err = np.abs(got - want).max() / np.abs(want).max()
    assert err <= 1e-10, f"{case}: float64 port vs numpy {err:.3g}"


def test_ltc_clipping_equals_the_numpy_slots_on_random_polygons() -> None:
    """form_factor_dr's clipping (edge parts above z = 0, each entry joined to the exit before it) against the
    frozen numpy slot walk, in float64, on 3000 random polygons of 3–8 vertices (random order: non-convex and
    self-intersecting ones too), about half of their vertices below the horizon: equal to 1e-12 (absolute; F ≤ a
    few); the float32 form within 1e-5 absolute (≤ 16 edges' terms of |θ| ≤ π, each ≈ 8u: 16 · π · 8u ≈ 2.4e-5
    before the 1/2π → 4e-6)."""
    rng = np.random.default_rng(41)
    for k in range(3, 9):
        poly = rng.normal(size=(500, k, 3))
        poly[..., 2] += 0.3
        want = _np_clipped_form_factor(poly)
        for dtype, tol in (("float64", 1e-12), ("float32", 1e-5)):
            with precision.computing_in(dtype, backend="llvm"):
                got = ltc_mod.clipped_form_factor(poly)
            assert np.abs(got - want).max() <= tol, f"K = {k}, {dtype}: {np.abs(got - want).max():.3g}"
        assert np.sum(want > 0) > 300 and np.sum((poly[..., 2] < 0).any(axis=1) & (poly[..., 2] >= 0).any(axis=1)) > 300


# -- texture lookups routed through the policy (irradiance maps, the split sum's DFG table) -------------------
def _np_dfg(table: object, mu: np.ndarray, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """The DFG table's bilinear, edge-clamped lookup (cell centres (i + ½)/n) in numpy float64."""
    n = table.size  # type: ignore[attr-defined]
    x = np.clip(mu * n - 0.5, 0.0, n - 1.0)
    y = np.clip(np.full_like(mu, alpha) * n - 0.5, 0.0, n - 1.0)
    x0, y0 = np.minimum(np.floor(x), n - 2).astype(int), np.minimum(np.floor(y), n - 2).astype(int)
    wx, wy = x - x0, y - y0

    def bil(t: np.ndarray) -> np.ndarray:
        top = t[y0, x0] * (1 - wx) + t[y0, x0 + 1] * wx
        return top * (1 - wy) + (t[y0 + 1, x0] * (1 - wx) + t[y0 + 1, x0 + 1] * wx) * wy
    return bil(table.a), bil(table.b)  # type: ignore[attr-defined]


@pytest.mark.parametrize("backend", BACKENDS)
def test_texture_lookups_compute_in_the_family_dtype_on_every_backend(backend: str) -> None:
    """CubeMap / LatLongMap.lookup (irradiance family) and DFGTable.lookup (specular family) ask the policy for
    their drjit types (float32) and equal their numpy float64 forms within 1e-5 of max|E| (bilinear weights and
    texel coordinates in float32: a coordinate of up to 2n ≈ 64 texels carries 64 u ≈ 4e-6 of a texel)."""
    from validate.local_models.irradiance import irradiance_map as im
    from validate.local_models.specular import split_sum as ss

    coeffs = _l1_coeffs()
    q = _receivers(500, seed=4)[1]
    maps = (im.irradiance_cube_from_sh(coeffs, 16), im.irradiance_latlong_from_sh(coeffs, 16))
    with precision.computing_in(backend=backend), precision.tracing() as seen:
        got = [m.lookup(q) for m in maps]
        table = ss.default_dfg_table()
        mu = np.linspace(0.0, 1.0, 301)
        dfg = table.lookup(mu, 0.37)
    assert seen and set(seen) == {"float32"}
    for m, g in zip(maps, got, strict=True):
        err = np.abs(g - m.lookup_numpy(q)).max() / np.abs(g).max()
        assert err < 1e-5, f"{type(m).__name__} on {backend}: {err:.3g}"
    for g, w in zip(dfg, _np_dfg(table, mu, 0.37), strict=True):
        assert np.abs(g - w).max() < 1e-5, f"DFG on {backend}: {np.abs(g - w).max():.3g}"


@pytest.mark.parametrize("backend", BACKENDS)
def test_shadow_map_lookups_compute_in_float32_on_every_backend(backend: str) -> None:
    """visibility_hard / _pcf / _pcss ask the policy for float32 (the shadow family) and give on every backend what
    they give on llvm (the Mitsuba variant's): hard exactly, PCF and PCSS within 1e-5 (float32 texel coordinates
    and tap sums: a few u; measured on scalar 1.2e-7 (PCF), 3.0e-7 (PCSS)).
    The map: 32² texels of random blocker depths over a receiver plane (window s, t ∈ [0, 1])."""
    from validate.local_models.shadow import shadow_map as smod

    res = 32
    view = smod.LightView(np.zeros(3), np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]),
                          np.array([0.0, 1.0, 0.0]), 0.0, 0.0, 1.0, 1.0, 3.0)
    rng = np.random.default_rng(2)
    z_occ = np.where(rng.uniform(size=res * res) < 0.5, rng.uniform(1.2, 1.9, res * res), np.inf)
    depth = np.where(np.isfinite(z_occ), view.depth_scale * (1 - 1 / z_occ), 1.0)
    with precision.computing_in(backend="llvm"):
        sm = smod.ShadowMap(view, res, precision.to_dr(depth), precision.to_dr(np.zeros(res * res)))
    xw = rng.uniform(2.0, res - 2.0, (400, 2))
    p = np.c_[xw / res * 2.0, np.full(400, 2.0)]
    n = np.tile([0.0, 0.0, -1.0], (400, 1))

    def run() -> list[np.ndarray]:
        return [smod.visibility_hard(sm, p, n), smod.visibility_pcf(sm, p, n, kernel=3),
                smod.visibility_pcss(sm, p, n, light_radius=0.05).visibility]

    with precision.computing_in(backend="llvm"):
        want = run()
    with precision.computing_in(backend=backend), precision.tracing() as seen:
        got = run()
    assert seen and set(seen) == {"float32"}
    assert np.array_equal(got[0], want[0])
    for g, w in zip(got[1:], want[1:], strict=True):
        assert np.abs(g - w).max() <= 1e-5, f"{backend}: {np.abs(g - w).max():.3g}"
    assert 0.05 < want[1].mean() < 0.95  # the map really shadows part of the receivers


# -- drjit vs GLSL where the suite's GLSL runtime runs the same technique -------------------------------------
PHONG_GLSL = """// validate: family=specular
// validate: name=glsl_phong_prefiltered_check
// validate: brdf=phong
// validate: description=phong_prefiltered as a fragment shader: k_s P_{s+1}(r), the harness's Phong map
vec3 specular(vec3 n, vec3 v) {
    float nv = dot(n, v);
    return u_reflectance * prefiltered_radiance(2.0 * nv * n - v);
}
"""


def test_phong_prefiltered_equals_its_glsl_form(tmp_path) -> None:  # noqa: ANN001
    """phong_prefiltered (drjit, float32) against the same shading as a fragment shader on llvmpipe (the specular
    family's GLSL harness builds phong_prefiltered's own map, P_{s+1}, on a footprint dilated 1e-4 rad) at
    s = 10, 100 on 2000 random (n, v) and the axis / edge / corner directions (face seams). Both are float32; r
    differs by ≤ 8u per component each way (inputs rounded alike, one dot product, two products: 16u between
    them), so the lookups differ by ≤ 16u · k_s (2NΔP + P) (test_glsl_techniques.py's split-sum note with
    S = k_s), plus the two sparse maps' own float32 difference: the same texels summed over other candidate sets
    (convolve_zonal's batches), ≤ 16u · P: |ΔL| ≤ 16u k_s (2NΔP + 2P), P, ΔP the map's maximum and largest
    neighbour difference."""
    from validate.gl import runtime
    from validate.local_models import glsl_technique as gt

    ok, why = runtime.available("llvmpipe")
    if not ok:
        pytest.skip(f"no llvmpipe GL: {why}")
    path = tmp_path / "phong_check.glsl"
    path.write_text(PHONG_GLSL, encoding="utf-8")
    tech = gt.technique_from_file(path)
    rng = np.random.default_rng(23)
    n, v = unit(rng.standard_normal((2000, 3))), unit(rng.standard_normal((2000, 3)))
    v = np.where(np.sum(n * v, axis=1, keepdims=True) < 0, -v, v)
    axes = unit(np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [0, 1, 1], [1, 0, 1], [1, 1, 1]], float))
    n, v = np.r_[n, axes, -axes], np.r_[v, axes, -axes]
    rad, fam = _phong_env(), lm.FAMILIES["specular"]
    for s in (10.0, 100.0):
        brdf = {"model": "phong", "exponent": s, "reflectance": 0.8}
        g, p = fam.call(tech, rad, brdf, n, v), fam.call("phong_prefiltered", rad, brdf, n, v)
        pad = np.asarray(ps.prefilter_phong_cube(rad, s + 1.0).padded, dtype=np.float64)
        d_p = max(np.abs(np.diff(pad, axis=1)).max(), np.abs(np.diff(pad, axis=2)).max())
        bound = 16 * 2.0**-24 * 0.8 * (2 * pad.shape[1] * d_p + 2 * pad.max())
        err = np.abs(g - p).max()
        assert np.all(np.isfinite(g)) and p.min() > 0.1
        assert err <= bound, f"s = {s}: |GLSL − drjit| = {err:.3g} > {bound:.3g}"
        print(f"phong_prefiltered s = {s}: |GLSL − drjit| = {err:.3g} (bound {bound:.3g}, "
              f"{err / p.max():.3g} of max L)")


# -- drjit's kernel cache: a new call with new numbers (and a new size) compiles nothing ----------------------
def _recompile_cases() -> dict[str, Callable[[int, int], object]]:
    """technique → call(variant, n): variant 0, 1, 2 change the light / BRDF / map numbers, n the receiver count."""
    def receivers(v: int, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        pts, nrm = _receivers(n, seed=30 + v)
        return pts, nrm, unit(nrm + np.random.default_rng(v).normal(0.0, 0.6, nrm.shape))

    def ltc(v: int, n: int) -> object:
        light = dict(LTC_LIGHTS[2], radius=0.3 + 0.05 * v, center=(0.1, 2.5 + 0.1 * v, -0.2))
        return lm.FAMILIES["specular_arealight"].call("ltc", light, {"alpha": 0.3 + 0.05 * v, "f0": 0.9 - 0.1 * v},
                                                      *receivers(v, n))

    def rep(v: int, n: int) -> object:
        light = dict(LTC_LIGHTS[2], radius=0.3 + 0.05 * v, radiance=2.0 + v)
        return lm.FAMILIES["specular_arealight"].call("representative_point", light,
                                                      {"alpha": 0.3 + 0.05 * v, "f0": 0.9 - 0.1 * v},
                                                      *receivers(v, n))

    def fore_june(v: int, n: int) -> object:
        light = dict(_uberlight_light(), d0=3.3 + 0.1 * v, width=0.8 + 0.05 * v, intensity=5.0 + v)
        return lm.FAMILIES["uberlight"].call("uberlight_fore_june_printed", light, *receivers(v, n),
                                             {"albedo": 0.7, "ks": 0.3, "specular_exponent": 20.0})

    def cap(v: int, n: int) -> object:
        return lm.FAMILIES["arealight"].call("cap_exact", dict(LIGHTS[0], radius=0.6 + 0.05 * v),
                                             *receivers(v, n)[:2])

    def sh9(v: int, n: int) -> object:
        return lm.FAMILIES["irradiance"].call("sh9", _phong_env() * (1.0 + v), receivers(v, n)[1])

    def phong(v: int, n: int) -> object:
        _, nrm, vw = receivers(v, n)
        vw = np.where(np.sum(nrm * vw, axis=1, keepdims=True) < 0, -vw, vw)
        return lm.FAMILIES["specular"].call("phong_prefiltered", _phong_env(),
                                            {"model": "phong", "exponent": 10.0, "reflectance": 0.8 - 0.1 * v}, nrm, vw)

    return {"ltc": ltc, "representative_point": rep, "uberlight_fore_june_printed": fore_june, "cap_exact": cap,
            "sh9": sh9, "phong_prefiltered": phong, **_brdf_light_recompile_cases(receivers)}


BRDF_RECOMPILE = ("lambert", "phong", "blinn_phong", "phong_normalized", "blinn_phong_normalized",
                  "cook_torrance_printed", "cook_torrance", "oren_nayar", "oren_nayar_full", "minnaert",
                  "cook_torrance_ganovelli", "cook_torrance_ganovelli_nl")
POINT_LIGHT_RECOMPILE = ("point_inverse_square", "point_two_sided", "point_gl_default", "point_ogre_r7",
                         "point_ogre_r50", "point_gltf_range", "point_ue4", "point_usc420_a1b1c0")


def _brdf_light_recompile_cases(receivers: Callable[[int, int], tuple[np.ndarray, np.ndarray, np.ndarray]]
                                ) -> dict[str, Callable[[int, int], object]]:
    """The brdf techniques (every number of the parameter set changes with the variant: albedo, k_s, the integral
    lobe exponents, α, η + ik, σ, Minnaert's K; GGX for the microfacet ones), the point, spot and directional
    lights (position, intensity, range, axis, cutoff, beam, exponent, E⊥), an area grid and Karis's tube (length,
    axis, centre, radius, radiance, α, F₀). On main's code each compiled one kernel per call (literals)."""
    def brdf_params(v: int) -> dict:
        return {"albedo": [0.8 - 0.1 * v, 0.5, 0.3], "ks": 0.5 + 0.1 * v, "exponent": 10.0 + 5 * v,
                "phong_exponent": 20.0 + 3 * v, "alpha": 0.2 + 0.05 * v, "eta": [1.5 + 0.1 * v, 1.2, 0.9],
                "k": [0.1 * v, 2.0, 3.0], "sigma": 0.3 + 0.1 * v, "minnaert_k": 0.7 + 0.05 * v, "distribution": "ggx"}

    def light_map(v: int, kind: str) -> dict:
        axis = unit(np.array([0.1 * v, -1.0, 0.05]))
        return {"type": kind, "position": (0.3 + 0.1 * v, 3.0, -0.2), "intensity": 10.0 + v, "range": 4.0 + v,
                "direction": tuple(axis), "cutoff_angle": 40.0 + 5 * v, "beam_width": 20.0 + v, "exponent": 2.0 + v,
                "irradiance": 1.0 + v}

    def brdf_case(name: str) -> Callable[[int, int], object]:
        def call(v: int, n: int) -> object:
            _, nrm, vw = receivers(v, n)
            lt = unit(nrm + np.random.default_rng(10 + v).normal(0.0, 0.6, nrm.shape))
            return lm.FAMILIES["brdf"].call(name, brdf_params(v), nrm, lt, vw)
        return call

    def light_case(name: str, kind: str) -> Callable[[int, int], object]:
        return lambda v, n: lm.FAMILIES["light"].call(name, light_map(v, kind), *receivers(v, n)[:2])

    def grid(v: int, n: int) -> object:
        return lm.FAMILIES["light"].call("area_grid", {"type": "sphere", "position": (0.5, 3.0 + 0.1 * v, 0.2),
                                                       "radius": 0.4 + 0.05 * v, "radiance": 2.0 + v, "grid": 4},
                                         *receivers(v, n)[:2])

    def tube_case(name: str) -> Callable[[int, int], object]:
        def call(v: int, n: int) -> object:
            light = {"shape": "tube", "center": (0.1 * v, 3.0, 0.0), "axis": tuple(unit(np.array([1.0, 0.1 * v, 0.2]))),
                     "length": 1.0 + 0.2 * v, "radius": 0.1 + 0.02 * v, "radiance": 4.0 + v}
            return lm.FAMILIES["specular_arealight"].call(name, light, {"alpha": 0.3 + 0.05 * v, "f0": 0.9 - 0.1 * v},
                                                          *receivers(v, n))
        return call

    cases: dict[str, Callable[[int, int], object]] = {name: brdf_case(name) for name in BRDF_RECOMPILE}
    cases |= {name: light_case(name, "point") for name in POINT_LIGHT_RECOMPILE}
    cases |= {name: light_case(name, "spot") for name in ("spot_cos_f", "spot_mitsuba")}
    cases |= {"directional": light_case("directional", "directional"), "area_grid": grid}
    cases |= {name: tube_case(name) for name in ("representative_point_tube", "representative_point_tube_unnormalized")}
    return cases


@pytest.mark.parametrize("name", list(_recompile_cases()))
def test_second_call_with_new_numbers_compiles_no_kernel(name: str) -> None:
    """On llvm, after a first call, calls with other light / BRDF / map numbers, same size and a new size, find
    every kernel in drjit's cache (dr.kernel_history: cache_hit, and not from the disk cache, which would hide a
    new hash): per-call numbers enter as opaque values and the receivers as one packed input
    (precision.constants_dr / packed_to_dr). A literal baked in, or one input per column, fails this."""
    import drjit as dr

    call = _recompile_cases()[name]
    flag = dr.flag(dr.JitFlag.KernelHistory)
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    try:
        with precision.computing_in(backend="llvm"):
            call(0, 300)
            dr.kernel_history()
            misses = []
            for v, n in ((1, 300), (2, 450)):
                call(v, n)
                jit = [k for k in dr.kernel_history() if str(k["type"]).endswith("JIT")]
                misses.append(sum(1 for k in jit if not k["cache_hit"] or k["cache_disk"]))
                assert jit, f"{name}: no kernel launched"
    finally:
        dr.set_flag(dr.JitFlag.KernelHistory, flag)
    assert misses == [0, 0], f"{name}: kernels compiled on the 2nd (same size) / 3rd (new size) call: {misses}"


@pytest.mark.parametrize("backend", ["llvm", "scalar"])
def test_opaque_power_equals_drjit_power_bit_for_bit(backend: str) -> None:
    """brdf.common.power_dr (the exponent opaque: the multiply chain over opaque bits, or exp2(log2 x · s)) gives
    drjit.power's float32 result bit for bit, for integral exponents 0 … 300 and the general case, on [0, 1.5]
    (cosines, with values > 1 whose high powers overflow) and at 0 and 1: the ports' outputs stay those of the
    literal exponent."""
    import drjit as dr

    x_np = np.r_[np.random.default_rng(3).uniform(0.0, 1.5, 4000), 0.0, 1.0, 1e-30]
    with precision.computing_in("float32", backend=backend):
        x = precision.to_dr(x_np)
        bad = [s for s in [*map(float, range(301)), 0.3, 2.5, 7.5, -0.3, -1.0]
               if not np.array_equal(np.array(bc.power_dr(x, s)), np.array(dr.power(x, s)), equal_nan=True)]
    assert bad == [], f"power_dr differs from drjit.power for exponents {bad}"

"""Heitz et al. 2016's multiple-scattering GGX conductor as a Mitsuba 3 BSDF (``microsurface_walk``).

[1] Heitz, Hanika, d'Eon, Dachsbacher, "Multiple-scattering microfacet BSDFs with the Smith model", ACM TOG 35(4)
    2016: §4 (the microsurface as a volume of microflakes with height distribution P¹, uniform on [−1, 1] here),
    §5 (Algorithm 1: the random walk; eq. 24–26 the next height), §6 (stochastic evaluation: next-event estimation
    toward ω_o at every scattering vertex).
[2] Dupuy & Benyoub, "Sampling visible GGX normals with spherical caps", CGF 42(8) 2023 (the VNDF sampler, valid for
    directions below the horizon, which the walk needs).
[3] Heitz 2014, "Understanding the masking-shadowing function", JCGT 3(2): Λ, G₁ and the projected area of GGX.

Local frame: n = +z; ω_i = ``si.wi`` and ω_o both point away from the surface (Mitsuba's convention); the walk's ray
direction ω_r points along the ray, so it starts at −ω_i. Mitsuba's ``eval`` returns f(ω_i, ω_o) cos θ_o.

The microsurface (isotropic GGX α, conductor with Schlick F(c) = F₀ + (1 − F₀)(1 − c)⁵ per bounce [1 §5.3 with
Schlick's F]):

* D(m) = α² / (π (m_z² (α² − 1) + 1)²); Λ(ω) = (−1 + sgn(ω_z) √(1 + α² tan²θ))/2, signed below the horizon [1 §5.1];
  projected area A(ω) = (ω_z + √(ω_z² + α² (1 − ω_z²)))/2 = (1 + Λ(ω)) ω_z [3];
* height: C¹(h) = (h + 1)/2; a ray at height h_r along ω_r escapes with probability G¹(ω_r, h_r) = C¹(h_r)^Λ(ω_r)
  (ω_r upward) else meets the surface at C¹⁻¹(C¹(h_r)/(1 − U)^{1/Λ(ω_r)}) [1 eq. 24–26];
* phase function (conductor): p(ω_i → ω_o) = F(ω_i·ω_h) D_{ω_i}(ω_h)/(4 ω_i·ω_h) = F D(ω_h)/(4 A(ω_i)),
  ω_h = normalise(ω_i + ω_o), D_ω(m) = ⟨ω·m⟩ D(m)/A(ω) the visible normals [1 eq. 30].

``sample`` runs Algorithm 1: the exit direction of one walk; its weight is the walk's energy Π F (1 when F₀ = 1).
``eval`` is the unbiased estimator of [1 §6]: f cos θ_o = E[Σ_k E_{k−1} p(−ω_r,k → ω_o) G¹(ω_o, h_k)], averaged over
``walks`` walks from ω_i, with the first order replaced by its expectation (a Rao–Blackwellisation: the first
height from +∞ has C¹(h₁) = V^{1/(1 + Λ_i)}, so E[C¹(h₁)^Λ_o] = (1 + Λ_i)/(1 + Λ_i + Λ_o) and the first order is
exactly F D G₂/(4 μ_i) with the height-correlated G₂ = 1/(1 + Λ_i + Λ_o) [1 §4.3]). One-sided (walks from ω_i only)
on purpose: reciprocity f(ω_i, ω_o) = f(ω_o, ω_i) is then a property of the model the checks can test, not one
the estimator enforces.

``pdf`` returns the same estimator with F ≡ 1: the walk's exit density. Fresnel only re-weights paths, so the walk
samples ω_o with density E[Σ_k p G¹ | F = 1] = f_{F=1}(ω_i, ω_o) cos θ_o exactly — the F = 1 microsurface absorbs
nothing, every walker leaves, and its exit density is the energy it reflects. No closed form exists, so the value
returned is an unbiased estimate (exact single scattering + Monte Carlo multiple scattering, ``walks`` walks); for
F₀ = 1, ``pdf`` and ``eval`` are the same estimator. A renderer's MIS weights built from it are noisy (consistent,
not exactly unbiased); the checks here never use MIS.

Randomness: ``sample`` seeds a PCG32 per lane from the bits of (sample1, sample2) (Mitsuba passes 3 uniforms, the
walk needs 3 per bounce); ``eval``/``pdf`` seed from the bits of (ω_i, ω_o), the plug-in's ``seed``, a per-call
counter and the lane index, so repeated calls are independent and a fixed call sequence is deterministic.

Properties: ``alpha`` (0 < α ≤ 2), ``f0`` (Schlick F₀ in [0, 1], default 1), ``walks`` (eval/pdf walks per lane,
default 16), ``max_order`` (bounces before a walk is dropped, default 64), ``seed``. Perturbations for the power
checks only, never in a reference: ``sample_alpha_scale`` (α × s in ``sample`` but not in ``eval``/``pdf``),
``nee_distant_g1`` (next-event shadowing by the distant G₁(ω_o) = 1/(1 + Λ_o) instead of the height-conditioned
G¹(ω_o, h_k) — it forgets that a deep vertex is more shadowed, which breaks reciprocity).
"""

from __future__ import annotations

import math
from typing import Any

from ..backend import init
from ..errors import ValidateError

PLUGIN = "microsurface_walk"
START_HEIGHT = 1.0 + (2.0 * 0.999 - 1.0)  # 1 + C¹⁻¹(0.999) [1]'s code: above every microsurface point, C¹ = 1
_REGISTERED = False


# ---------------------------------------------------------------- the microsurface (drjit, any variant)

def lambda_ggx(w: Any, alpha: Any) -> Any:
    """Smith Λ(ω) of isotropic GGX, signed below the horizon [1 §5.1]: Λ(−ω) = −1 − Λ(ω)."""
    import drjit as dr

    z = dr.clip(w.z, -1.0, 1.0)
    a2t2 = alpha * alpha * dr.maximum(1.0 - z * z, 0.0) / dr.maximum(z * z, 1e-30)
    lam = 0.5 * (-1.0 + dr.sign(z) * dr.sqrt(1.0 + a2t2))
    return dr.select(z > 0.9999, 0.0, dr.select(z < -0.9999, -1.0, lam))


def projected_area(w: Any, alpha: Any) -> Any:
    """A(ω) = ∫ ⟨ω·m⟩ D(m) dm = (ω_z + √(ω_z² + α² sin²θ))/2 for GGX [3], positive for every ω except −n."""
    import drjit as dr

    z = dr.clip(w.z, -1.0, 1.0)
    return 0.5 * (z + dr.sqrt(z * z + alpha * alpha * dr.maximum(1.0 - z * z, 0.0)))


def ndf_ggx(m: Any, alpha: Any) -> Any:
    """GGX D(m) = α²/(π (m_z²(α² − 1) + 1)²) on the upper hemisphere (0 below)."""
    import drjit as dr

    t = m.z * m.z * (alpha * alpha - 1.0) + 1.0
    return dr.select(m.z > 0.0, alpha * alpha / (dr.pi * t * t), 0.0)


def schlick(f0: Any, c: Any) -> Any:
    """Schlick's Fresnel F₀ + (1 − F₀)(1 − c)⁵."""
    import drjit as dr

    x = 1.0 - dr.clip(c, 0.0, 1.0)
    x2 = x * x
    return f0 + (1.0 - f0) * x2 * x2 * x


def _c1(h: Any) -> Any:
    import drjit as dr

    return dr.clip(0.5 * (h + 1.0), 0.0, 1.0)


def _inv_c1(u: Any) -> Any:
    import drjit as dr

    return dr.clip(2.0 * u - 1.0, -1.0, 1.0)


def shadowing_height(w: Any, h: Any, alpha: Any, lam: Any = None) -> Any:
    """G¹(ω, h) = C¹(h)^Λ(ω): probability that a ray leaving height h along ω (upward) escapes [1 eq. 23];
    ``lam``: Λ(ω) when the caller has it (:func:`lambda_ggx`, e.g. formed once outside a loop)."""
    import drjit as dr

    g = dr.power(_c1(h), lambda_ggx(w, alpha) if lam is None else lam)
    return dr.select(w.z > 0.9999, 1.0, dr.select(w.z <= 0.0, 0.0, g))


def shadowing_distant(w: Any, alpha: Any) -> Any:
    """Distant G₁(ω) = 1/(1 + Λ(ω)) (ω upward): G¹ averaged over the heights, not conditioned on one."""
    import drjit as dr

    return dr.select(w.z > 0.0, 1.0 / (1.0 + lambda_ggx(w, alpha)), 0.0)


def sample_height(wr: Any, hr: Any, u: Any, alpha: Any) -> tuple[Any, Any]:
    """Next height along ω_r from h_r [1 eq. 24–26]: (h, escaped). Near-vertical and near-horizontal rays as in
    the authors' code (straight down: C¹(h) = U C¹(h_r); horizontal: h = h_r)."""
    import drjit as dr

    z = wr.z
    lam = lambda_ggx(wr, alpha)
    c = _c1(hr)
    g1 = dr.select(z > 0.9999, 1.0, dr.select(z <= 0.0, 0.0, dr.power(c, lam)))
    escaped = (z > 0.9999) | (u > 1.0 - g1)
    p = dr.power(1.0 - u, 1.0 / dr.select(dr.abs(lam) > 1e-12, lam, 1e-12))
    h = _inv_c1(dr.select(p > 0.0, c / p, 1.0))
    h = dr.select(z < -0.9999, _inv_c1(u * c), h)
    h = dr.select(dr.abs(z) < 1e-4, hr, h)
    return h, escaped


def sample_vndf(wi: Any, alpha: Any, u1: Any, u2: Any) -> Any:
    """Visible GGX normal for ω_i (either hemisphere) by Dupuy & Benyoub's spherical cap [2]: in the stretched
    configuration sample z uniformly on [−s_z, 1] and φ on [0, 2π), add s, unstretch and normalise."""
    import drjit as dr
    import mitsuba as mi

    s = dr.normalize(mi.Vector3f(alpha * wi.x, alpha * wi.y, wi.z))
    phi = 2.0 * dr.pi * u1
    z = (1.0 - u2) * (1.0 + s.z) - s.z
    st = dr.safe_sqrt(1.0 - z * z)
    sp, cp = dr.sincos(phi)
    h = mi.Vector3f(st * cp + s.x, st * sp + s.y, z + s.z)
    return dr.normalize(mi.Vector3f(alpha * h.x, alpha * h.y, h.z))


def phase_conductor(wi: Any, wo: Any, alpha: Any, f0: Any) -> Any:
    """p(ω_i → ω_o) = F(ω_i·ω_h) D(ω_h)/(4 A(ω_i)) for ω_i·ω_h > 0 [1 eq. 30 with Schlick's F]."""
    import drjit as dr

    h = dr.normalize(wi + wo)
    c = dr.dot(wi, h)
    v = schlick(f0, c) * ndf_ggx(h, alpha) / (4.0 * dr.maximum(projected_area(wi, alpha), 1e-12))
    return dr.select((c > 0.0) & (h.z > 0.0), v, 0.0)


def single_scattering(wi: Any, wo: Any, alpha: Any, f0: Any) -> Any:
    """First order of the walk in closed form: f₁ cos θ_o = F D(ω_h) G₂/(4 μ_i), G₂ = 1/(1 + Λ_i + Λ_o) [1 §4.3]."""
    import drjit as dr

    h = dr.normalize(wi + wo)
    g2 = 1.0 / (1.0 + lambda_ggx(wi, alpha) + lambda_ggx(wo, alpha))
    v = schlick(f0, dr.dot(wi, h)) * ndf_ggx(h, alpha) * g2 / (4.0 * dr.maximum(wi.z, 1e-12))
    return dr.select((wi.z > 0.0) & (wo.z > 0.0), v, 0.0)


# ---------------------------------------------------------------- the walks

def _opaque(x: Any) -> Any:
    """A JIT variable rather than a literal (α and F₀ are not folded into the loop: with F₀ = 1 the energy update
    E·F would fold to E, and a symbolic loop re-recorded inside a render then sees its state change type)."""
    import drjit as dr
    import mitsuba as mi

    return dr.opaque(mi.Float, x) if dr.is_jit_v(mi.Float) and isinstance(x, (int, float)) else x


def walk_sample(wi: Any, alpha: Any, f0: Any, rng: Any, max_order: int) -> tuple[Any, Any, Any]:
    """Algorithm 1 of [1]: one walk from ω_i per lane → (ω_o, energy Π F, order). A walk that meets the surface a
    (``max_order`` + 1)-th time is dropped (energy 0), as :func:`walk_eval` drops those orders."""
    import drjit as dr
    import mitsuba as mi

    alpha, f0 = _opaque(alpha), _opaque(f0)
    n = dr.width(wi)
    state = (-wi, dr.full(mi.Float, START_HEIGHT, n), dr.full(mi.Float, 1.0, n), dr.zeros(mi.UInt32, n),
             wi.z > 0.0, wi.z < 0.0, rng)

    def body(wr: Any, hr: Any, energy: Any, order: Any, alive: Any, dropped: Any, rng: Any) -> tuple[Any, ...]:
        h, esc = sample_height(wr, hr, rng.next_float32(), alpha)
        m = sample_vndf(-wr, alpha, rng.next_float32(), rng.next_float32())
        c = dr.dot(-wr, m)
        hit = alive & (esc ^ True)  # not ~esc: a scalar variant's Python bool inverts to an int
        dropped = dropped | (hit & (order >= max_order))
        go = hit & (order < max_order)
        wr = dr.select(go, 2.0 * c * m + wr, wr)
        energy = dr.select(go, energy * schlick(f0, c), energy)
        return wr, dr.select(go, h, hr), energy, dr.select(go, order + 1, order), go, dropped, rng

    wr, _, energy, order, _, dropped, _ = dr.while_loop(state, lambda *s: s[4], body,
                                                        label="microsurface_walk_sample")
    return wr, dr.select(dropped | (wr.z <= 0.0), 0.0, energy), order


def walk_eval(wi: Any, wo: Any, alpha: Any, f0: Any, rng: Any, walks: int, max_order: int,
              distant_g1: bool = False) -> tuple[Any, Any]:
    """[1 §6]'s estimator of f(ω_i, ω_o) cos θ_o, ``walks`` walks per lane → (mean, variance of the mean).

    Order 1 exact (:func:`single_scattering`); orders k ≥ 2 by next-event estimation: each vertex adds
    E_{k−1} p(−ω_r → ω_o) G¹(ω_o, h_k) (E_{k−1} the energy after k − 1 bounces). The variance is the sample
    variance of the per-walk sums over the walks (0 for one walk)."""
    mean, var, _ = walk_eval_state(wi, wo, alpha, f0, rng, walks, max_order, distant_g1)
    return mean, var


def walk_eval_state(wi: Any, wo: Any, alpha: Any, f0: Any, rng: Any, walks: int, max_order: int,
                    distant_g1: bool = False,
                    resume: tuple[Any, ...] | None = None) -> tuple[Any, Any, tuple[Any, ...]]:
    """:func:`walk_eval` → (mean, variance of the mean, the loop's final state). ``resume``: the final state of an
    earlier call with the same ω_i, ω_o, α, F₀ and ``rng`` seed but fewer walks; each lane's walks run one after
    another from its own stream, and a lane's state after w walks is what a longer call holds after its first w,
    so the call continues from there (``rng`` unused) and returns what a fresh call of ``walks`` walks returns,
    bit for bit, without repeating the first w walks."""
    import drjit as dr
    import mitsuba as mi

    alpha, f0 = _opaque(alpha), _opaque(f0)
    n = dr.width(wi) if dr.width(wi) > 1 else dr.width(wo)
    zero = dr.zeros(mi.Float, n)
    start = -wi + mi.Vector3f(zero, zero, zero)
    valid = (wi.z > 0.0) & (wo.z > 0.0)
    # the loop invariants of the next-event shadowing, formed once outside the loop (the same values)
    g_distant = shadowing_distant(wo, alpha) if distant_g1 else None
    lam_o = None if distant_g1 else lambda_ggx(wo, alpha)

    def body(wr: Any, hr: Any, energy: Any, order: Any, acc: Any, s1: Any, s2: Any, k: Any,
             rng: Any) -> tuple[Any, ...]:
        h, esc = sample_height(wr, hr, rng.next_float32(), alpha)
        esc = esc | (order >= max_order)
        g = g_distant if distant_g1 else shadowing_height(wo, h, alpha, lam_o)
        nee = energy * phase_conductor(-wr, wo, alpha, f0) * g
        acc = acc + dr.select((esc ^ True) & (order >= 1), nee, 0.0)
        m = sample_vndf(-wr, alpha, rng.next_float32(), rng.next_float32())
        c = dr.dot(-wr, m)
        s1 = dr.select(esc, s1 + acc, s1)
        s2 = dr.select(esc, s2 + acc * acc, s2)
        k = dr.select(esc, k + 1, k)
        wr = dr.select(esc, start, 2.0 * c * m + wr)
        hr = dr.select(esc, START_HEIGHT, h)
        energy = dr.select(esc, 1.0, energy * schlick(f0, c))
        order = dr.select(esc, 0, order + 1)
        return wr, hr, energy, order, dr.select(esc, 0.0, acc), s1, s2, k, rng

    if resume is None:
        state = (start, zero + START_HEIGHT, zero + 1.0, dr.zeros(mi.UInt32, n), zero, zero, zero,
                 dr.select(valid, dr.zeros(mi.UInt32, n), walks), rng)
    else:  # an invalid lane never walks: its count is the new total
        state = (*resume[:7], dr.select(valid, resume[7], walks), resume[8])
    state = dr.while_loop(state, lambda *s: s[7] < walks, body, label="microsurface_walk_eval")
    s1, s2 = state[5], state[6]
    mean = s1 / walks
    var = dr.maximum(s2 / walks - mean * mean, 0.0) * walks / max(walks - 1, 1) / walks
    return (dr.select(valid, single_scattering(wi, wo, alpha, f0) + mean, 0.0), dr.select(valid, var, 0.0),
            tuple(state))


# ---------------------------------------------------------------- seeding

def _bits(x: Any) -> Any:
    """The IEEE-754 bits of a float32 (array or scalar), as UInt32."""
    import struct

    import drjit as dr
    import mitsuba as mi

    if isinstance(x, float):  # scalar variants
        return struct.unpack("<I", struct.pack("<f", x))[0]
    return dr.reinterpret_array(mi.UInt32, mi.Float(x))


def rng_from(values: list[Any], seed: int, lane: Any = None) -> Any:
    """A PCG32 per lane whose stream is a TEA hash of the float bits of ``values`` and ``seed`` (and the lane index
    when given): distinct inputs give independent streams, equal inputs the same one. Outside a symbolic scope the
    seed is an opaque JIT value, not a literal: every seed then reuses the same compiled kernels (a literal is baked
    into the kernel, so each new seed compiled the whole walk loop again); the values are the same integers."""
    import drjit as dr
    import mitsuba as mi

    jit = dr.is_jit_v(mi.Float) and not dr.flag(dr.JitFlag.SymbolicScope)
    v0 = dr.opaque(mi.UInt32, seed & 0xFFFFFFFF) if jit else mi.UInt32(seed & 0xFFFFFFFF)
    v1 = mi.UInt32(0x9E3779B9)
    for x in values:
        v0, v1 = mi.sample_tea_32(v0 ^ _bits(x), v1)
    if lane is not None:
        v0, v1 = mi.sample_tea_32(v0, v1 ^ lane)
    return mi.PCG32(initstate=mi.UInt64(v0), initseq=mi.UInt64(v1))


# ---------------------------------------------------------------- the plug-in

def register() -> str:
    """Register the ``microsurface_walk`` BSDF with Mitsuba (once per process) and return its name."""
    global _REGISTERED
    init()
    if _REGISTERED:
        return PLUGIN
    import mitsuba as mi

    mi.register_bsdf(PLUGIN, lambda props: _plugin_class()(props))
    _REGISTERED = True
    return PLUGIN


def _props(props: Any) -> dict[str, Any]:
    """The plug-in's properties, checked (one-line ValidateError naming the accepted ranges)."""
    p = {"alpha": float(props.get("alpha", 0.5)), "f0": float(props.get("f0", 1.0)),
         "walks": int(props.get("walks", 16)), "max_order": int(props.get("max_order", 64)),
         "seed": int(props.get("seed", 0)), "sample_alpha_scale": float(props.get("sample_alpha_scale", 1.0)),
         "nee_distant_g1": bool(props.get("nee_distant_g1", False))}
    if not (0.0 < p["alpha"] <= 2.0 and 0.0 <= p["f0"] <= 1.0 and p["walks"] >= 1 and p["max_order"] >= 1
            and math.isfinite(p["sample_alpha_scale"]) and p["sample_alpha_scale"] > 0.0):
        raise ValidateError(f"{PLUGIN}: alpha={p['alpha']}, f0={p['f0']}, walks={p['walks']}, "
                            f"max_order={p['max_order']}: expected 0 < alpha <= 2, f0 in [0, 1], walks >= 1, "
                            "max_order >= 1")
    return p


def _plugin_class() -> type:
    import drjit as dr
    import mitsuba as mi

    class MicrosurfaceWalk(mi.BSDF):
        """GGX conductor with multiple scattering: Heitz et al. 2016's random walk (see the module docstring)."""

        def __init__(self, props: Any) -> None:
            super().__init__(props)
            self.p = _props(props)
            self.calls = 0
            self.m_flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.FrontSide
            self.m_components = [self.m_flags]

        def _enabled(self, ctx: Any, si: Any, active: Any) -> Any:
            return active & (mi.Frame3f.cos_theta(si.wi) > 0.0) & ctx.is_enabled(mi.BSDFFlags.GlossyReflection)

        def _rng(self, si: Any, wo: Any, fixed: bool) -> Any:
            """``fixed``: a pure function of (ω_i, ω_o, seed) — ``pdf`` and ``bs.pdf`` must agree for MIS weights
            to sum to 1; otherwise (``eval``) fresh per call and lane, independent of the pdf's."""
            if fixed:
                return rng_from([si.wi.x, si.wi.y, si.wi.z, wo.x, wo.y, wo.z], self.p["seed"] * 7919)
            self.calls += 1
            n = max(dr.width(si.wi), dr.width(wo))
            jit = dr.is_jit_v(mi.Float) and not dr.flag(dr.JitFlag.SymbolicScope)
            lane = dr.arange(mi.UInt32, n) if jit else None
            return rng_from([si.wi.x, si.wi.y, si.wi.z, wo.x, wo.y, wo.z], self.p["seed"] * 7919 + self.calls, lane)

        def _estimate(self, si: Any, wo: Any, f0: float, fixed: bool = False) -> tuple[Any, Any]:
            return walk_eval(si.wi, wo, self.p["alpha"], f0, self._rng(si, wo, fixed), self.p["walks"],
                             self.p["max_order"], self.p["nee_distant_g1"])

        def sample(self, ctx: Any, si: Any, sample1: Any, sample2: Any, active: Any = True) -> Any:
            rng = rng_from([sample1, sample2.x, sample2.y], self.p["seed"])
            alpha = self.p["alpha"] * self.p["sample_alpha_scale"]
            wo, energy, _ = walk_sample(si.wi, alpha, self.p["f0"], rng, self.p["max_order"])
            ok = self._enabled(ctx, si, active) & (energy > 0.0)
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = wo
            bs.pdf = dr.select(ok, self._pdf(si, wo), 0.0)
            bs.eta = 1.0
            bs.sampled_type = mi.UInt32(+mi.BSDFFlags.GlossyReflection)
            bs.sampled_component = mi.UInt32(0)
            return bs, dr.select(ok, mi.Spectrum(energy), mi.Spectrum(0.0))

        def _pdf(self, si: Any, wo: Any) -> Any:
            return self._estimate(si, wo, 1.0, fixed=True)[0]

        def eval(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            v, _ = self._estimate(si, wo, self.p["f0"])
            return dr.select(self._enabled(ctx, si, active), mi.Spectrum(v), mi.Spectrum(0.0))

        def pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            return dr.select(self._enabled(ctx, si, active), self._pdf(si, wo), 0.0)

        def eval_pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def pdf_state(self, si: Any, wo: Any, resume: tuple[Any, ...] | None = None) -> tuple[Any, tuple[Any, ...]]:
            """``pdf`` (default context) and the walk loop's final state; ``resume``: an earlier call's state with
            fewer ``walks`` (:func:`walk_eval_state`: the same values as a fresh call)."""
            rng = self._rng(si, wo, True)
            v, _, state = walk_eval_state(si.wi, wo, self.p["alpha"], 1.0, rng, self.p["walks"], self.p["max_order"],
                                          self.p["nee_distant_g1"], resume)
            return dr.select(self._enabled(mi.BSDFContext(), si, True), v, 0.0), state

        def estimate(self, si: Any, wo: Any, f0: float | None = None) -> tuple[Any, Any]:
            """(f cos θ_o estimate, its variance) — :func:`walk_eval` with this plug-in's settings (F₀ by default)."""
            return self._estimate(si, wo, self.p["f0"] if f0 is None else f0)

        def traverse(self, callback: Any) -> None:
            return None

        def to_string(self) -> str:
            return f"MicrosurfaceWalk[{', '.join(f'{k}={v}' for k, v in self.p.items())}]"

    return MicrosurfaceWalk


# ---------------------------------------------------------------- checks of the plug-in (χ², reciprocity, furnace)

def _bsdf_dict(alpha: float, f0: float, walks: int, seed: int, **extra: Any) -> dict[str, Any]:
    """The plug-in's ``load_dict`` entry, checked here (Mitsuba would wrap the ValidateError in its parser's)."""
    d = {"type": register(), "alpha": float(alpha), "f0": float(f0), "walks": int(walks), "seed": int(seed), **extra}
    _props(d)
    return d


def load_bsdf(alpha: float, f0: float = 1.0, walks: int = 16, seed: int = 0, **extra: Any) -> Any:
    """A ``microsurface_walk`` instance (bad properties → one-line ValidateError)."""
    import mitsuba as mi

    return mi.load_dict(_bsdf_dict(alpha, f0, walks, seed, **extra))


def _direction(theta_deg: float, phi_deg: float = 0.0) -> list[float]:
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def _pdf_grid(res: tuple[int, int], ires: int, count: int) -> tuple[Any, Any, Any]:
    """The integration points and trapezoid weights of Mitsuba's ``ChiSquareTest.tabulate_pdf`` (same layout:
    cell-major, ``ires``² points per cell, SphericalDomain (φ, −cos θ) ∈ [−π, π] × [−1, 1]) → (directions (N, 3),
    weights (N,) × ``count``, cell index (N,))."""
    import numpy as np

    nx, ny = res
    size = np.array([2.0 * np.pi / nx, 2.0 / ny])
    step = size / (ires - 1)
    cell = np.repeat(np.arange(nx * ny), ires * ires)
    k = np.tile(np.arange(ires * ires), nx * ny)
    sx, sy = k % ires, k // ires
    cx, cy = cell % nx, cell // nx
    px = -np.pi + cx * size[0] + (sx + 1e-4) * (1 - 2e-4) * step[0]
    py = -1.0 + cy * size[1] + (sy + 1e-4) * (1 - 2e-4) * step[1]
    w = np.where((sx == 0) | (sx == ires - 1), 0.5, 1.0) * np.where((sy == 0) | (sy == ires - 1), 0.5, 1.0)
    ct = -py
    st = np.sqrt(np.maximum(1.0 - ct * ct, 0.0))
    d = np.stack([np.cos(px) * st, np.sin(px) * st, ct], -1)
    return d, w * step[0] * step[1] * count, cell


def pooled_chi2(observed: Any, expected: Any, variance: Any, min_expected: float = 5.0) -> tuple[float, int]:
    """Pearson's statistic with the expected counts' own Monte Carlo variance added to the Poisson one:
    X² = Σ (O − Ê)²/(Ê + Var Ê), cells sorted by Ê and pooled until each holds ≥ ``min_expected`` (as Mitsuba's
    ``math.chi2``); returns (X², degrees of freedom = pooled cells − 1)."""
    import numpy as np

    idx = np.argsort(expected)
    o, e, v = (np.asarray(a, dtype=np.float64)[idx] for a in (observed, expected, variance))
    cells: list[tuple[float, float, float]] = []
    acc = np.zeros(3)
    for row in zip(o, e, v, strict=True):
        acc += row
        if acc[1] >= min_expected:
            cells.append(tuple(acc))
            acc = np.zeros(3)
    if acc[1] > 0 and cells:
        cells[-1] = tuple(np.asarray(cells[-1]) + acc)
    c = np.asarray(cells)
    return float(np.sum((c[:, 0] - c[:, 1]) ** 2 / (c[:, 1] + c[:, 2]))), len(c) - 1


# chi2_walk's last pdf evaluation: {"key": (α, θ_i, walks, seed, repeats, grid), "vals": (repeats, points)}. The
# expected counts are a deterministic function of these (``pdf`` seeds from (ω_i, ω_o, seed) alone) and never see
# ``extra``, so a power check right after its case (the same settings, a perturbed sampler) reuses them.
_PDF_MEMO: dict[str, Any] = {}
# chi2_walk's last histogram: {"key": (α, θ_i, samples, seed, grid, the sampler's properties), "state": the harness's
# fields after ``tabulate_histogram``}. ``sample`` never reads ``walks`` (only ``bs.pdf`` does, which the adapter
# drops: it returns ``bs.wo`` and the weight), so a case re-run with more pdf walks has the same histogram.
_HISTOGRAM_MEMO: dict[str, Any] = {}
# chi2_walk's last pdf walk states per repeat {"key": (α, θ_i, seed, grid), "walks", "states": {repeat: state}}:
# repeat r's plug-in seed is seed + 1000 (r + 1) whatever the walks, so a case re-run with 4× the walks continues
# each repeat's walks (walk_eval_state) instead of repeating them; the expected counts are those of a fresh run.
_PDF_STATES: dict[str, Any] = {}


def chi2_walk(alpha: float, theta_i: float, samples: int, seed: int, res: int = 31, ires: int = 4, repeats: int = 4,
              walks: int = 8, test_count: int = 1, significance: float = 0.01, **extra: Any) -> dict[str, Any]:
    """χ² goodness of fit of ``sample`` against ``pdf`` for the plug-in at (α, θ_i), F₀ = 1, with Mitsuba's harness.

    Histogram: ``mitsuba.chi2.ChiSquareTest.tabulate_histogram`` on ``BSDFAdapter`` (``samples`` walks). Expected
    counts: the harness's cell integration (trapezoid rule, ``ires``² points per cell, same grid) of ``pdf`` through
    the adapter's ``pdf_functor``, ``repeats`` independent plug-in seeds of ``walks`` walks each; their spread gives
    each cell's Monte Carlo variance. Why not the harness's ``run`` alone: Pearson's X² assumes exact expected
    counts; here they are estimates, whose variance inflates X² (a false rejection when it is comparable to the
    Poisson variance Ê). :func:`pooled_chi2` adds it to the denominator; ``run``'s own p-value (exact-pdf
    assumption) and its sanity checks are reported beside it. ``extra``: plug-in properties (the power checks'
    perturbations, e.g. ``sample_alpha_scale``), which only the sampler sees: the expected counts of the same
    (α, θ_i, walks, seed, repeats, grid) as the previous call are that call's (:data:`_PDF_MEMO`), and the
    histogram of the same sampler (α, θ_i, samples, seed, grid, ``extra``; any ``walks``) that call's
    (:data:`_HISTOGRAM_MEMO`)."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np
    from mitsuba import chi2
    from scipy import stats

    wi = _direction(theta_i)
    sample_func, _ = chi2.BSDFAdapter(register(), _bsdf_dict(alpha, 1.0, walks, seed, **extra), wi=wi)
    test = chi2.ChiSquareTest(domain=chi2.SphericalDomain(), sample_func=sample_func, pdf_func=lambda p: p.x * 0.0,
                              sample_dim=3, sample_count=samples, res=res, ires=ires, seed=seed)
    hkey = (float(alpha), float(theta_i), int(samples), int(seed), int(res), int(ires), repr(sorted(extra.items())))
    if _HISTOGRAM_MEMO.get("key") == hkey:  # the same sampler and samples: the same histogram (see the memo)
        for k, v in _HISTOGRAM_MEMO["state"].items():
            setattr(test, k, v)
    else:
        test.tabulate_histogram()
        _HISTOGRAM_MEMO.clear()
        _HISTOGRAM_MEMO.update(key=hkey, state={k: getattr(test, k) for k in ("histogram", "histogram_sum", "fail",
                                                                                "messages")})
    nx, ny = int(test.res.x), int(test.res.y)
    d, w, cell = _pdf_grid((nx, ny), ires, samples)
    key = (float(alpha), float(theta_i), int(walks), int(seed), int(repeats), nx, ny, int(ires))
    if _PDF_MEMO.get("key") == key:  # the pdf side ignores ``extra`` (a power check's sampler perturbation)
        vals = _PDF_MEMO["vals"]
    else:
        dirs = mi.Vector3f(np.ascontiguousarray(d.T, dtype=np.float32))
        # the walk states of the last pdf evaluation of this (α, θ_i, seed, grid), with fewer walks, continue
        skey = (float(alpha), float(theta_i), int(seed), nx, ny, int(ires))
        states = _PDF_STATES["states"] if _PDF_STATES.get("key") == skey and _PDF_STATES["walks"] < walks else {}
        vals, new_states = [], {}
        for r in range(repeats):
            # the harness's pdf functor (BSDFAdapter: default context, si.wi = ω_i), keeping the walk states
            bsdf = mi.load_dict(_bsdf_dict(alpha, 1.0, walks, seed + 1000 * (r + 1)))
            si = dr.zeros(mi.SurfaceInteraction3f, dr.width(dirs))
            si.wi = wi
            v, new_states[r] = bsdf.pdf_state(si, dirs, states.get(r))
            dr.eval(v, new_states[r])
            vals.append(np.asarray(v, dtype=np.float64))
        vals = np.asarray(vals)
        _PDF_MEMO.clear()
        _PDF_MEMO.update(key=key, vals=vals)
        _PDF_STATES.clear()
        _PDF_STATES.update(key=skey, walks=int(walks), states=new_states)
    mean, var = vals.mean(0), vals.var(0, ddof=1) / repeats
    expected = np.bincount(cell, w * mean, nx * ny)
    variance = np.bincount(cell, w * w * var, nx * ny)
    observed = np.asarray(test.histogram, dtype=np.float64)
    test.pdf = mi.Float(expected.astype(np.float32))
    test.pdf_start = test.pdf_end = test.histogram_start = test.histogram_end = 0.0
    test.pdf_sum = mi.Float(float(expected.sum() / samples))
    harness_ok = test.run(significance_level=significance, test_count=test_count, quiet=True)
    x2, dof = pooled_chi2(observed, expected, variance)
    stray = int(np.sum((expected <= 0) & (observed > 0)))
    p = float(stats.chi2.sf(x2, dof)) if stray == 0 else 0.0
    return {"alpha": alpha, "theta_i": theta_i, "samples": samples, "cells": nx * ny, "dof": dof, "chi2": x2,
            "p_value": p, "harness_p_value": float(test.p_value), "harness_accepts": bool(harness_ok),
            "harness_sanity_fail": bool(test.fail), "stray_samples": stray,
            "histogram_mass": float(observed.sum() / samples), "pdf_mass": float(expected.sum() / samples),
            "variance_ratio": float(np.max(variance[expected > 5] / expected[expected > 5])),
            "perturbation": {k: v for k, v in extra.items()}}


RECIPROCITY_PAIRS = tuple((ta, tb, dphi) for ta, tb in ((15.0, 45.0), (15.0, 75.0), (45.0, 75.0))
                          for dphi in (0.0, 90.0, 180.0))


def reciprocity_walk(alpha: float, f0: float, walks: int, lanes: int, seed: int,
                     pairs: tuple[tuple[float, float, float], ...] = RECIPROCITY_PAIRS,
                     **extra: Any) -> dict[str, Any]:
    """Reciprocity of the one-sided estimator: for each pair (θ_a, θ_b, Δφ), ω_a = (θ_a, 0), ω_b = (θ_b, Δφ),
    a = f̂(ω_a → ω_b) = ``eval``/cos θ_b and b = f̂(ω_b → ω_a) = ``eval``/cos θ_a from independent walks
    (``lanes`` × ``walks`` each), z = (a − b)/√(se_a² + se_b²). The model is reciprocal [1 §6: the conductor phase
    function is, and so is every path's weight], so |z| is a standard normal's under the null."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    bsdf = mi.load_dict(_bsdf_dict(alpha, f0, walks, seed, **extra))
    a_dirs = np.repeat([_direction(ta) for ta, _, _ in pairs], lanes, 0)
    b_dirs = np.repeat([_direction(tb, dphi) for _, tb, dphi in pairs], lanes, 0)

    def one_side(wi: Any, wo: Any) -> tuple[Any, Any]:
        si = dr.zeros(mi.SurfaceInteraction3f, len(wi))
        si.wi = mi.Vector3f(np.ascontiguousarray(wi.T, dtype=np.float32))
        est, var = bsdf.estimate(si, mi.Vector3f(np.ascontiguousarray(wo.T, dtype=np.float32)))
        f = np.asarray(est, dtype=np.float64).reshape(len(pairs), lanes) / wo[::lanes, 2][:, None]
        v = np.asarray(var, dtype=np.float64).reshape(len(pairs), lanes) / wo[::lanes, 2][:, None] ** 2
        return f.mean(1), v.sum(1) / lanes**2

    fa, va = one_side(a_dirs, b_dirs)
    fb, vb = one_side(b_dirs, a_dirs)
    z = (fa - fb) / np.sqrt(va + vb)
    return {"alpha": alpha, "f0": f0, "pairs": [list(p) for p in pairs], "f_ab": fa.tolist(), "f_ba": fb.tolist(),
            "se": np.sqrt(va + vb).tolist(), "z": z.tolist(), "max_abs_z": float(np.max(np.abs(z))),
            "walks_per_side": walks * lanes, "perturbation": dict(extra)}


def furnace_eval(alpha: float, mu_i: float, f0: float, directions: int, walks: int, seed: int,
                 **extra: Any) -> dict[str, float]:
    """Directional albedo from ``eval``: A(μ_i) = ∫ f cos θ_o dω_o = E[eval(ω_o)/q(ω_o)] → value ± standard error,
    ``directions`` directions of ``walks`` walks each. q = ½ cos θ_o/π + ½ q_vis: half the directions cosine-
    distributed, half reflected about a visible normal drawn by Mitsuba's own ``MicrofacetDistribution`` (GGX,
    visible normals), q_vis = pdf(ω_i, ω_h)/(4 ω_i·ω_h) — independent of the plug-in's sampler. At F₀ = 1 the
    theorem (the microsurface absorbs nothing, [1] fig. 7) says A = 1 for every α and μ_i."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    bsdf = mi.load_dict(_bsdf_dict(alpha, f0, walks, seed, **extra))
    rng = np.random.default_rng(seed)
    u1, u2, u3 = (rng.random(directions).astype(np.float32) for _ in range(3))
    wi = mi.Vector3f(float(math.sqrt(1.0 - mu_i * mu_i)), 0.0, float(mu_i))
    md = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, alpha, True)
    m, _ = md.sample(wi, mi.Point2f(mi.Float(u1), mi.Float(u2)))
    spec = mi.reflect(wi, m)
    cos = mi.warp.square_to_cosine_hemisphere(mi.Point2f(mi.Float(u1), mi.Float(u2)))
    wo = dr.select(mi.Bool(u3 < 0.5), spec, cos)
    h = dr.normalize(wi + wo)
    q = 0.5 * dr.maximum(wo.z, 0.0) / dr.pi + 0.5 * md.pdf(wi, h) / (4.0 * dr.abs(dr.dot(wi, h)))
    si = dr.zeros(mi.SurfaceInteraction3f, directions)
    si.wi = wi
    est, _ = bsdf.estimate(si, wo)
    q_np = np.asarray(q, dtype=np.float64)
    ok = (np.asarray(wo.z) > 0.0) & (q_np > 0.0)
    x = np.where(ok, np.asarray(est, dtype=np.float64) / np.where(ok, q_np, 1.0), 0.0)
    return {"alpha": alpha, "mu_i": mu_i, "f0": f0, "albedo": float(x.mean()),
            "se": float(x.std(ddof=1) / math.sqrt(directions)), "directions": directions, "walks": walks}


def single_scatter_vs_mitsuba(alpha: float, n: int, seed: int, alpha_scale: float = 1.0) -> dict[str, float]:
    """The plug-in's closed first order against Mitsuba's ``roughconductor`` (GGX, η = 0, k = 1: F = 1) on ``n``
    random direction pairs: Mitsuba uses the separable G₁(ω_i)G₁(ω_o), the walk the height-correlated G₂, so the
    comparable quantity is f_Mitsuba · G₂/(G₁(ω_i)G₁(ω_o)) with G₁ from Mitsuba's own ``MicrofacetDistribution``
    (Λ = 1/G₁ − 1, G₂ = 1/(1 + Λ_i + Λ_o)) → max relative difference. ``alpha_scale`` perturbs the plug-in's α
    (power check)."""
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    init()
    rng = np.random.default_rng(seed)

    def hemi(k: int) -> np.ndarray:
        u1, u2 = rng.random(k) * 0.97 + 0.02, rng.random(k)
        st = np.sqrt(1.0 - u1 * u1)
        return np.stack([st * np.cos(2 * np.pi * u2), st * np.sin(2 * np.pi * u2), u1], -1)

    wi_np, wo_np = hemi(n), hemi(n)
    wi = mi.Vector3f(np.ascontiguousarray(wi_np.T, dtype=np.float32))
    wo = mi.Vector3f(np.ascontiguousarray(wo_np.T, dtype=np.float32))
    rc = mi.load_dict({"type": "roughconductor", "distribution": "ggx", "alpha": alpha, "eta": 0.0, "k": 1.0})
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = wi
    f_rc = np.asarray(rc.eval(mi.BSDFContext(), si, wo), dtype=np.float64)[0]
    md = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, alpha, True)
    h = dr.normalize(wi + wo)
    g1i = np.asarray(md.smith_g1(wi, h), dtype=np.float64)
    g1o = np.asarray(md.smith_g1(wo, h), dtype=np.float64)
    g2 = 1.0 / (1.0 / g1i + 1.0 / g1o - 1.0)
    ref = f_rc * g2 / (g1i * g1o)
    mine = np.asarray(single_scattering(wi, wo, alpha * alpha_scale, 1.0), dtype=np.float64)
    rel = np.abs(mine - ref) / np.maximum(ref, 1e-12)
    ok = ref > 1e-6 * ref.max()
    return {"alpha": alpha, "pairs": int(ok.sum()), "max_rel_diff": float(rel[ok].max()),
            "separable_max_rel_diff": float((np.abs(mine - f_rc) / np.maximum(f_rc, 1e-12))[ok].max())}


def render_furnace(alpha: float, spp: int, res: int, seed: int, **extra: Any) -> dict[str, Any]:
    """White furnace in Mitsuba's own ``path`` integrator: a unit sphere of the plug-in (F₀ = 1) under a constant
    environment of radiance 1, seen from distance 4 with a 20° field of view (every pixel on the sphere: its
    angular radius is 14.5°, the frame's half-diagonal 14.1°). Every path ends in the environment at weight 1, so
    every pixel's expectation is 1 — through ``sample`` (its energy weight), ``eval`` and ``pdf`` (emitter sampling
    and the MIS weights, which sum to 1 because ``pdf`` and ``bs.pdf`` are the same function). → pixel mean ± its
    standard error (pixels are independent)."""
    import mitsuba as mi
    import numpy as np

    bsdf = _bsdf_dict(alpha, 1.0, 4, seed, **extra)
    scene = mi.load_dict({
        "type": "scene", "integrator": {"type": "path", "max_depth": 256, "rr_depth": 512},
        "sensor": {"type": "perspective", "fov": 20.0,
                   "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": res, "height": res, "rfilter": {"type": "box"}},
                   "sampler": {"type": "independent", "sample_count": spp}},
        "env": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
        "sphere": {"type": "sphere", "bsdf": bsdf}})
    img = np.asarray(mi.render(scene, seed=seed), dtype=np.float64)[:, :, 1]
    return {"alpha": alpha, "spp": spp, "pixels": res * res, "mean": float(img.mean()),
            "se": float(img.std(ddof=1) / res), "perturbation": dict(extra)}


__all__ = ["PLUGIN", "register", "load_bsdf", "chi2_walk", "reciprocity_walk", "furnace_eval", "render_furnace",
           "single_scatter_vs_mitsuba", "pooled_chi2", "walk_sample", "walk_eval", "single_scattering",
           "phase_conductor", "sample_height", "sample_vndf", "lambda_ggx", "rng_from"]

"""The brdf family's shared terms: the shading geometry, Fresnel, microfacet distributions and masking, and the
Oren–Nayar and Cook–Torrance terms that several techniques (and the specular area-light family) evaluate.
References are numbered as in :mod:`validate.local_models.brdf.classic_brdfs`; nothing here registers a technique.

Two forms of each term: numpy float64 (per-parameter set-up such as the multiscatter tables and F_avg, and the
brdfs experiment's term-by-term analysis) and ``*_dr`` on drjit arrays of the family's dtype (float32,
:mod:`validate.local_models.precision`), which the techniques evaluate per direction (:class:`GeometryDr`, colours
as :class:`RGB`, the complex Fresnel in real arithmetic, Beckmann's Λ with ``drjit.erf``)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from functools import cached_property
from typing import Any

import numpy as np
from scipy.special import erf

from ...errors import ValidateError
from ...geometry import NORM_FLOOR, unit

DEFAULTS: dict[str, Any] = {"albedo": 0.0, "ks": 0.0, "exponent": 10.0, "phong_exponent": 10.0, "alpha": 0.3,
                            "distribution": "beckmann", "eta": 0.0, "k": 1.0, "sigma": 0.0, "minnaert_k": 1.0}


def param(params: Mapping[str, Any], key: str, who: str) -> np.ndarray:
    """``params[key]`` (or its default) as a float array broadcastable to (N, 3): scalar or RGB."""
    value = params.get(key, DEFAULTS[key])
    arr = np.asarray(value, dtype=np.float64)
    if arr.ndim > 1 or (arr.ndim == 1 and arr.shape[0] != 3) or not np.all(np.isfinite(arr)):
        raise ValidateError(f"technique '{who}' (brdf): parameter {key}={value!r} must be a finite scalar or RGB")
    return arr if arr.ndim == 1 else arr.reshape(())


class Geometry:
    """Per-sample dot products of (n, l, v): cosines, half vector, mirror direction, azimuth difference. Each is
    formed on first use (``functools.cached_property``, the same float64 expressions): a caller that needs only the
    horizon mask (:meth:`finish`) does not pay for the half vector, cos Δφ and the polar angles."""

    def __init__(self, normals: np.ndarray, lights: np.ndarray, views: np.ndarray):
        self.n, self.l, self.v = unit(normals), unit(lights), unit(views)

    @cached_property
    def cl(self) -> np.ndarray:
        return np.sum(self.n * self.l, axis=-1)

    @cached_property
    def cv(self) -> np.ndarray:
        return np.sum(self.n * self.v, axis=-1)

    @cached_property
    def h(self) -> np.ndarray:
        return unit(self.l + self.v)

    @cached_property
    def ch(self) -> np.ndarray:
        return np.clip(np.sum(self.n * self.h, axis=-1), 0.0, 1.0)

    @cached_property
    def vh(self) -> np.ndarray:
        return np.clip(np.sum(self.v * self.h, axis=-1), 0.0, 1.0)

    @cached_property
    def rv(self) -> np.ndarray:
        r = 2.0 * self.cl[:, None] * self.n - self.l
        return np.sum(r * self.v, axis=-1)

    @cached_property
    def front(self) -> np.ndarray:
        return (self.cl > 0.0) & (self.cv > 0.0)

    @cached_property
    def cos_dphi(self) -> np.ndarray:
        lt = self.l - self.cl[:, None] * self.n
        vt = self.v - self.cv[:, None] * self.n
        norm = np.linalg.norm(lt, axis=-1) * np.linalg.norm(vt, axis=-1)
        return np.where(norm > 1e-12, np.sum(lt * vt, axis=-1) / np.maximum(norm, 1e-300), 0.0)

    @cached_property
    def theta_l(self) -> np.ndarray:
        return np.arccos(np.clip(self.cl, -1.0, 1.0))

    @cached_property
    def theta_v(self) -> np.ndarray:
        return np.arccos(np.clip(self.cv, -1.0, 1.0))

    def finish(self, f_cos: np.ndarray) -> np.ndarray:
        """(N, 3), zero where l or v is below the horizon."""
        return finish_front(self.front, f_cos)


def finish_front(front: np.ndarray, f_cos: np.ndarray) -> np.ndarray:
    """:meth:`Geometry.finish` with the horizon mask given: (N, 3) max(0, f_cos), zero where ``front`` is false."""
    out = np.broadcast_to(np.asarray(f_cos, dtype=np.float64).reshape(len(front), -1), (len(front), 3))
    return np.where(front[:, None], np.maximum(out, 0.0), 0.0)


def front_mask(normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> np.ndarray:
    """:attr:`Geometry.front` (n·l > 0 and n·v > 0 of the unit vectors) by components, the same float64 numbers:
    |x| = √((x₀² + x₁²) + x₂²) and n·l = (n₀l₀ + n₁l₁) + n₂l₂ are the left-to-right sums that ``np.linalg.norm``
    and ``np.sum(·, axis=-1)`` form over a length-3 axis, and x/max(|x|, 10⁻³⁰⁰) is :func:`validate.geometry.unit`."""
    def units(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        m = np.asarray(a, dtype=np.float64).reshape(-1, 3)
        x, y, z = m[:, 0], m[:, 1], m[:, 2]
        r = np.maximum(np.sqrt(x * x + y * y + z * z), NORM_FLOOR)
        return x / r, y / r, z / r

    n, l, v = units(normals), units(lights), units(views)
    cl = n[0] * l[0] + n[1] * l[1] + n[2] * l[2]
    cv = n[0] * v[0] + n[1] * v[1] + n[2] * v[2]
    return (cl > 0.0) & (cv > 0.0)


def column(x: np.ndarray) -> np.ndarray:
    return np.asarray(x, dtype=np.float64)[:, None]


def fresnel_exact(cos_theta: np.ndarray, eta: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Unpolarised Fresnel reflectance of the complex index η + ik at incidence cos θ (conductor or dielectric):
    r_s = (c − ñ c_t)/(c + ñ c_t), r_p = (ñ c − c_t)/(ñ c + c_t), c_t = √(1 − (1 − c²)/ñ²), F = (|r_s|² + |r_p|²)/2."""
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)[:, None]
    n = (np.asarray(eta, dtype=np.float64) + 1j * np.asarray(k, dtype=np.float64)) * np.ones((1, 3))
    n = np.where(np.abs(n) < 1e-12, 1e-12 + 0j, n)
    ct = np.sqrt(1.0 - (1.0 - c * c) / (n * n) + 0j)
    rs = (c - n * ct) / (c + n * ct)
    rp = (n * c - ct) / (n * c + ct)
    return 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)


def fresnel_f0(eta: np.ndarray, k: np.ndarray) -> np.ndarray:
    """Normal-incidence reflectance F₀ = ((η − 1)² + k²)/((η + 1)² + k²) (RGB, (3,))."""
    eta, k = np.asarray(eta, dtype=np.float64) * np.ones(3), np.asarray(k, dtype=np.float64) * np.ones(3)
    return ((eta - 1.0) ** 2 + k * k) / ((eta + 1.0) ** 2 + k * k)


def fresnel_schlick(cos_theta: np.ndarray, f0: np.ndarray) -> np.ndarray:
    """Schlick [8]: F = F₀ + (1 − F₀)(1 − cos θ)⁵, (N, 3)."""
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 0.0, 1.0)[:, None]
    return f0 + (1.0 - f0) * (1.0 - c) ** 5


def beckmann_d(cos_h: np.ndarray, m: float, normalised: bool = True) -> np.ndarray:
    """Beckmann D = exp(−tan²θ_h/m²)/(π m² cos⁴θ_h) ([9] eq. 25); without the π as printed in [6]."""
    c2 = np.maximum(np.asarray(cos_h, dtype=np.float64) ** 2, 1e-12)
    d = np.exp(-(1.0 - c2) / (c2 * m * m)) / (m * m * c2 * c2)
    return np.where(cos_h > 1e-6, d / np.pi if normalised else d, 0.0)


def ggx_d(cos_h: np.ndarray, alpha: float) -> np.ndarray:
    """GGX D = α²/(π cos⁴θ_h (α² + tan²θ_h)²) ([9] eq. 33)."""
    c2 = np.asarray(cos_h, dtype=np.float64) ** 2
    a2 = alpha * alpha
    return np.where(cos_h > 0.0, a2 / (np.pi * (c2 * (a2 - 1.0) + 1.0) ** 2), 0.0)


def smith_g1(cos_theta: np.ndarray, alpha: float, distribution: str) -> np.ndarray:
    """Smith's monodirectional masking G₁ for Beckmann ([9] eq. 25–26, exact, with erf) or GGX ([9] eq. 34)."""
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), 1e-12, 1.0)
    tan = np.sqrt(np.maximum(1.0 - c * c, 0.0)) / c
    if distribution == "ggx":
        return 2.0 / (1.0 + np.sqrt(1.0 + alpha * alpha * tan * tan))
    a = np.minimum(1.0 / np.maximum(alpha * tan, 1e-300), 1e8)  # Λ(a) < 1e-300 beyond a ≈ 26: no masking
    lam = np.where(a < 30.0, 0.5 * (erf(a) - 1.0) + np.exp(-np.minimum(a * a, 700.0)) / (2.0 * a * np.sqrt(np.pi)),
                   0.0)
    return 1.0 / (1.0 + lam)


def vcavity_g(g: Geometry) -> np.ndarray:
    """Cook–Torrance's V-cavity G = min{1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h)} [6]."""
    vh = np.maximum(g.vh, 1e-12)
    return np.minimum(1.0, np.minimum(2.0 * g.ch * g.cv / vh, 2.0 * g.ch * g.cl / vh))


def oren_nayar_ab(sigma: float) -> tuple[float, float]:
    """A = 1 − 0.5σ²/(σ² + 0.33), B = 0.45σ²/(σ² + 0.09) [10] eq. 30."""
    s2 = sigma * sigma
    return 1.0 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)


def scalar_param(params: Mapping[str, Any], key: str, who: str, low: float = -np.inf) -> float:
    arr = param(params, key, who)
    if arr.ndim != 0 or not float(arr) >= low:
        raise ValidateError(f"technique '{who}' (brdf): parameter {key}={arr.tolist()!r} must be a scalar ≥ {low:g}")
    return float(arr)


def distribution_param(params: Mapping[str, Any], who: str) -> str:
    d = str(params.get("distribution", DEFAULTS["distribution"])).lower()
    if d not in ("beckmann", "ggx"):
        raise ValidateError(f"technique '{who}' (brdf): distribution={d!r}; expected 'beckmann' or 'ggx'")
    return d


def cook_torrance_printed_terms(params: Mapping[str, Any], g: Geometry, fresnel: str = "schlick_nl",
                                geometry: str = "vcavity", denominator: str = "printed",
                                normalised_d: bool = False) -> np.ndarray:
    """The specular part of Ganovelli's Cook–Torrance with each term switchable (term-by-term analysis):
    ``fresnel`` 'schlick_nl' (printed) | 'schlick_vh' | 'exact'; ``geometry`` 'vcavity' | 'smith';
    ``denominator`` 'printed' ((n·l)(n·v)) | 'walter' (4(n·l)(n·v)); ``normalised_d`` adds the 1/π.
    Returns S/π (π-folded light) ≙ f_r·(n·l), (N, 3)."""
    who = "cook_torrance_printed"
    m = scalar_param(params, "alpha", who, 1e-4)
    eta, k = param(params, "eta", who), param(params, "k", who)
    f0 = fresnel_f0(eta, k)
    if fresnel == "schlick_nl":
        f = fresnel_schlick(g.cl, f0)
    elif fresnel == "schlick_vh":
        f = fresnel_schlick(g.vh, f0)
    else:
        f = fresnel_exact(g.vh, eta, k)
    d = beckmann_d(g.ch, m, normalised=normalised_d)
    gg = vcavity_g(g) if geometry == "vcavity" else smith_g1(g.cl, m, "beckmann") * smith_g1(g.cv, m, "beckmann")
    denom = np.maximum(g.cl * g.cv, 1e-12) * (4.0 if denominator == "walter" else 1.0)
    spec = f * column(d * gg / denom * g.cl)
    return spec / np.pi


def microfacet_specular(params: Mapping[str, Any], g: Geometry, who: str = "cook_torrance") -> np.ndarray:
    """F(v·h) D G₁(l) G₁(v) / (4 (n·l)(n·v)) · (n·l) [9] eq. 20, (N, 3)."""
    a = scalar_param(params, "alpha", who, 1e-4)
    dist = distribution_param(params, who)
    d = beckmann_d(g.ch, a) if dist == "beckmann" else ggx_d(g.ch, a)
    gg = smith_g1(g.cl, a, dist) * smith_g1(g.cv, a, dist)
    f = fresnel_exact(g.vh, param(params, "eta", who), param(params, "k", who))
    return f * column(d * gg / (4.0 * np.maximum(g.cv, 1e-12)))


def alpha_beta(g: Geometry) -> tuple[np.ndarray, np.ndarray]:
    return np.maximum(g.theta_l, g.theta_v), np.minimum(g.theta_l, g.theta_v)


def oren_nayar_full_terms(sigma: float, albedo: np.ndarray, g: Geometry) -> tuple[np.ndarray, np.ndarray]:
    """(direct L₁, inter-reflection L₂) of the full model [10] eq. 27–29, each as f_r·(n·l), (N, 3)."""
    s2 = sigma * sigma
    al, be = alpha_beta(g)
    be = np.minimum(be, np.pi / 2 - 1e-9)
    cd = g.cos_dphi
    c1 = 1.0 - 0.5 * s2 / (s2 + 0.33)
    c2 = np.where(cd >= 0.0, 0.45 * s2 / (s2 + 0.09) * np.sin(al),
                  0.45 * s2 / (s2 + 0.09) * (np.sin(al) - (2.0 * be / np.pi) ** 3))
    c3 = 0.125 * s2 / (s2 + 0.09) * (4.0 * al * be / np.pi ** 2) ** 2
    direct = c1 + cd * c2 * np.tan(be) + (1.0 - np.abs(cd)) * c3 * np.tan(0.5 * (al + be))
    inter = 0.17 * s2 / (s2 + 0.13) * (1.0 - cd * (2.0 * be / np.pi) ** 2)
    return (albedo / np.pi * column(direct * g.cl), albedo * albedo / np.pi * column(inter * g.cl))


# ---------------------------------------------------------------------------------------------
# The same terms on drjit arrays, in the family's dtype (:mod:`validate.local_models.precision`): what the
# techniques evaluate per direction. The numpy functions above stay for per-parameter set-up (the multiscatter
# tables, F_avg) and for the brdfs experiment's term-by-term analysis.

def _dr() -> Any:
    import drjit as dr  # noqa: PLC0415 — drjit is imported lazily across local_models

    return dr


class RGB:
    """Three channels, each a drjit array or a number; +, −, ×, ÷ channel by channel (with an RGB, a drjit array or
    a number), so a (N, 3) numpy expression ports term for term."""

    __slots__ = ("ch",)

    def __init__(self, r: Any, g: Any = None, b: Any = None):
        self.ch = (r, r, r) if g is None else (r, g, b)

    @staticmethod
    def of(x: Any) -> RGB:
        """An RGB as is; a (3,) numpy / sequence channel by channel; a number or a drjit array on all three."""
        if isinstance(x, RGB):
            return x
        if isinstance(x, np.ndarray) or isinstance(x, (tuple, list)):
            a = np.asarray(x, dtype=np.float64)
            return RGB(float(a)) if a.ndim == 0 else RGB(*(float(c) for c in a.reshape(3)))
        return RGB(x)

    def map(self, f: Any, *others: Any) -> RGB:
        rest = [RGB.of(o).ch for o in others]
        return RGB(*(f(c, *(o[i] for o in rest)) for i, c in enumerate(self.ch)))

    def __add__(self, o: Any) -> RGB:
        return self.map(lambda a, b: a + b, o)

    __radd__ = __add__

    def __sub__(self, o: Any) -> RGB:
        return self.map(lambda a, b: a - b, o)

    def __rsub__(self, o: Any) -> RGB:
        return self.map(lambda a, b: b - a, o)

    def __mul__(self, o: Any) -> RGB:
        return self.map(lambda a, b: a * b, o)

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> RGB:
        return self.map(lambda a, b: a / b, o)

    def __rtruediv__(self, o: Any) -> RGB:
        return self.map(lambda a, b: b / a, o)

    def __neg__(self) -> RGB:
        return self.map(lambda a: -a)

    def to_np(self, n: int) -> np.ndarray:
        """(n, 3) float64 numpy (numbers broadcast)."""
        from ..precision import rgb_to_np  # noqa: PLC0415

        return rgb_to_np(*self.ch, n)


def rgb_param(params: Mapping[str, Any], key: str, who: str) -> RGB:
    """:func:`param` as an :class:`RGB` of numbers (a scalar on all three channels)."""
    return RGB.of(param(params, key, who))


def _tiny() -> float:
    """A positive floor that is not flushed to zero in the active dtype (float32's smallest normal is 1.2e-38)."""
    from ..precision import active  # noqa: PLC0415

    return 1e-300 if active() == "float64" else 1e-30


def below_half_pi() -> float:
    """The largest angle < π/2 of the active dtype (π/2 − 1e-9 rounds up to float32's π/2, whose tan is < 0)."""
    from ..precision import active  # noqa: PLC0415

    return np.pi / 2 - 1e-9 if active() == "float64" else float(np.nextafter(np.float32(np.pi / 2), np.float32(0)))


def _dot(a: tuple[Any, Any, Any], b: tuple[Any, Any, Any]) -> Any:
    return _dr().fma(a[0], b[0], _dr().fma(a[1], b[1], a[2] * b[2]))


def _unit(a: tuple[Any, Any, Any]) -> tuple[Any, Any, Any]:
    dr = _dr()
    inv = dr.rsqrt(dr.maximum(_dot(a, a), _tiny()))
    return a[0] * inv, a[1] * inv, a[2] * inv


def acos_dr(x: Any) -> Any:
    """:func:`validate.local_models.precision.acos` (arccos on every drjit backend)."""
    from ..precision import acos  # noqa: PLC0415

    return acos(x)


def _number(x: Any) -> bool:
    return isinstance(x, (int, float, np.floating, np.integer))


def opaque(*values: float) -> list[Any]:
    """Per-call numbers (a BRDF parameter, a product of parameters formed in float64) as opaque drjit values of the
    active dtype (:func:`validate.local_models.precision.constants_dr`): the same float32 (float64) value the Python
    literal was rounded to, but not baked into the kernel, so a new parameter reuses the compiled kernel."""
    from ..precision import constants_dr  # noqa: PLC0415

    return constants_dr(np.asarray(values, dtype=np.float64))


def opaque_rgb(x: Any) -> RGB:
    """An :class:`RGB` (or anything :meth:`RGB.of` takes) with each number channel opaque (:func:`opaque`; always
    three values, so a scalar and an RGB parameter give the same kernel), drjit channels as they are."""
    ch = RGB.of(x).ch
    nums = [float(c) for c in ch if _number(c)]
    vals = iter(opaque(*nums)) if nums else iter(())
    return RGB(*(next(vals) if _number(c) else c for c in ch))


POWER_BITS = 10  # integral exponents 0 … 2¹⁰ − 1 take the opaque multiply chain of :func:`power_dr`


def power_dr(x: Any, s: float) -> Any:
    """``drjit.power(x, s)`` bit for bit with the exponent opaque. drjit expands an integral Python exponent into
    the square-and-multiply chain (r ← r·p on bit i of s, p ← p²) and any other one into exp2(log2(x)·s) (its
    documented rule); the same chain runs here over :data:`POWER_BITS` bits selected by opaque 0/1 values, and the
    general case with an opaque s, so a new exponent reuses the kernel. A negative integral exponent (drjit's
    reciprocal of the chain) keeps the literal."""
    dr = _dr()
    s = float(s)
    if s.is_integer() and 0.0 <= s < 2 ** POWER_BITS:
        k = int(s)
        bits = opaque(*((k >> i) & 1 for i in range(POWER_BITS)))
        res, p = dr.full(type(x), 1.0, dr.width(x)), x
        for i, b in enumerate(bits):
            res = dr.select(b > 0.5, res * p, res)
            if i + 1 < POWER_BITS:
                p = p * p
        return res
    if s.is_integer():
        return dr.power(x, s)
    (e,) = opaque(s)
    return dr.exp2(dr.log2(x) * e)


_PACKED: list[Any] = [None]  # the last read-only (normals, lights, views) and their packed drjit input


def frozen_copy(a: np.ndarray) -> np.ndarray:
    """A read-only float64 copy of ``a`` with no base (:func:`_frozen`): callers that pass the same such arrays to
    technique after technique share their drjit conversion and geometry (:func:`_packed_directions`,
    :class:`GeometryDr`)."""
    out = np.array(a, dtype=np.float64, copy=True)
    out.setflags(write=False)
    return out


def _frozen(a: Any) -> bool:
    """A numpy array that nothing can write into: it and every base below it read-only."""
    while isinstance(a, np.ndarray):
        if a.flags.writeable:
            return False
        a = a.base
    return True


def _packed_directions(normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> list[Any]:
    """The nine direction components of :class:`GeometryDr` as drjit arrays of the active dtype, gathered from one
    packed row-major (N, 9) input — :func:`validate.local_models.precision.packed_to_dr` of the nine columns, the
    same kernel (rows side by side formed by one ``np.concatenate`` instead of nine strided column copies).

    Memoised by identity for read-only inputs: the brdfs experiment's environment quadrature calls every technique
    (each building a GeometryDr) on the same three frozen arrays (:func:`_frozen`, held by weak reference so a
    recycled id cannot match), which are then converted once; the gathers stay per call (lazy, traced into each
    technique's kernel as before)."""
    import weakref  # noqa: PLC0415

    from ..precision import active, active_backend, float_type, to_dr, uint_type  # noqa: PLC0415

    dr = _dr()
    arrays = (normals, lights, views)
    key = (active(), active_backend())
    hit = _PACKED[0]
    packed = None
    if hit is not None and hit[0] == key and all(r() is a for r, a in zip(hit[1], arrays, strict=True)):
        packed, n = hit[2], hit[3]
    if packed is None:
        rows = np.concatenate([np.asarray(a, dtype=np.float64).reshape(-1, 3) for a in arrays], axis=1)
        n = len(rows)
        packed = to_dr(rows)
        frozen = all(isinstance(a, np.ndarray) and _frozen(a) for a in arrays)
        _PACKED[0] = (key, tuple(weakref.ref(a) for a in arrays), packed, n) if frozen else None
    idx = dr.arange(uint_type(), n) * 9
    return [dr.gather(float_type(), packed, idx + j) for j in range(9)]


_GEOMETRY_FIELDS = ("cl", "cv", "ch", "vh", "rv", "front", "cos_dphi", "theta_l", "theta_v")
_EVALUATED: list[Any] = [None]  # the last frozen (normals, lights, views) and their evaluated GeometryDr fields


def _evaluated_geometry(normals: np.ndarray, lights: np.ndarray, views: np.ndarray) -> dict[str, Any] | None:
    """The evaluated :class:`GeometryDr` fields of the last read-only (normals, lights, views) (:func:`_frozen`, held
    by weak reference, keyed by the active dtype and backend as :func:`_packed_directions`), or None."""
    from ..precision import active, active_backend  # noqa: PLC0415

    hit = _EVALUATED[0]
    arrays = (normals, lights, views)
    if hit is not None and hit[0] == (active(), active_backend()) and all(
            r() is a for r, a in zip(hit[1], arrays, strict=True)):
        return hit[2]
    return None


class GeometryDr:
    """:class:`Geometry` on drjit arrays of the active dtype: the same per-sample cosines (n·l, n·v, n·h, v·h, r·v),
    horizon mask, cos Δφ and polar angles, from (N, 3) numpy directions converted once
    (:func:`validate.local_models.precision.vec_to_dr`)."""

    def __init__(self, normals: np.ndarray, lights: np.ndarray, views: np.ndarray):
        dr = _dr()
        # one packed input gathered nine ways (precision.packed_to_dr: row-major, offsets free of the size): with
        # nine separate inputs the LLVM kernel's hash follows the order drjit happens to number them in, and a
        # column-major offset k·N is a literal of the size, so identical calls or a new N missed the kernel cache
        size = len(np.asarray(normals).reshape(-1, 3))
        self.size = size
        known = _evaluated_geometry(normals, lights, views)
        if known is not None:
            for name, value in known.items():
                setattr(self, name, value)
            return
        c = _packed_directions(normals, lights, views)
        n, l, v = (_unit((c[3 * i], c[3 * i + 1], c[3 * i + 2])) for i in range(3))
        self.cl, self.cv = _dot(n, l), _dot(n, v)
        h = _unit((l[0] + v[0], l[1] + v[1], l[2] + v[2]))
        self.ch = dr.clip(_dot(n, h), 0.0, 1.0)
        self.vh = dr.clip(_dot(v, h), 0.0, 1.0)
        r = tuple(2.0 * self.cl * n[i] - l[i] for i in range(3))
        self.rv = _dot(r, v)
        self.front = (self.cl > 0.0) & (self.cv > 0.0)
        lt = tuple(l[i] - self.cl * n[i] for i in range(3))
        vt = tuple(v[i] - self.cv * n[i] for i in range(3))
        norm = dr.sqrt(_dot(lt, lt)) * dr.sqrt(_dot(vt, vt))
        self.cos_dphi = dr.select(norm > 1e-12, _dot(lt, vt) / dr.maximum(norm, _tiny()), 0.0)
        self.theta_l, self.theta_v = acos_dr(self.cl), acos_dr(self.cv)
        if all(isinstance(a, np.ndarray) and _frozen(a) for a in (normals, lights, views)):
            import weakref  # noqa: PLC0415

            from ..precision import active, active_backend  # noqa: PLC0415

            fields = {name: getattr(self, name) for name in _GEOMETRY_FIELDS}
            dr.eval(*fields.values())
            _EVALUATED[0] = ((active(), active_backend()), tuple(weakref.ref(a) for a in (normals, lights, views)),
                             fields)

    def finish(self, f_cos: Any) -> np.ndarray:
        """(N, 3) float64 numpy, max(0, ·) and zero where l or v is below the horizon."""
        dr = _dr()
        zero = dr.zeros(type(self.cl), self.size)
        ch = [dr.select(self.front, dr.maximum(zero + c, 0.0), 0.0) for c in RGB.of(f_cos).ch]
        dr.eval(*ch)  # one kernel for the three channels (they share every geometric term)
        # each channel widened (exact) straight into its column: the values of precision.rgb_to_np, without its
        # float64 temporaries and strided stack
        out = np.empty((self.size, 3))
        for i, c in enumerate(ch):
            out[:, i] = np.array(c)
        return out


def fresnel_exact_dr(cos_theta: Any, eta: RGB, k: RGB) -> RGB:
    """:func:`fresnel_exact` in real arithmetic: ñ = η + ik per channel (numbers), w = 1 − (1 − c²)/ñ², c_t = √w (the
    principal root, the stable form: Re = √((|w| + Re w)/2), Im = Im w/(2 Re) for Re w ≥ 0 and the mirror for
    Re w < 0), ñ c_t = p + iq, F = ½[((c − p)² + q²)/((c + p)² + q²) + ((ηc − Re c_t)² + (kc − Im c_t)²)/((ηc +
    Re c_t)² + (kc + Im c_t)²)]."""
    dr = _dr()
    c = dr.clip(cos_theta, 0.0, 1.0)
    s2 = 1.0 - c * c

    def one(e: float, kk: float) -> Any:
        if math.hypot(e, kk) < 1e-12:
            e, kk = 1e-12, 0.0
        a, b = e * e - kk * kk, 2.0 * e * kk  # ñ²
        m2 = a * a + b * b
        # η, k and the two parts of 1/ñ² opaque (formed in float64 as the literals were), each channel its own,
        # so neither a new index nor equal channels change the kernel
        e, kk, am, bm = opaque(e, kk, a / m2, b / m2)
        x, y = 1.0 - s2 * am, s2 * bm  # w = 1 − s²/ñ², 1/ñ² = (a − ib)/|ñ²|²
        r = dr.sqrt(x * x + y * y)
        big = dr.sqrt(0.5 * (r + dr.abs(x)))
        small = y / (2.0 * dr.maximum(big, _tiny()))
        ctr = dr.select(x >= 0.0, big, dr.abs(small))
        cti = dr.select(x >= 0.0, small, dr.copysign(big, y))
        p, q = e * ctr - kk * cti, e * cti + kk * ctr
        rs = (dr.square(c - p) + q * q) / (dr.square(c + p) + q * q)
        rp = ((dr.square(e * c - ctr) + dr.square(kk * c - cti))
              / (dr.square(e * c + ctr) + dr.square(kk * c + cti)))
        return 0.5 * (rs + rp)

    return RGB(*(one(float(e), float(kk)) for e, kk in zip(RGB.of(eta).ch, RGB.of(k).ch, strict=True)))


def fresnel_f0_rgb(eta: np.ndarray, k: np.ndarray) -> RGB:
    """:func:`fresnel_f0` (per-parameter set-up, numbers) as an :class:`RGB`."""
    return RGB.of(fresnel_f0(eta, k))


def fresnel_schlick_dr(cos_theta: Any, f0: RGB) -> RGB:
    """Schlick [8] on drjit arrays: F = F₀ + (1 − F₀)(1 − cos θ)⁵."""
    dr = _dr()
    w = dr.power(1.0 - dr.clip(cos_theta, 0.0, 1.0), 5)
    return opaque_rgb(f0) + opaque_rgb(1.0 - RGB.of(f0)) * w


def beckmann_d_dr(cos_h: Any, m: float, normalised: bool = True) -> Any:
    """:func:`beckmann_d` on drjit arrays."""
    dr = _dr()
    (m2,) = opaque(m * m)
    c2 = dr.maximum(cos_h * cos_h, 1e-12)
    d = dr.exp(-(1.0 - c2) / (c2 * m2)) / (m2 * c2 * c2)
    return dr.select(cos_h > 1e-6, d / np.pi if normalised else d, 0.0)


def ggx_d_dr(cos_h: Any, alpha: float) -> Any:
    """:func:`ggx_d` on drjit arrays."""
    dr = _dr()
    a2, a2m1 = opaque(alpha * alpha, alpha * alpha - 1.0)
    return dr.select(cos_h > 0.0, a2 / (np.pi * dr.square(cos_h * cos_h * a2m1 + 1.0)), 0.0)


def smith_g1_dr(cos_theta: Any, alpha: float, distribution: str) -> Any:
    """:func:`smith_g1` on drjit arrays (Beckmann's Λ with ``drjit.erf``)."""
    dr = _dr()
    c = dr.clip(cos_theta, 1e-12, 1.0)
    tan = dr.sqrt(dr.maximum(1.0 - c * c, 0.0)) / c
    if distribution == "ggx":
        (a2,) = opaque(alpha * alpha)
        return 2.0 / (1.0 + dr.sqrt(1.0 + a2 * tan * tan))
    (al,) = opaque(alpha)
    a = dr.minimum(1.0 / dr.maximum(al * tan, _tiny()), 1e8)
    tail = dr.exp(-dr.minimum(a * a, 700.0)) / (2.0 * a * math.sqrt(np.pi))
    lam = dr.select(a < 30.0, 0.5 * (dr.erf(a) - 1.0) + tail, 0.0)
    return 1.0 / (1.0 + lam)


def vcavity_g_dr(g: GeometryDr) -> Any:
    """:func:`vcavity_g` on drjit arrays."""
    dr = _dr()
    vh = dr.maximum(g.vh, 1e-12)
    return dr.minimum(1.0, dr.minimum(2.0 * g.ch * g.cv / vh, 2.0 * g.ch * g.cl / vh))


def alpha_beta_dr(g: GeometryDr) -> tuple[Any, Any]:
    dr = _dr()
    return dr.maximum(g.theta_l, g.theta_v), dr.minimum(g.theta_l, g.theta_v)


def cook_torrance_printed_dr(params: Mapping[str, Any], g: GeometryDr) -> RGB:
    """:func:`cook_torrance_printed_terms` with its printed defaults (Schlick F(n·l), V-cavity G, (n·l)(n·v), D
    without 1/π) on drjit arrays."""
    dr = _dr()
    who = "cook_torrance_printed"
    m = scalar_param(params, "alpha", who, 1e-4)
    f = fresnel_schlick_dr(g.cl, fresnel_f0_rgb(param(params, "eta", who), param(params, "k", who)))
    d = beckmann_d_dr(g.ch, m, normalised=False)
    denom = dr.maximum(g.cl * g.cv, 1e-12)
    return f * (d * vcavity_g_dr(g) / denom * g.cl / np.pi)


def microfacet_specular_dr(params: Mapping[str, Any], g: GeometryDr, who: str = "cook_torrance",
                           fresnel: RGB | None = None) -> RGB:
    """:func:`microfacet_specular` on drjit arrays: F(v·h) D G₁(l) G₁(v) / (4 (n·l)(n·v)) · (n·l) [9] eq. 20; F
    the exact Fresnel of η + ik unless ``fresnel`` is given."""
    dr = _dr()
    a = scalar_param(params, "alpha", who, 1e-4)
    dist = distribution_param(params, who)
    d = beckmann_d_dr(g.ch, a) if dist == "beckmann" else ggx_d_dr(g.ch, a)
    gg = smith_g1_dr(g.cl, a, dist) * smith_g1_dr(g.cv, a, dist)
    f = fresnel if fresnel is not None else fresnel_exact_dr(g.vh, rgb_param(params, "eta", who),
                                                             rgb_param(params, "k", who))
    return f * (d * gg / (4.0 * dr.maximum(g.cv, 1e-12)))


def oren_nayar_full_dr(sigma: float, albedo: RGB, g: GeometryDr) -> tuple[RGB, RGB]:
    """:func:`oren_nayar_full_terms` on drjit arrays: (direct L₁, inter-reflection L₂), each f_r·(n·l)."""
    dr = _dr()
    s2 = sigma * sigma
    al, be = alpha_beta_dr(g)
    be = dr.minimum(be, below_half_pi())
    cd = g.cos_dphi
    c1, b, b3, b_inter = opaque(1.0 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09), 0.125 * s2 / (s2 + 0.09),
                                0.17 * s2 / (s2 + 0.13))
    c2 = dr.select(cd >= 0.0, b * dr.sin(al), b * (dr.sin(al) - dr.power(2.0 * be / np.pi, 3)))
    c3 = b3 * dr.square(4.0 * al * be / np.pi ** 2)
    direct = c1 + cd * c2 * dr.tan(be) + (1.0 - dr.abs(cd)) * c3 * dr.tan(0.5 * (al + be))
    inter = b_inter * (1.0 - cd * dr.square(2.0 * be / np.pi))
    return (opaque_rgb(RGB.of(albedo) / np.pi) * (direct * g.cl),
            opaque_rgb(RGB.of(albedo) * RGB.of(albedo) / np.pi) * (inter * g.cl))

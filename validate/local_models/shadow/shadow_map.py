"""Shadow mapping for a disc light: unoccluded disc irradiance × visibility from a depth map (drjit).

Shading of a Lambertian point x with normal n and albedo ρ (radiance towards the camera):

    L_o(x) = ρ/π · E_disc(x, n) · V(x)

**Unoccluded irradiance** E_disc (``disc_irradiance``): the disc of radius r, radiance L_e, centre c,
normal n_L, seen from x at distance d in direction l = (c − x)/d. With cos θ = n·l and
sin²σ = r²/(r² + d²) (so that π sin²σ is the projected solid angle of a *facing* disc on its axis),

    E = L_e · I(cos θ, sin²σ) · max(0, n_L·(−l)),
    I = π sin²σ cos θ                                          if cos²θ > sin²σ (all above the horizon)
    I = (cos θ acos y − x sin θ √(1 − y²)) sin²σ + atan(sin θ √(1 − y²) / x)   otherwise (clipped),
        with x = √(1/sin²σ − 1) = d/r, y = −x cos θ / sin θ, and I = 0 below cos θ = −sin σ,

the "illuminanceSphereOrDisk" form of [1] §4.7 (the horizon-clipped spherical cap of [2]; I is
:func:`validate.local_models.arealight.sphere_cap.cap_irradiance_dr` with one sin²σ per point), with the
disc's foreshortening max(0, n_L·(−l)) as the extra factor. It is exact on the disc's axis with n
facing the disc, E = π L_e r²/(r² + d²), and has the right point-light limit E = L_e πr² cos θ cos θ_L
/ d²; elsewhere it is an approximation whose error grows like (r/d)² (measured against
:func:`validate.reference.shadow_render.disc_irradiance_quadrature`, the slow exact integral
E = L_e ∫_disc max(0, n·ω) max(0, −n_L·ω) /
|q − x|² dA_q: ≤ 6.5·10⁻⁵ of the on-axis value for r/d ≤ 0.02, ≤ 6 % for r/d ≤ 0.4).

**Shadow map** (``build_shadow_map``): a perspective view from the disc centre O along n_L, with the
orthonormal frame (right, up, forward = n_L). A point p has view depth z = (p − O)·forward and
tan-plane coordinates s = (p − O)·right / z, t = (p − O)·up / z. The square window [s0, s0 + span] ×
[t0, t0 + span] is fitted to the receivers (the pixels' G-buffer points in front of the light); near
n and far f are fitted to the map's own depth range and the receivers (SDSM-style). Texel (i, j) has
its centre at s = s0 + (i + ½)·span/R, t = t0 + (j + ½)·span/R; its depth is found by casting a ray
with Mitsuba (a stand-in for a depth-only raster pass, which samples depth at texel centres too).
Stored depth is the window depth of a [0, 1] depth range, quantised to 24 bits (a D24 buffer):

    z_w = f (z − n) / (z (f − n)) = A (1 − n/z),  A = f/(f − n).

**Bias** (``PolygonOffset``): glPolygonOffset(factor, units) [3] adds o = factor·DZ + units·r to the
occluder's depth, with r = 2⁻²⁴ the smallest resolvable depth step and DZ = max(|∂z_w/∂x_w|,
|∂z_w/∂y_w|) its depth slope per texel. For the tangent plane of the hit (normal N) the slope is
exact: ∂z_w/∂x_w = −A n (N·right) / (z (N·D)) · span/R with D = forward + s·right + t·up. The offset is
added at lookup, which equals offsetting at raster time up to one depth-buffer step.

**Visibility** (receiver window depth z_r, clamped to [0, 1] as GL clamps the reference value):

* ``hard``: the nearest texel; lit iff z_r ≤ D + o.
* ``pcf``: k×k taps one texel apart centred on the receiver, each a bilinear-weighted 2×2 comparison
  like ``sampler2DShadow`` with GL_LINEAR [3]; the mean of the taps.
* ``pcss`` [4]: (1) blocker search: ``search_taps`` nearest-texel taps on a disc of tan-plane radius
  w_s = r (z_r − n)/(n z_r) (the region through which x sees the light at the near plane); blockers are
  the taps that fail the depth test; their mean view depth is z_b. No blockers → V = 1. (2) penumbra:
  the light disc seen from x through depth z_b covers a tan-plane disc of radius
  w_p = r (z_r − z_b)/(z_b z_r) (similar triangles; exact for a blocker plane parallel to the light).
  (3) ``filter_taps`` bilinear PCF taps on a disc of radius w_p: the fraction of the disc's area lit.
  Tap patterns are Vogel (golden-angle) spirals, uniform in area, fixed for every pixel.

Texels outside the window read as empty (depth 1, like GL_CLAMP_TO_BORDER with a border depth of 1),
so taps that leave the window are lit; the window is fitted to the receivers with a 2 % margin.

Receiver-plane depth (``receiver_plane=True``): each tap compares the depth of the receiver's own
tangent plane at that tap's texel centre instead of z_r (Isidoro [5]), so wide kernels on sloped
receivers do not shadow the receiver with itself. The classic pipeline (hard, PCF) compares z_r.

References
[1] S. Lagarde, C. de Rousiers, "Moving Frostbite to Physically Based Rendering 3.0", SIGGRAPH 2014
    course notes, §4.7 (area lights: sphere and disc, "illuminanceSphereOrDisk").
[2] J. Snyder, "Area light sources for real-time graphics", Microsoft Research MSR-TR-96-11, 1996.
[3] OpenGL Programming Guide ("Red Book"), ch. 7 shadow mapping: glPolygonOffset, sampler2DShadow;
    the OpenGL 4.6 core specification (polygon offset; depth texture comparison with LINEAR filtering).
[4] R. Fernando, "Percentage-Closer Soft Shadows", SIGGRAPH 2005 sketch.
[5] J. Isidoro, "Shadow Mapping: GPU-based Tips and Techniques", GDC 2006 (receiver plane depth bias).
[6] J. de Vries, "Shadow Mapping", LearnOpenGL, Advanced Lighting (learnopengl.com), section "PCF": the
    3×3 texel neighbourhood averaged around the receiver, the kernel most tutorials and engines start from.
[7] T. Annen, T. Mertens, H.-P. Seidel, E. Flerackers, J. Kautz, "Exponential Shadow Maps", Graphics
    Interface 2008 (Fig. 1: 2k × 2k maps, 5×5 Gauss filtering for CSMs, VSMs and ESMs).
[8] W. Donnelly, A. Lauritzen, "Variance Shadow Maps", I3D 2006.
[9] C. Peters, R. Klein, "Moment Shadow Mapping", I3D 2015.

This module is the family's shared code and registers nothing. The techniques (family ``shadow``,
:mod:`validate.local_models.families`; each is the family's contract fn(shadow_map, light, points, normals)
-> (N,) V′ and registers exactly as a plug-in does) are one file each in this folder:
:mod:`.percentage_closer` ``hard`` (nearest texel, glPolygonOffset(2, 4) [3]), ``pcf`` (3×3 bilinear taps
[6] [3], footprint 4×4 texels) and ``pcss`` ([4], 32 blocker-search and 64 filter taps, receiver-plane depth [5]). The
filterable maps (VSM [8], ESM [7], MSM [9]) each register in their own module (``shadow_vsm``,
``shadow_esm``, ``shadow_msm``) on :func:`filter_footprint`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ...backend import init
from ...errors import ValidateError
from ...scenes.shadow_scenes import DiscLight
from ..arealight.sphere_cap import cap_irradiance_dr
from ..precision import float_type, int_type, on_active, to_dr, uint_type

DEPTH_BITS = 24
DEPTH_LSB = 2.0**-DEPTH_BITS  # r of glPolygonOffset for a D24 buffer
MIN_RESOLUTION, MAX_RESOLUTION = 16, 8192
MAX_PCF_KERNEL = 65  # k×k taps; 65² = 4225 taps per pixel is already far beyond any real-time budget
NEAR_MARGIN = 0.99  # near plane = 0.99 × nearest depth in the map
FAR_MARGIN = 1.01  # far plane = 1.01 × farthest of map and receivers
WINDOW_PAD = 0.02  # fraction of the fitted window added on each side
RAY_CHUNK = 1 << 22  # shadow-map rays per Mitsuba call
GOLDEN_ANGLE = np.pi * (3.0 - np.sqrt(5.0))


@dataclass(frozen=True)
class PolygonOffset:
    """glPolygonOffset(factor, units) for a 24-bit depth buffer: o = factor·DZ + units·2⁻²⁴."""

    factor: float = 2.0
    units: float = 4.0

    def scaled(self, k: float) -> PolygonOffset:
        return PolygonOffset(self.factor * k, self.units * k)


@dataclass
class LightView:
    """Perspective view from ``origin`` along ``forward``; square tan-plane window; depth range [near, far]."""

    origin: np.ndarray
    forward: np.ndarray
    right: np.ndarray
    up: np.ndarray
    s0: float
    t0: float
    span: float
    near: float = 0.0
    far: float = 0.0

    def view_coords(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(s, t, z) of points p (N, 3)."""
        rel = np.asarray(p, dtype=np.float64) - self.origin
        z = rel @ self.forward
        with np.errstate(divide="ignore", invalid="ignore"):
            return (rel @ self.right) / z, (rel @ self.up) / z, z

    @property
    def depth_scale(self) -> float:
        """A = f/(f − n)."""
        return self.far / (self.far - self.near)


@dataclass
class ShadowMap:
    """R×R window depths (``depth``, row-major j·R + i, D24-quantised, 1 = empty) and slopes DZ per texel."""

    view: LightView
    resolution: int
    depth: Any  # drjit Float
    slope: Any  # drjit Float
    build_seconds: float = 0.0

    @property
    def texel_tan(self) -> float:
        return self.view.span / self.resolution

    def depth_image(self) -> np.ndarray:
        """The stored window depths as a (R, R) float64 array, row j, column i (1 = empty)."""
        return np.array(self.depth, dtype=np.float64).reshape(self.resolution, self.resolution)

    def view_depth_image(self) -> np.ndarray:
        """Linear view depth z = n / (1 − z_w / A) per texel (R, R); +inf where the texel is empty."""
        zw = self.depth_image()
        with np.errstate(divide="ignore"):
            z = self.view.near / (1.0 - zw / self.view.depth_scale)
        return np.where(zw >= 1.0, np.inf, z)

    def window_coords(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(x, y, z_w, z) of points (N, 3): continuous texel coordinates (texel (i, j) covers [i, i + 1) ×
        [j, j + 1)), the window depth z_w clamped to [0, 1] as GL clamps the reference value, and the
        linear view depth z. Points behind the light get z = far and coordinates far outside the map."""
        v = self.view
        s, t, z = v.view_coords(np.asarray(points, dtype=np.float64).reshape(-1, 3))
        bad = ~(z > 0)
        z = np.where(bad, v.far, z)
        x = np.where(bad, -1e6, (s - v.s0) / v.span * self.resolution)
        y = np.where(bad, -1e6, (t - v.t0) / v.span * self.resolution)
        return x, y, np.clip(v.depth_scale * (1 - v.near / z), 0.0, 1.0), z


def light_frame(light: DiscLight) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(forward, right, up): forward = n_L, (right, up) = ``light.frame()``, the disc's own plane axes."""
    right, up = light.frame()
    return light.normal, right, up


def fit_light_view(light: DiscLight, receivers: np.ndarray) -> LightView:
    """The square tan-plane window around the receivers in front of the light (near/far set later)."""
    f, r, u = light_frame(light)
    view = LightView(np.array(light.centre, dtype=np.float64), f, r, u, 0.0, 0.0, 1.0)
    s, t, z = view.view_coords(np.asarray(receivers).reshape(-1, 3))
    front = z > 1e-3 * np.linalg.norm(np.subtract(light.target, light.centre))
    if not front.any():
        raise ValidateError("shadow map: no receiver lies in front of the light")
    s, t = s[front], t[front]
    span = max(s.max() - s.min(), t.max() - t.min())
    if not np.isfinite(span) or span <= 0:
        raise ValidateError("shadow map: the receivers span no area in the light's view")
    pad = WINDOW_PAD * span
    view.span = float(span + 2 * pad)
    view.s0 = float(0.5 * (s.max() + s.min()) - 0.5 * view.span)
    view.t0 = float(0.5 * (t.max() + t.min()) - 0.5 * view.span)
    view.far = float(z[front].max())
    return view


def quantise_depth(z_w: Any) -> Any:
    """Round window depths (drjit Float) to the nearest of the 2²⁴ levels of a D24 buffer."""
    import drjit as dr

    levels = float(2**DEPTH_BITS - 1)
    return dr.round(dr.clip(z_w, 0.0, 1.0) * levels) / levels


def build_shadow_map(geometry: Any, light: DiscLight, receivers: np.ndarray, resolution: int) -> ShadowMap:
    """Render the depth (and slope) map of ``geometry`` (a Mitsuba scene without the light)."""
    import time

    import drjit as dr
    import mitsuba as mi

    init()
    if not (MIN_RESOLUTION <= resolution <= MAX_RESOLUTION):
        raise ValidateError(f"shadow-map resolution {resolution}: must be in "
                            f"[{MIN_RESOLUTION}, {MAX_RESOLUTION}]")
    t_start = time.perf_counter()
    view = fit_light_view(light, receivers)
    f, r, u = (mi.Vector3f(*map(float, v)) for v in (view.forward, view.right, view.up))
    idx = dr.arange(mi.UInt32, resolution * resolution)
    step = view.span / resolution
    s = view.s0 + (mi.Float(idx % resolution) + 0.5) * step
    t = view.t0 + (mi.Float(idx // resolution) + 0.5) * step
    d = f + s * r + t * u  # forward component 1, so view depth = distance / |d|
    norm = dr.norm(d)
    ray = mi.Ray3f(mi.Point3f(*map(float, view.origin)), d / norm)
    si = geometry.ray_intersect(ray, ray_flags=mi.RayFlags.Minimal, coherent=True)
    hit = si.is_valid()
    z = dr.select(hit, si.t / norm, 1.0)
    n = si.n
    slope_dir = dr.maximum(dr.abs(dr.dot(n, r)), dr.abs(dr.dot(n, u)))
    n_d = dr.dot(n, d)
    dr.eval(hit, z, slope_dir, n_d)
    if not dr.any(hit):
        raise ValidateError("shadow map: no geometry in the light's view")
    z_hit_min = float(dr.min(dr.select(hit, z, dr.inf))[0])
    z_hit_max = float(dr.max(dr.select(hit, z, 0.0))[0])
    view.near = NEAR_MARGIN * z_hit_min
    view.far = FAR_MARGIN * max(view.far, z_hit_max)
    a = view.depth_scale
    z_w = dr.select(hit, quantise_depth(a * (1.0 - view.near / z)), 1.0)
    # DZ = |∂z_w/∂x_w| (max over x, y) = A n max(|N·right|, |N·up|) / (z |N·D|) · span/R
    dz = a * view.near * slope_dir / (z * dr.maximum(dr.abs(n_d), 1e-12)) * step
    dz = dr.select(hit & dr.isfinite(dz), dz, 0.0)
    dr.eval(z_w, dz)
    return ShadowMap(view, resolution, z_w, dz, time.perf_counter() - t_start)


# ---------------------------------------------------------------------------------------------- receivers

@dataclass
class _Receivers:
    """Per-receiver drjit arrays: window coords (x, y), window depth z_w, view depth z, plane terms."""

    x: Any
    y: Any
    z_w: Any
    z: Any
    plane_c: Any  # N·(X − O)
    n_f: Any  # N·forward
    n_r: Any  # N·right
    n_u: Any  # N·up
    count: int


def _receivers(sm: ShadowMap, position: np.ndarray, normal: np.ndarray) -> _Receivers:
    F = float_type()
    v = sm.view
    p = np.asarray(position, dtype=np.float64).reshape(-1, 3)
    nrm = np.asarray(normal, dtype=np.float64).reshape(-1, 3)
    s, t, z = v.view_coords(p)
    bad = ~(z > 0)
    z = np.where(bad, v.far, z)
    s, t = np.where(bad, -1e3, s), np.where(bad, -1e3, t)
    rel = p - v.origin

    def f32(a: np.ndarray) -> Any:
        return F(np.ascontiguousarray(a, dtype=np.float32))

    res = sm.resolution
    return _Receivers(f32((s - v.s0) / v.span * res), f32((t - v.t0) / v.span * res),
                      f32(np.clip(v.depth_scale * (1 - v.near / z), 0.0, 1.0)), f32(z),
                      f32(np.einsum("pk,pk->p", nrm, rel)), f32(nrm @ v.forward), f32(nrm @ v.right),
                      f32(nrm @ v.up), p.shape[0])


def _expand(rc: _Receivers, taps: int) -> _Receivers:
    """Each receiver repeated ``taps`` times (lane = receiver·taps + tap)."""
    import drjit as dr

    return _Receivers(*[dr.repeat(getattr(rc, k), taps) for k in ("x", "y", "z_w", "z", "plane_c", "n_f", "n_r",
                                                                   "n_u")], rc.count * taps)


def _plane_window_depth(sm: ShadowMap, rc: _Receivers, xw: Any, yw: Any) -> Any:
    """Window depth of the receiver's tangent plane at window position (xw, yw), clamped to [0, 1]."""
    import drjit as dr

    v = sm.view
    s = v.s0 + xw * (v.span / sm.resolution)
    t = v.t0 + yw * (v.span / sm.resolution)
    denom = rc.n_f + s * rc.n_r + t * rc.n_u
    z = rc.plane_c / denom
    ok = (z > 0) & dr.isfinite(z)
    z = dr.select(ok, z, rc.z)
    return dr.clip(v.depth_scale * (1 - v.near / z), 0.0, 1.0)


def _fetch(sm: ShadowMap, i: Any, j: Any, offset: PolygonOffset) -> tuple[Any, Any, Any]:
    """(inside, D, D + o) of texel (i, j): the stored window depth D and the occluder depth offset by
    o = factor·DZ + units·2⁻²⁴ (``PolygonOffset``); outside the map D = 0 and ``inside`` is False."""
    import drjit as dr

    F = float_type()
    res = sm.resolution
    inside = (i >= 0) & (i < res) & (j >= 0) & (j < res)
    U = uint_type()
    idx = U(dr.clip(j, 0, res - 1)) * res + U(dr.clip(i, 0, res - 1))
    d = dr.gather(F, on_active(sm.depth), idx, inside)
    dz = dr.gather(F, on_active(sm.slope), idx, inside)
    return inside, d, d + offset.factor * dz + offset.units * DEPTH_LSB


def _test(sm: ShadowMap, i: Any, j: Any, ref_w: Any, offset: PolygonOffset) -> Any:
    """1.0 where texel (i, j) passes the depth test (lit), outside the map → lit."""
    import drjit as dr

    F = float_type()
    inside, _, occluder = _fetch(sm, i, j, offset)
    lit = ref_w <= occluder
    return dr.select(inside & ~lit, F(0.0), F(1.0))


def _bilinear_pcf(sm: ShadowMap, rc: _Receivers, xw: Any, yw: Any, offset: PolygonOffset,
                  receiver_plane: bool) -> Any:
    """sampler2DShadow with GL_LINEAR at window position (xw, yw): bilinear weights of 4 comparisons."""
    import drjit as dr

    x, y = xw - 0.5, yw - 0.5
    i0, j0 = dr.floor(x), dr.floor(y)
    fx, fy = x - i0, y - j0
    out = 0.0
    for di, dj, w in ((0, 0, (1 - fx) * (1 - fy)), (1, 0, fx * (1 - fy)), (0, 1, (1 - fx) * fy), (1, 1, fx * fy)):
        ii, jj = i0 + di, j0 + dj
        ref = _plane_window_depth(sm, rc, ii + 0.5, jj + 0.5) if receiver_plane else rc.z_w
        out = out + w * _test(sm, _int(ii), _int(jj), ref, offset)
    return out


def _int(a: Any) -> Any:
    """Float texel coordinates (already floored) → Int32 of the active backend."""
    return int_type()(a)


def _to_numpy(a: Any) -> np.ndarray:
    return np.array(a, dtype=np.float64)


def visibility_hard(sm: ShadowMap, position: np.ndarray, normal: np.ndarray,
                    offset: PolygonOffset = PolygonOffset()) -> np.ndarray:
    """V ∈ {0, 1}: nearest-texel depth comparison."""
    import drjit as dr

    rc = _receivers(sm, position, normal)
    return _to_numpy(_test(sm, _int(dr.floor(rc.x)), _int(dr.floor(rc.y)), rc.z_w, offset))


def pcf_offsets(kernel: int) -> np.ndarray:
    """(k², 2) tap offsets in texels: a k×k grid one texel apart, centred on 0."""
    if not (1 <= kernel <= MAX_PCF_KERNEL):
        raise ValidateError(f"PCF kernel {kernel}: must be an integer in [1, {MAX_PCF_KERNEL}]")
    g = np.arange(kernel) - (kernel - 1) / 2.0
    gx, gy = np.meshgrid(g, g, indexing="ij")
    return np.stack([gx.ravel(), gy.ravel()], axis=1)


def vogel_disc(n: int) -> np.ndarray:
    """(n, 2) points of a golden-angle spiral in the unit disc: radius √((k + ½)/n), angle k·(3 − √5)π."""
    if n < 1:
        raise ValidateError(f"tap count {n}: must be ≥ 1")
    k = np.arange(n)
    r = np.sqrt((k + 0.5) / n)
    return np.stack([r * np.cos(k * GOLDEN_ANGLE), r * np.sin(k * GOLDEN_ANGLE)], axis=1)


def _tap_arrays(offsets: np.ndarray, count: int) -> tuple[Any, Any]:
    """Offsets tiled over ``count`` receivers (lane = receiver·taps + tap)."""
    import drjit as dr

    F = float_type()
    return (dr.tile(F(offsets[:, 0].astype(np.float32)), count),
            dr.tile(F(offsets[:, 1].astype(np.float32)), count))


def visibility_pcf(sm: ShadowMap, position: np.ndarray, normal: np.ndarray, kernel: int = 3,
                   offset: PolygonOffset = PolygonOffset(), receiver_plane: bool = False) -> np.ndarray:
    """V = mean over a k×k grid of bilinear PCF taps one texel apart (footprint (k+1)² texels)."""
    import drjit as dr

    offs = pcf_offsets(kernel)
    rc = _expand(_receivers(sm, position, normal), offs.shape[0])
    ox, oy = _tap_arrays(offs, rc.count // offs.shape[0])
    lit = _bilinear_pcf(sm, rc, rc.x + ox, rc.y + oy, offset, receiver_plane)
    return _to_numpy(dr.block_sum(lit, offs.shape[0]) / offs.shape[0])


@dataclass
class PCSSResult:
    visibility: np.ndarray
    blocker_depth: np.ndarray  # mean blocker view depth (NaN: no blocker found)
    penumbra_texels: np.ndarray  # filter radius in texels (0 where no blocker)


def visibility_pcss(sm: ShadowMap, position: np.ndarray, normal: np.ndarray, light_radius: float,
                    offset: PolygonOffset = PolygonOffset(), search_taps: int = 32, filter_taps: int = 64,
                    receiver_plane: bool = True) -> PCSSResult:
    """PCSS [4]: blocker search → penumbra width from the light size → variable-radius PCF (see module doc)."""
    import drjit as dr

    if not (np.isfinite(light_radius) and light_radius > 0):
        raise ValidateError(f"PCSS light radius {light_radius}: must be a finite number > 0")
    F = float_type()
    v = sm.view
    base = _receivers(sm, position, normal)
    n = base.count
    texel = sm.texel_tan
    # (1) blocker search on a disc of radius w_s (tan units) = r (z_r − n) / (n z_r)
    search = vogel_disc(search_taps)
    rc = _expand(base, search_taps)
    ox, oy = _tap_arrays(search, n)
    w_s = light_radius * (rc.z - v.near) / (v.near * rc.z) / texel
    xw, yw = rc.x + ox * w_s, rc.y + oy * w_s
    i, j = dr.floor(xw), dr.floor(yw)
    ref = _plane_window_depth(sm, rc, i + 0.5, j + 0.5) if receiver_plane else rc.z_w
    inside, d, occluder = _fetch(sm, i, j, offset)
    blocker = inside & (occluder < ref)
    z_lin = v.near / (1 - d / v.depth_scale)
    count = dr.block_sum(dr.select(blocker, F(1.0), F(0.0)), search_taps)
    z_b = dr.block_sum(dr.select(blocker, z_lin, F(0.0)), search_taps) / dr.maximum(count, 1.0)
    # (2) penumbra radius w_p = r (z_r − z_b) / (z_b z_r), in texels
    w_p = dr.select(count > 0, light_radius * dr.maximum(base.z - z_b, 0.0) / (z_b * base.z) / texel, 0.0)
    # (3) PCF on a disc of radius w_p
    filt = vogel_disc(filter_taps)
    rc = _expand(base, filter_taps)
    ox, oy = _tap_arrays(filt, n)
    w = dr.repeat(w_p, filter_taps)
    lit = _bilinear_pcf(sm, rc, rc.x + ox * w, rc.y + oy * w, offset, receiver_plane)
    vis = dr.select(count > 0, dr.block_sum(lit, filter_taps) / filter_taps, 1.0)
    zb = _to_numpy(z_b)
    return PCSSResult(_to_numpy(vis), np.where(_to_numpy(count) > 0, zb, np.nan), _to_numpy(w_p))


# ---------------------------------------------------------------------------------------------- shading

def disc_irradiance(light: DiscLight, position: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Unoccluded irradiance E (N,) of the disc at points with normals (N, 3): the [1] form (module doc),
    I(cos θ, sin²σ) from :func:`~validate.local_models.arealight.sphere_cap.cap_irradiance_dr`."""
    F = float_type()
    p = np.asarray(position, dtype=np.float64).reshape(-1, 3)
    nrm = np.asarray(normal, dtype=np.float64).reshape(-1, 3)
    lv = np.asarray(light.centre)[None, :] - p
    d2 = np.einsum("pk,pk->p", lv, lv)
    lv = lv / np.sqrt(d2)[:, None]
    cos_t = F(np.clip(np.einsum("pk,pk->p", nrm, lv), -1, 1).astype(np.float32))
    cos_l = F(np.clip(-(lv @ light.normal), 0, 1).astype(np.float32))
    r2 = light.radius**2
    sin2s = F((r2 / (r2 + d2)).astype(np.float32))
    return _to_numpy(light.radiance * cap_irradiance_dr(cos_t, sin2s) * cos_l)


def shade(albedo: np.ndarray, irradiance: np.ndarray, visibility: np.ndarray) -> np.ndarray:
    """L_o = ρ/π · E · V (Lambertian), (N, 3)."""
    return np.asarray(albedo) / np.pi * (np.asarray(irradiance) * np.asarray(visibility))[:, None]


# ---------------------------------------------------------------------------------------------- filterable maps

GAUSS5 = np.array([1.0, 4.0, 6.0, 4.0, 1.0]) / 16.0  # 5-tap binomial Gauss (the 5×5 Gauss filtering of [7] Fig. 1)


@dataclass
class FilterFootprint:
    """What a prefiltered (moment) shadow map returns at each receiver, computed exactly at lookup.

    A filterable map [7] [8] [9] stores a function of depth, blurs it with the 5×5 Gauss G = g gᵀ
    (``GAUSS5``) and is read with bilinear filtering. Both are linear, so the value read at a receiver is
    Σ_k w_k f(d_k) over the 6×6 texels around it, with separable weights w = (bilinear ∗ g) in x and y
    (Σ w = 1). ``depth`` holds those texels' normalised linear depths d = (z − n)/(f − n) ∈ [0, 1]
    (empty texels and texels outside the map: d = 1, the far plane — lit, like GL_CLAMP_TO_BORDER),
    ``weight`` the w_k, ``receiver`` the receiver's own t = (z_r − n)/(f − n), clamped to [0, 1].
    """

    depth: np.ndarray  # (N, 36)
    weight: np.ndarray  # (N, 36)
    receiver: np.ndarray  # (N,)

    def moments(self, order: int) -> np.ndarray:
        """(N, order) filtered moments b_k = Σ w d^k, k = 1 … order."""
        return np.stack([(self.weight * self.depth**k).sum(axis=1) for k in range(1, order + 1)], axis=1)

    def depth_test(self) -> np.ndarray:
        """The filtered depth test Σ w 1[t ≤ d] = P(D ≥ t): what the moment bounds bound from above."""
        return (self.weight * (self.receiver[:, None] <= self.depth)).sum(axis=1)


def filter_footprint(sm: ShadowMap, points: np.ndarray) -> FilterFootprint:
    """The 6×6 texels and weights a bilinear lookup of the 5×5-Gauss-prefiltered map reads (see the class)."""
    res = sm.resolution
    x, y, _, z = sm.window_coords(points)
    v = sm.view
    i0, j0 = np.floor(x - 0.5), np.floor(y - 0.5)

    def weights(f: np.ndarray) -> np.ndarray:  # (N, 6): (1 − f)·[g, 0] + f·[0, g]
        w = np.zeros((f.size, 6))
        w[:, :5] += (1 - f)[:, None] * GAUSS5
        w[:, 1:] += f[:, None] * GAUSS5
        return w

    wx, wy = weights(x - 0.5 - i0), weights(y - 0.5 - j0)
    ii = np.clip(i0, -8, res + 8).astype(np.int64)[:, None] - 2 + np.arange(6)  # (N, 6)
    jj = np.clip(j0, -8, res + 8).astype(np.int64)[:, None] - 2 + np.arange(6)
    inside = ((ii >= 0) & (ii < res))[:, None, :] & ((jj >= 0) & (jj < res))[:, :, None]  # (N, 6 j, 6 i)
    idx = np.clip(jj, 0, res - 1)[:, :, None] * res + np.clip(ii, 0, res - 1)[:, None, :]
    zw = np.asarray(dr_gather_numpy(sm.depth, idx.ravel()), dtype=np.float64).reshape(idx.shape)
    zw = np.where(inside, zw, 1.0)
    with np.errstate(divide="ignore"):
        zlin = np.where(zw >= 1.0, v.far, v.near / (1.0 - zw / v.depth_scale))
    d = np.clip((zlin - v.near) / (v.far - v.near), 0.0, 1.0)
    w = wy[:, :, None] * wx[:, None, :]
    t = np.clip((z - v.near) / (v.far - v.near), 0.0, 1.0)
    return FilterFootprint(d.reshape(-1, 36), w.reshape(-1, 36), t)


@dataclass
class FootprintDr:
    """A :class:`FilterFootprint` as flat drjit arrays of the active dtype (:mod:`..precision`): ``depth`` and
    ``weight`` hold the 36 taps of each receiver side by side (N·36), ``receiver`` one t per receiver (N) and
    ``receiver_per_tap`` the same repeated over its taps."""

    depth: Any
    weight: Any
    receiver: Any
    receiver_per_tap: Any
    n: int

    def filtered(self, f: Any) -> Any:
        """Σ_k w_k f(d_k) per receiver, for a per-tap drjit array ``f`` (what the filtered map returns)."""
        import drjit as dr

        return dr.block_sum(self.weight * f, TAPS)

    def moments(self, order: int) -> list[Any]:
        """[b_1 … b_order], b_k = Σ w d^k per receiver (the filtered moment map)."""
        out, power = [], self.depth
        for _ in range(order):
            out.append(self.filtered(power))
            power = power * self.depth
        return out


TAPS = 36  # 6×6 texels of a bilinear lookup of the 5×5-Gauss-prefiltered map


def footprint_dr(fp: FilterFootprint) -> FootprintDr:
    """``fp`` converted to drjit arrays of the active dtype (:class:`FootprintDr`)."""
    import drjit as dr

    t = to_dr(fp.receiver)
    return FootprintDr(to_dr(fp.depth), to_dr(fp.weight), t, dr.repeat(t, TAPS), len(fp.receiver))


def dr_gather_numpy(values: Any, index: np.ndarray) -> np.ndarray:
    """values[index] for a drjit Float ``values`` and a numpy index array (one gather, no full copy)."""
    import drjit as dr

    U = uint_type()
    return np.array(dr.gather(float_type(), on_active(values), U(np.ascontiguousarray(index, dtype=np.uint32))))

"""Independent check of the reference quadrature: a path-traced white Lambertian sphere.

The reference irradiance E(n) (:mod:`validate.reference.irradiance`) is a quadrature of Mitsuba's
radiance. Here Mitsuba computes the same quantity by a different road — light transport:

* Scene: the unit sphere with Mitsuba's ``diffuse`` BSDF, reflectance 1 (f = 1/π), lit only by the
  environment (``envmap``), seen by an ``orthographic`` sensor whose film spans [−1, 1]² in camera
  space, so the sphere exactly fills the image. ``path`` integrator, ``max_depth = 2`` (camera ray,
  then one bounce: direct lighting, MIS between envmap and BSDF sampling), ``hide_emitters``; a
  ``box`` reconstruction filter, so a pixel is the plain mean of samples uniform over its footprint.
* A sphere is convex, so nothing is occluded and no light inter-reflects; the rendering equation
  collapses to L_o(x) = ∫ L(ω) (1/π) max(0, n(x)·ω) dω = E(n(x)) / π  (Lambert's law with ρ = 1).
* Pixel value: ⟨L_o⟩_pixel = (1/A) ∫_pixel E(n(x, y)) / π dx dy. The quadrature side evaluates it
  with a k×k Gauss–Legendre product rule over the pixel footprint (k = :data:`FOOTPRINT_NODES`),
  calling :func:`~validate.reference.irradiance.reference_irradiance` on the concatenated sub-pixel
  normals. Only pixels whose footprint lies entirely inside the silhouette are compared.

Image ↔ world mapping (measured with an ``aov`` ``sh_normal`` render; ``tests/reference/test_pathtrace.py``):
the sensor's ``to_world = look_at(origin, target, up)`` has columns (left, up', forward, origin);
film column u ∈ [0, 1] maps to camera x = 1 − 2u (column 0 is the camera's *left*, +x local), film
row v to camera y = 1 − 2v (row 0 is the top). The visible sphere point of camera (x, y) has normal
n = x·left + y·up' − √(1 − x² − y²)·forward.

Statistics (per pixel p and channel c). P independent passes with seeds ``seed·MAX_PASSES + i``
give the per-pass means; m = their mean, s_m = sample standard deviation / √P (P − 1 degrees of
freedom). With q the quadrature value and u_q its uncertainty (mean of the sub-pixel
``ReferenceIrradiance.uncertainty`` / π — conservative, the errors of neighbouring normals are
correlated; ≈ 10⁻⁵ relative),

    t = (m − q) / √(s_m² + u_q²)  ~  Student t with P − 1 dof under H₀ (per-pass means ≈ normal, CLT),

converted to a standard-normal quantile z = sign(t) Φ⁻¹(1 − F_t(|t|; P − 1)) so every value has the
same unit-variance null distribution. Pixels are independent (independent samples per pixel); the
three channels of a pixel share their paths and are correlated. ``passed`` is the conjunction of

1. *No outlier*: no |z| exceeds the Šidák-corrected two-sided critical value
   z* = Φ⁻¹(1 − α₁/2), α₁ = 1 − (1 − α)^{1/M} over the M = 3N tested values (family-wise level α,
   default 0.01; Šidák's inequality holds for correlated two-sided normal tests [2]).
2. *No bias*: for every channel, |mean_p z̃| / sd_p(z̃) ≤ 4/√N (N pixels): a 4σ bound, per-channel
   false-alarm rate 6·10⁻⁵. z̃ is the cross-fitted z of :func:`validate.stats.cross_fitted_z`: the
   difference of one half of the passes over the standard error of the other half, whose mean is 0
   under H₀ even for skewed passes (the mean of the t above is not: E[t] ≈ −γ/(2√P) for pass
   skewness γ). A 3 % bias moves every z̃ by ≈ 0.03·q/σ (≳ 1 at the default settings) and the
   mean by the same, far beyond 4/√N ≈ 0.1.

χ²/dof = Σ z² / 3N and its upper-tail p-value (per channel χ²_N, the smallest of the three
Šidák-combined) are reported, not part of ``passed``: they test the calibration of s_m.

References:
  [1] M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering*, 4th ed., §4.3 (Lambertian
      reflection: L_o = ρ E / π) and §2 (Monte Carlo estimators, variance).
  [2] Z. Šidák, "Rectangular confidence regions for the means of multivariate normal
      distributions", JASA 62 (1967) 626–633.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..backend import init
from ..errors import ValidateError
from ..scenes.environment import Environment
from ..scenes.procedural import direction_from_elevation
from ..stats import (
    cross_fitted_z,
    mean_and_stderr,
    mean_z_bound,
    sidak_critical,
    sidak_p_value,
    standardized_mean,
    t_to_z,
)
from .cache import cached
from .irradiance import reference_irradiance

VIEW_ELEVATION_DEG = 15.0  # camera direction seen from the sphere: a little above the horizon …
VIEW_AZIMUTH_DEG = 0.0  # … towards −z (φ = 0), where disc_on_sky's disc (azimuth 30°) lights the sphere
CAMERA_DISTANCE = 5.0  # any distance > 1 works for an orthographic sensor
# Gauss–Legendre nodes per pixel axis on the quadrature side. Measured at 48 px (disc_on_sky, the worst
# of the built-ins): |GL3 − GL8| ≤ 1.4e-4 relative, ≤ 0.05 σ_MC of a 256 spp × 8 pass render; mean 3e-7.
FOOTPRINT_NODES = 3
MAX_PASSES = 1024  # seeds of pass i are seed·MAX_PASSES + i, so different seeds never share a pass
MIN_PASSES = 4  # the t distribution needs P − 1 > 2 for a finite variance
BIAS_SIGMAS = 4.0  # bias check: |mean z̃| / sd(z̃) ≤ BIAS_SIGMAS / √N per channel (z̃ cross-fitted)
INTEGRATOR = {"type": "path", "max_depth": 2, "hide_emitters": True}
SAMPLER = "independent"


# A relative difference |render − quadrature| / quadrature is reported only where the quadrature is at least
# this fraction of its mean over the tested pixels: below it the ratio measures a near-zero denominator, not
# the reference (near_directional's unlit side gave "max rel. diff 3.99e+21 %"); the masked share is reported.
REL_FLOOR = 1.0e-3

@dataclass
class SphereRender:
    """Per-pixel mean and standard error of P independent passes of the white Lambertian sphere.

    ``mean``, ``stderr``: (H, W, 3) outgoing radiance and its standard error of the mean (from the
    spread of the passes, P − 1 dof). ``normals``: (H, W, 3) sphere normal at each pixel centre, NaN
    where the centre misses the sphere. ``mask``: pixels whose whole footprint is on the sphere.
    """

    mean: np.ndarray
    stderr: np.ndarray
    normals: np.ndarray
    mask: np.ndarray
    spp_per_pass: int
    passes: int
    seed: int
    integrator: dict[str, Any]
    view: tuple[float, float] = (VIEW_ELEVATION_DEG, VIEW_AZIMUTH_DEG)
    images: np.ndarray | None = None  # (P, H, W, 3) the passes themselves (the bias test's cross-fitted z)

    @property
    def resolution(self) -> int:
        return int(self.mean.shape[0])


@dataclass
class CrossCheck:
    """Render vs quadrature over the valid pixels; see the module docstring for the test."""

    z: np.ndarray  # (N, 3) normal-quantile z of every valid pixel and channel
    n_pixels: int
    mean_z: float
    mean_z_channels: np.ndarray  # (3,) the bias test's statistic: standardized mean of the cross-fitted z
    bias_limit: float  # BIAS_SIGMAS / √N
    chi2_per_dof: float
    p_value: float
    critical_z: float  # Šidák-corrected two-sided critical value
    fraction_beyond: float
    max_abs_z: float
    max_rel_diff: float
    passed: bool
    alpha: float
    render: np.ndarray  # (H, W, 3) path-traced mean
    quadrature: np.ndarray  # (H, W, 3) E/π averaged over the footprint, NaN outside the mask
    z_image: np.ndarray  # (H, W, 3), NaN outside the mask
    settings: dict[str, Any] = field(default_factory=dict)
    rel_masked_fraction: float = 0.0  # share of tested pixel-channels left out of max_rel_diff (REL_FLOOR)

    def summary(self) -> str:
        bias = float(np.abs(self.mean_z_channels).max())
        return (f"N={self.n_pixels} px, mean z={self.mean_z:+.3f}, bias |mean z̃|/sd={bias:.3f} "
                f"(limit {self.bias_limit:.3f}), "
                f"χ²/dof={self.chi2_per_dof:.3f} (p={self.p_value:.3g}), max|z|={self.max_abs_z:.2f} "
                f"(z*={self.critical_z:.2f}), max rel diff={self.max_rel_diff:.2%}, "
                f"{'passed' if self.passed else 'FAILED'}")


def camera_to_world(view: tuple[float, float]) -> Any:
    """The sensor's ``to_world``: look at the origin from ``CAMERA_DISTANCE`` along (elevation, azimuth)."""
    import mitsuba as mi

    v = direction_from_elevation(*view)
    up = [0.0, 1.0, 0.0] if abs(v[1]) < 0.99 else [0.0, 0.0, -1.0]
    return mi.ScalarTransform4f().look_at(origin=(CAMERA_DISTANCE * v).tolist(), target=[0.0, 0.0, 0.0],
                                          up=up)


def camera_frame(view: tuple[float, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(left, up', forward) world vectors: the first three columns of Mitsuba's ``to_world``."""
    m = np.array(camera_to_world(view).matrix, dtype=np.float64).reshape(4, 4)
    return m[:3, 0], m[:3, 1], m[:3, 2]


def film_to_normals(u: np.ndarray, v: np.ndarray, view: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """Sphere normals (..., 3) at film coordinates (u, v) ∈ [0, 1]², and whether the point is on it.

    Camera x = 1 − 2u, y = 1 − 2v; n = x·left + y·up' − √(1 − x² − y²)·forward (module docstring).
    """
    left, up, fwd = camera_frame(view)
    x, y = 1.0 - 2.0 * np.asarray(u, np.float64), 1.0 - 2.0 * np.asarray(v, np.float64)
    r2 = x * x + y * y
    inside = r2 <= 1.0
    h = np.sqrt(np.clip(1.0 - r2, 0.0, 1.0))
    n = x[..., None] * left + y[..., None] * up - h[..., None] * fwd
    return n, inside


def footprint_mask(resolution: int) -> np.ndarray:
    """(R, R) pixels whose whole footprint lies inside the unit disc (farthest corner r ≤ 1)."""
    edges = 1.0 - 2.0 * np.arange(resolution + 1) / resolution
    far = np.maximum(np.abs(edges[:-1]), np.abs(edges[1:]))  # farthest |coordinate| per row/column
    return far[:, None] ** 2 + far[None, :] ** 2 <= 1.0


def footprint_nodes(k: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes in [0, 1] and weights summing to 1 (exact for degree ≤ 2k − 1)."""
    g, w = np.polynomial.legendre.leggauss(k)
    return 0.5 * (g + 1.0), 0.5 * w


def sphere_scene(env: Environment, resolution: int, spp: int, view: tuple[float, float]) -> Any:
    import mitsuba as mi

    return mi.load_dict({
        "type": "scene",
        "integrator": dict(INTEGRATOR),
        "sensor": {
            "type": "orthographic",
            "to_world": camera_to_world(view),
            "film": {"type": "hdrfilm", "width": resolution, "height": resolution,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": SAMPLER, "sample_count": spp},
        },
        "sphere": {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0,
                   "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}}},
        "environment": env.mitsuba_emitter(),
    })


def integrator_settings(view: tuple[float, float]) -> dict[str, Any]:
    return dict(INTEGRATOR, sampler=SAMPLER, rfilter="box", sensor="orthographic", bsdf="diffuse, reflectance 1",
                view_elevation_deg=view[0], view_azimuth_deg=view[1])


def render_lambertian_sphere(env: Environment, resolution: int = 48, spp: int = 256, passes: int = 8,
                             seed: int = 0, view: tuple[float, float] | None = None) -> SphereRender:
    """Render the white Lambertian sphere in ``passes`` independent passes of ``spp`` samples per pixel.

    Pass i uses the seed ``seed·MAX_PASSES + i``; Mitsuba's box-filter film reduces each pixel's
    samples in a fixed order, so a fixed seed gives bit-identical images. Cached on the
    environment digest and every setting.
    """

    view = (VIEW_ELEVATION_DEG, VIEW_AZIMUTH_DEG) if view is None else (float(view[0]), float(view[1]))
    if resolution < 4:
        raise ValidateError(f"resolution={resolution}: need at least 4 pixels across the sphere")
    if spp < 1:
        raise ValidateError(f"spp={spp}: need at least 1 sample per pixel")
    if not MIN_PASSES <= passes <= MAX_PASSES:
        raise ValidateError(f"passes={passes}: need {MIN_PASSES}..{MAX_PASSES} independent passes")
    if not 0 <= seed < (1 << 32) // MAX_PASSES:
        raise ValidateError(f"seed={seed}: must be in [0, {(1 << 32) // MAX_PASSES})")
    settings = integrator_settings(view)

    def compute() -> dict[str, np.ndarray]:
        import mitsuba as mi

        init()
        scene = sphere_scene(env, resolution, spp, view)
        images = [np.array(mi.render(scene, seed=seed * MAX_PASSES + i, spp=spp), dtype=np.float64)
                  for i in range(passes)]
        return {"passes": np.stack(images)}

    parts = {"env": env.digest, "resolution": resolution, "spp": spp, "passes": passes, "seed": seed,
             "settings": settings}
    images = cached("sphere_render", parts, compute)["passes"]
    if not np.all(np.isfinite(images)) or images.min() < 0:
        raise ValidateError(f"{env.name}: sphere render has NaN/Inf or negative pixels")
    mean, stderr = mean_and_stderr(images, axis=0)
    c = (np.arange(resolution) + 0.5) / resolution
    normals, inside = film_to_normals(c[None, :], c[:, None], view)
    normals[~inside] = np.nan
    return SphereRender(mean, stderr, normals, footprint_mask(resolution), spp, passes, seed, settings, view, images)


def quadrature_sphere(env: Environment, render: SphereRender,
                      k: int = FOOTPRINT_NODES) -> tuple[np.ndarray, np.ndarray]:
    """Footprint-averaged E/π (H, W, 3) on the masked pixels (NaN elsewhere) and its uncertainty.

    ⟨E/π⟩_pixel ≈ Σ_ab w_a w_b E(n(u_a, v_b)) / π with k×k Gauss–Legendre nodes in the pixel.
    """
    r = render.resolution
    x, w = footprint_nodes(k)
    rows, cols = np.nonzero(render.mask)
    u = (cols[:, None, None] + x[None, None, :]) / r  # (N, k_v, k_u)
    v = (rows[:, None, None] + x[None, :, None]) / r
    u, v = np.broadcast_arrays(u, v)
    normals, _ = film_to_normals(u, v, render.view)
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    ref = reference_irradiance(env, normals.reshape(-1, 3))
    weights = (w[:, None] * w[None, :]).reshape(1, k * k, 1)
    e = (ref.irradiance.reshape(-1, k * k, 3) * weights).sum(axis=1)
    de = (ref.uncertainty.reshape(-1, k * k, 3) * weights).sum(axis=1)
    radiance = np.full(render.mean.shape, np.nan)
    uncertainty = np.full(render.mean.shape, np.nan)
    radiance[rows, cols] = e / np.pi
    uncertainty[rows, cols] = de / np.pi
    return radiance, uncertainty


def compare(render: SphereRender, expected: np.ndarray, uncertainty: np.ndarray,
            alpha: float = 0.01) -> CrossCheck:
    """Test the render against expected pixel radiance (H, W, 3) ± uncertainty (module docstring)."""
    from scipy import stats

    if not 0.0 < alpha < 1.0:
        raise ValidateError(f"alpha={alpha}: must be in (0, 1)")
    mask = render.mask
    n = int(mask.sum())
    if n == 0:
        raise ValidateError(f"resolution={render.resolution}: no pixel lies entirely inside the sphere")
    m, se = render.mean[mask], render.stderr[mask]
    q, uq = expected[mask], uncertainty[mask]
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(uq))):
        raise ValidateError("expected radiance has NaN/Inf on a tested pixel")
    sigma = np.sqrt(se**2 + uq**2)
    diff = m - q
    t = np.divide(diff, sigma, out=np.where(diff == 0, 0.0, np.copysign(np.inf, diff)), where=sigma > 0)
    z = t_to_z(t, render.passes - 1)
    tests = z.size
    z_crit = sidak_critical(tests, alpha)
    if render.images is None:
        raise ValidateError("compare: the render carries no passes (SphereRender.images) for the bias test")
    channel_means = standardized_mean(cross_fitted_z(render.images[:, mask], q[None], uq))
    bias_limit = mean_z_bound(n, BIAS_SIGMAS)
    chi2_c = (z**2).sum(axis=0)
    p_min = float(stats.chi2.sf(chi2_c, n).min())
    p_value = sidak_p_value(p_min, 3)  # Šidák over the three channel χ² tests
    beyond = np.abs(z) > z_crit
    keep = np.abs(q) >= REL_FLOOR * np.abs(q).mean()
    rel = np.abs(diff[keep]) / np.abs(q[keep]) if keep.any() else np.zeros(1)
    z_image = np.full(render.mean.shape, np.nan)
    z_image[mask] = z
    return CrossCheck(
        z=z, n_pixels=n, mean_z=float(z.mean()), mean_z_channels=channel_means, bias_limit=float(bias_limit),
        chi2_per_dof=float(chi2_c.sum() / tests), p_value=float(p_value), critical_z=z_crit,
        fraction_beyond=float(beyond.mean()), max_abs_z=float(np.abs(z).max()), max_rel_diff=float(rel.max()),
        rel_masked_fraction=float(1.0 - keep.mean()),
        passed=bool(not beyond.any() and np.all(np.abs(channel_means) <= bias_limit)), alpha=alpha,
        render=render.mean, quadrature=expected, z_image=z_image,
        settings=dict(render.integrator, resolution=render.resolution, spp_per_pass=render.spp_per_pass,
                      passes=render.passes, seed=render.seed, footprint_nodes=FOOTPRINT_NODES),
    )


def crosscheck_sphere(env: Environment, resolution: int = 48, spp: int = 256, passes: int = 8, seed: int = 0,
                      alpha: float = 0.01) -> CrossCheck:
    """Path-traced white sphere vs the reference quadrature E/π, pixel by pixel (module docstring)."""
    render = render_lambertian_sphere(env, resolution, spp, passes, seed)
    expected, uncertainty = quadrature_sphere(env, render)
    return compare(render, expected, uncertainty, alpha)

"""A plug-in with one technique in every technique family, as a user would write it (one file).

Used by tests/local_models/test_plugins.py: ``python -m validate all --quick --plugin tests/plugins/every_family.py``
must give each technique a row, ``results.json`` entries and its declared-threshold claims.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from validate.local_models import FAMILIES, arealight, family, irradiance, shadow, specular


def _sh2_irradiance(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Order-2 SH irradiance in plain numpy (lat-long texel quadrature, Mitsuba's envmap convention)."""
    h, w, _ = radiance.shape
    theta = np.arange(h) * np.pi / (h - 1)
    phi = 2 * np.pi * (np.arange(w) + 0.5) / w
    st, ct = np.sin(theta)[:, None], np.cos(theta)[:, None]
    d = np.stack(np.broadcast_arrays(np.sin(phi)[None] * st, ct, -np.cos(phi)[None] * st), -1).reshape(-1, 3)
    dw = np.broadcast_to(st * (np.pi / (h - 1)) * (2 * np.pi / w), (h, w)).reshape(-1)

    def basis(v: np.ndarray) -> np.ndarray:
        x, y, z = v[:, 0], v[:, 1], v[:, 2]
        return np.stack([0.282095 + 0 * x, 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y,
                         1.092548 * y * z, 0.315392 * (3 * z * z - 1), 1.092548 * x * z,
                         0.546274 * (x * x - y * y)], -1)

    coeffs = basis(d).T @ (radiance.reshape(-1, 3) * dw[:, None])
    a = np.array([np.pi] + [2 * np.pi / 3] * 3 + [np.pi / 4] * 5)
    return basis(np.asarray(normals, dtype=np.float64)) @ (a[:, None] * coeffs)


@irradiance.register("plugin_sh2_numpy", "a user's order-2 SH irradiance in plain numpy",
                     thresholds={"flux_luminance.max": 0.0938},
                     source="R&H 2001 (JOSA): order-2 SH irradiance error ≤ 3/32 Φ for any lighting")
def plugin_sh2_numpy(radiance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return _sh2_irradiance(radiance, normals)


@specular.register("plugin_ambient_specular", "a user's crude specular: the mean radiance (no lobe)",
                   brdf=("phong", "ggx", "plastic", "conductor"))
def plugin_ambient_specular(radiance: np.ndarray, brdf: Mapping[str, Any], normals: np.ndarray,
                            views: np.ndarray) -> np.ndarray:
    return np.broadcast_to(np.maximum(radiance.reshape(-1, 3).mean(axis=0), 0.0), (len(normals), 3)).copy()


@arealight.register("plugin_point_shortcut", "a user's point-light shortcut: I cos θ / d² with I = L·A",
                    shapes=("disc", "sphere", "rectangle"))
def plugin_point_shortcut(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    c = np.asarray(light["center"], dtype=np.float64)
    r = float(light.get("radius", 0.0) or 0.0)
    size = light.get("size")
    area = float(np.prod(size)) if size is not None else np.pi * r * r
    to = c - np.asarray(points, dtype=np.float64)
    d2 = np.maximum((to * to).sum(-1), 1e-12)
    cos = np.maximum((np.asarray(normals) * to).sum(-1) / np.sqrt(d2), 0.0)
    n_l = light.get("normal")
    cos_l = 1.0 if n_l is None or light.get("shape") == "sphere" else np.maximum(-(to * np.asarray(n_l)).sum(-1)
                                                                              / np.sqrt(d2), 0.0)
    return float(light.get("radiance", 1.0)) * area * cos * cos_l / d2


@shadow.register("plugin_no_shadow", "a user's 'shadows off' baseline: V′ = 1 everywhere")
def plugin_no_shadow(shadow_map: Any, light: Any, points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    return np.ones(len(points))


@family("light").register("plugin_point_linear", "a user's point light with 1/d falloff (a common shader bug)",
                          lights=("point",))
def plugin_point_linear(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                        visible: Any = None) -> np.ndarray:
    p, n = np.asarray(points, dtype=np.float64), np.asarray(normals, dtype=np.float64)
    v = np.asarray(light["position"], dtype=np.float64) - p
    d = np.linalg.norm(v, axis=1)
    e = float(light["intensity"]) * np.maximum((v * n).sum(1) / d, 0.0) / d
    if visible is not None:
        e = e * visible(p, n, np.broadcast_to(light["position"], p.shape))
    return e


@family("brdf").register("plugin_wrap_lambert", "a user's wrap lighting ρ/π · max(0, (n·l + 0.2)/1.2)")
def plugin_wrap_lambert(params: Mapping[str, Any], normals: np.ndarray, lights: np.ndarray,
                        views: np.ndarray) -> np.ndarray:
    rho = np.asarray(params.get("albedo", 0.0), dtype=np.float64) * np.ones(3)
    c = np.sum(normals * lights, axis=1)
    cv = np.sum(normals * views, axis=1)
    out = rho / np.pi * np.maximum((c + 0.2) / 1.2, 0.0)[:, None]
    return np.where((cv > 0)[:, None], out, 0.0)


@family("uberlight").register("plugin_uberlight_half_power", "a user's überlight with 1/d falloff instead of 1/d²")
def plugin_uberlight_half_power(light: Mapping[str, Any], points: np.ndarray, normals: np.ndarray,
                                views: np.ndarray, material: Mapping[str, Any],
                                shadow: np.ndarray | None = None) -> np.ndarray:
    from validate.local_models.uberlight import orange_book as ub

    d = np.linalg.norm(np.asarray(points, dtype=np.float64) - np.asarray(light["position"], dtype=np.float64), axis=1)
    return ub.shade(light, points, normals, views, material, shadow, 1.0 / d)


@family("specular_arealight").register("plugin_point_specular", "a user's point-light specular: the light's "
                                       "whole power along the centre direction, GGX D·G·F/4 (no area)")
def plugin_point_specular(light: Mapping[str, Any], brdf: Mapping[str, Any], points: np.ndarray,
                          normals: np.ndarray, views: np.ndarray) -> np.ndarray:
    to = np.asarray(light["center"], dtype=np.float64) - np.asarray(points, dtype=np.float64)
    d2 = np.maximum((to * to).sum(-1), 1e-12)
    l = to / np.sqrt(d2)[:, None]
    n, v = np.asarray(normals, dtype=np.float64), np.asarray(views, dtype=np.float64)
    h = l + v
    h /= np.maximum(np.linalg.norm(h, axis=1), 1e-12)[:, None]
    a2 = float(brdf["alpha"]) ** 2
    nh, nl, nv = (n * h).sum(-1), np.maximum((n * l).sum(-1), 0.0), np.maximum((n * v).sum(-1), 1e-6)
    dist = a2 / (np.pi * (nh * nh * (a2 - 1) + 1) ** 2)
    size = light.get("size")
    r = float(light.get("radius", 0.0) or 0.0)
    area = float(np.prod(size)) if size is not None else np.pi * r * r
    e = float(light.get("radiance", 1.0)) * area / d2 * nl
    return np.repeat((float(brdf.get("f0", 1.0)) * dist / (4 * nv) * e)[:, None], 3, axis=1)


PLUGIN_TECHNIQUES = {"irradiance": "plugin_sh2_numpy", "specular": "plugin_ambient_specular",
                     "arealight": "plugin_point_shortcut", "shadow": "plugin_no_shadow",
                     "light": "plugin_point_linear", "brdf": "plugin_wrap_lambert",
                     "uberlight": "plugin_uberlight_half_power", "specular_arealight": "plugin_point_specular"}
assert set(PLUGIN_TECHNIQUES) <= set(FAMILIES)

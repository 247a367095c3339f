"""Mitsuba truth of a user's glTF (:class:`validate.scenes.gltf_import.GltfScene`), per pixel, with its standard error.

The scene, as Mitsuba sees it:

* Meshes: one ``mi.Mesh`` per primitive, world-space positions, vertex normals (interpolated: Mitsuba's shading
  normal; none → the face normal), ``TEXCOORD_0`` as given (Mitsuba's ``si.uv`` is glTF's uv unchanged: measured,
  ``tests/infra/test_gltf_truth.py``), and, where a normal texture is used and the file has ``TANGENT``, the
  tangent and bitangent (B = (N × T) w) as vertex attributes ``vertex_tangent``/``vertex_bitangent``.
* Material: the plug-in ``gltf_textured`` below — glTF 2.0 Appendix B [1], the formulas of
  :mod:`validate.reference.gltf_bsdf` generalised by KHR_materials_specular and _ior [2]:

      f0 = min(((ior − 1)/(ior + 1))² specularColor, 1) · specular,   f90 = specular
      F_d(f0, f90) = f0 + (f90 − f0)(1 − |V·H|)⁵
      dielectric = (1 − F_d) baseColor/π + F_d V D,   metal = F(baseColor, 1) V D
      f = (1 − metallic) dielectric + metallic metal

  (specular = 1, specularColor = 1, ior = 1.5 is ``gltf_metallic_roughness`` exactly; specular = 0 is Lambert),
  with baseColor = factor × texture, metallic = factor × B, roughness = factor × G of the metallic-roughness
  texture, α = roughness² (≥ ``ALPHA_MIN``). Textures are sampled at the hit's uv (:class:`TextureLookup`:
  bilinear between texel centres or nearest, wrapS/wrapT each of repeat, clamp, mirror).
* Normal map: n' = normalise((2c − 1)·(s, s, 1) in (T, B, N)); T, B from the vertex attributes, or without
  ``TANGENT`` from the triangle's ∂p/∂u orthogonalised to N and B = N × T — the glTF Sample Viewer's fallback
  (``material_info.glsl`` getNormalInfo, screen-space uv derivatives = the triangle's ∂p/∂u). The BRDF is
  evaluated in the frame of n' (both directions above it), and, as Mitsuba's own ``normalmap``, both must also lie
  on the shading normal's side. ``doubleSided``: a back-face hit flips n' (the Sample Viewer flips T, B, N);
  single-sided back faces are black (Mitsuba has no culling: a camera that sees a back face sees black there).
* Emission: Mitsuba ``area`` emitter on the mesh, radiance = emissiveFactor × emissiveTexture × strength
  (Mitsuba's ``bitmap`` texture, whose uv convention is glTF's: row 0 at v = 0), one-sided (the front).
* Lights and environment: the suite's own mapping (:func:`validate.scenes.render_scenes.mitsuba_light`: lux → W/m²,
  cd → W/sr, KHR's spot falloff exact; :func:`~validate.scenes.render_scenes.mitsuba_environment`: the equirect in
  the orientation of :mod:`validate.scenes.env_orientation`).
* Transport: ``direct`` — Mitsuba ``path`` with max_depth 2 (camera ray, emission seen, one bounce of lights and
  environment with shadows: what an engine without global illumination computes, and the suite's scenes' truth)
  or ``full`` (max_depth −1, Russian roulette from depth 5: unbiased). Emitters are visible to the camera (an
  emissive mesh must show); pixels whose centre ray misses every mesh are NaN (not judged).

Statistics as :mod:`validate.reference.render_reference`: P passes of ``spp`` samples per pixel centre, pass i
seeded seed·MAX_PASSES + i; per pixel the mean and s = std(passes, ddof 1)/√P. Cached by the file's content hash
(every byte it reads), the environment's, the image size and the settings (:func:`render_gltf_truth`).

[1] Khronos, glTF 2.0 Specification, Appendix B; 3.9.3 (normal textures: "+Y up", B = cross(N, T) · w).
[2] Khronos, KHR_materials_specular ("dielectric_f0 = min(f0_ior · specularColor, 1) · specular,
    dielectric_f90 = specular"), KHR_materials_ior.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import ValidateError
from ..scenes.gltf_import import GltfMaterial, GltfScene, MeshPart, Texture
from ..scenes.render_scenes import Environment, mitsuba_environment, mitsuba_light
from ..stats import mean_and_stderr
from .cache import array_digest, cached
from .gltf_bsdf import ALPHA_MIN, ggx_d, mixture_pdf, reflection_sample, smith_v_height_correlated
from .render_reference import MAX_PASSES, MIN_PASSES, RenderReference, trace_pass

TRANSPORTS = {"direct": {"type": "path", "max_depth": 2, "hide_emitters": False},
              "full": {"type": "path", "max_depth": -1, "rr_depth": 5, "hide_emitters": False}}
GLTF_TRUTH_VERSION = 1  # bump when the translation changes what is traced


# ---------------------------------------------------------------- textures and the BRDF (drjit, any variant)

class TextureLookup:
    """A :class:`~validate.scenes.gltf_import.Texture` sampled at uv (glTF: u right, v down from the image's top
    row): texel (i, j) centred at ((j + ½)/W, (i + ½)/H); linear = bilinear between the four nearest centres,
    nearest = the texel containing uv; indices outside wrap per axis (repeat, clamp to edge, mirrored repeat as
    OpenGL's MIRRORED_REPEAT)."""

    def __init__(self, tex: Texture) -> None:
        import mitsuba as mi

        t = np.asarray(tex.texels, np.float32)
        self.h, self.w, self.c = t.shape
        self.data = mi.Float(np.ascontiguousarray(t).ravel())
        self.wrap, self.filter = tex.wrap, tex.filter

    @staticmethod
    def _wrap(i: Any, n: int, mode: str) -> Any:
        import drjit as dr
        import mitsuba as mi

        if mode == "clamp":
            return dr.clip(i, 0, n - 1)
        if mode == "repeat":
            return i - n * mi.Int32(dr.floor(mi.Float(i) / n))
        k = i - 2 * n * mi.Int32(dr.floor(mi.Float(i) / (2 * n)))
        return dr.select(k < n, k, 2 * n - 1 - k)

    def eval(self, uv: Any) -> list[Any]:
        """The C channels (mi.Float each) at ``uv`` (mi.Point2f)."""
        import drjit as dr
        import mitsuba as mi

        def fetch(ix: Any, iy: Any) -> list[Any]:
            base = (self._wrap(iy, self.h, self.wrap[1]) * self.w + self._wrap(ix, self.w, self.wrap[0])) * self.c
            return [dr.gather(mi.Float, self.data, mi.UInt32(base + k)) for k in range(self.c)]

        x, y = uv.x * self.w, uv.y * self.h
        if self.filter == "nearest":
            return fetch(mi.Int32(dr.floor(x)), mi.Int32(dr.floor(y)))
        x, y = x - 0.5, y - 0.5
        x0, y0 = dr.floor(x), dr.floor(y)
        fx, fy = x - x0, y - y0
        ix, iy = mi.Int32(x0), mi.Int32(y0)
        a, b, c, d = fetch(ix, iy), fetch(ix + 1, iy), fetch(ix, iy + 1), fetch(ix + 1, iy + 1)
        return [(a[k] * (1 - fx) + b[k] * fx) * (1 - fy) + (c[k] * (1 - fx) + d[k] * fx) * fy for k in range(self.c)]


def fresnel_f0_f90(specular: float, specular_color: tuple[float, float, float], ior: float
                   ) -> tuple[list[float], float]:
    """(dielectric f0 per channel, f90) of KHR_materials_specular and _ior [2] (ior 0: KHR_materials_ior's
    "infinite" ior, f0_ior = 1)."""
    f0_ior = 1.0 if ior == 0 else ((ior - 1.0) / (ior + 1.0)) ** 2
    return [min(f0_ior * c, 1.0) * specular for c in specular_color], float(specular)


def textured_brdf_cos(wi: Any, wo: Any, base: Any, metallic: Any, alpha: Any, f0: Any, f90: Any) -> Any:
    """f(ω_i, ω_o) μ_o of the module docstring in the local frame (n = +z); 0 unless both above."""
    import drjit as dr

    h = dr.normalize(wi + wo)
    x = 1.0 - dr.clip(dr.abs(dr.dot(wi, h)), 0.0, 1.0)
    x5 = x * x * x * x * x
    spec = smith_v_height_correlated(wo.z, wi.z, alpha) * ggx_d(h.z, alpha)
    fd = f0 + (f90 - f0) * x5
    dielectric = (1.0 - fd) * base * dr.inv_pi + fd * spec
    metal = (base + (1.0 - base) * x5) * spec
    f = (1.0 - metallic) * dielectric + metallic * metal
    return dr.select((wi.z > 0.0) & (wo.z > 0.0), f * wo.z, 0.0)


def _spectrum(vals: list[Any]) -> Any:
    import drjit as dr
    import mitsuba as mi

    return mi.Spectrum(mi.Color3f(*vals)) if dr.is_array_v(mi.Spectrum) else mi.Spectrum(*vals)


def material_params(mat: GltfMaterial, tex: dict[str, Any], si: Any) -> tuple[Any, Any, Any]:
    """(base colour, metallic, α = max(roughness², ALPHA_MIN)) at ``si``: the factors times their textures
    (glTF 2.0 §3.9.2: metallic in B, roughness in G of the metallic-roughness texture)."""
    import drjit as dr
    import mitsuba as mi

    base = [mi.Float(v) for v in mat.base_color[:3]]
    if tex["base_color_texture"] is not None:
        base = [b * t for b, t in zip(base, tex["base_color_texture"].eval(si.uv), strict=True)]
    metallic, rough = mi.Float(mat.metallic), mi.Float(mat.roughness)
    if tex["metallic_roughness_texture"] is not None:
        _, g, b = tex["metallic_roughness_texture"].eval(si.uv)
        metallic, rough = metallic * b, rough * g
    return _spectrum(base), metallic, dr.maximum(rough * rough, ALPHA_MIN)


def shading_frame(mat: GltfMaterial, tex: dict[str, Any], tangents: bool, si: Any, active: Any) -> tuple[Any, Any]:
    """(the frame of the shading normal n' in world space, the sign: −1 on a double-sided back face); the normal
    texture's n' = normalize((2c − 1)·(s, s, 1) in (t, b, n)) (glTF 2.0 §3.9.3), the tangents from the mesh or from
    ∂p/∂u."""
    import drjit as dr
    import mitsuba as mi

    n = si.sh_frame.n
    sign = dr.select(si.wi.z < 0.0, -1.0, 1.0) if mat.double_sided else mi.Float(1.0)
    if tex["normal_texture"] is not None:
        if tangents:
            t = mi.Vector3f(si.shape.eval_attribute_3("vertex_tangent", si, active))
            b = mi.Vector3f(si.shape.eval_attribute_3("vertex_bitangent", si, active))
        else:
            t = dr.normalize(si.dp_du - n * dr.dot(n, si.dp_du))
            b = dr.cross(n, t)
        c = tex["normal_texture"].eval(si.uv)
        s = mat.normal_scale
        n = dr.normalize((2.0 * c[0] - 1.0) * s * t + (2.0 * c[1] - 1.0) * s * b + (2.0 * c[2] - 1.0) * n)
    return mi.Frame3f(n * sign), sign


def _plugin_class() -> type:
    import drjit as dr
    import mitsuba as mi

    class GltfTextured(mi.BSDF):
        """glTF metallic-roughness with textures (module docstring); configured by :meth:`configure`."""

        def __init__(self, props: Any) -> None:
            super().__init__(props)
            self.m_flags = mi.BSDFFlags.GlossyReflection | mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide
            self.m_components = [self.m_flags]

        def configure(self, mat: GltfMaterial, tangents: bool) -> None:
            self.mat = mat
            self.tex = {k: None if getattr(mat, k) is None else TextureLookup(getattr(mat, k))
                        for k in ("base_color_texture", "metallic_roughness_texture", "normal_texture")}
            self.f0, self.f90 = fresnel_f0_f90(mat.specular, mat.specular_color, mat.ior)
            self.tangents = tangents
            if mat.double_sided:
                self.m_flags = self.m_flags | mi.BSDFFlags.BackSide
                self.m_components = [self.m_flags]

        def _local(self, si: Any, wo: Any, active: Any) -> tuple[Any, Any, Any, Any]:
            frame, sign = shading_frame(self.mat, self.tex, self.tangents, si, active)
            wi_l = frame.to_local(si.to_world(si.wi))
            wo_l = frame.to_local(si.to_world(wo))
            ok = active & (si.wi.z * sign > 0.0) & (wo.z * sign > 0.0) & (wi_l.z > 0.0) & (wo_l.z > 0.0)
            return frame, wi_l, wo_l, ok

        def eval(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            _, wi_l, wo_l, ok = self._local(si, wo, active)
            base, metallic, alpha = material_params(self.mat, self.tex, si)
            f = textured_brdf_cos(wi_l, wo_l, base, metallic, alpha, _spectrum(self.f0), self.f90)
            return dr.select(ok, f, mi.Spectrum(0.0))

        def pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            _, wi_l, wo_l, ok = self._local(si, wo, active)
            _, metallic, alpha = material_params(self.mat, self.tex, si)
            return dr.select(ok, mixture_pdf(wi_l, wo_l, alpha, 0.5 * (1.0 - metallic)), 0.0)

        def eval_pdf(self, ctx: Any, si: Any, wo: Any, active: Any = True) -> Any:
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx: Any, si: Any, sample1: Any, sample2: Any, active: Any = True) -> Any:
            frame, sign = shading_frame(self.mat, self.tex, self.tangents, si, active)
            wi_l = frame.to_local(si.to_world(si.wi))
            base, metallic, alpha = material_params(self.mat, self.tex, si)
            p_d = 0.5 * (1.0 - metallic)
            md = mi.MicrofacetDistribution(mi.MicrofacetType.GGX, alpha, True)
            m, _ = md.sample(dr.select(wi_l.z > 0.0, wi_l, mi.Vector3f(0.0, 0.0, 1.0)), sample2)
            wo_l = dr.select(sample1 < p_d, mi.warp.square_to_cosine_hemisphere(sample2), mi.reflect(wi_l, m))
            wo = si.to_local(frame.to_world(wo_l))
            pdf = mixture_pdf(wi_l, wo_l, alpha, p_d)
            ok = active & (si.wi.z * sign > 0.0) & (wo.z * sign > 0.0) & (wi_l.z > 0.0) & (wo_l.z > 0.0) & \
                (pdf > 0.0)
            f = textured_brdf_cos(wi_l, wo_l, base, metallic, alpha, _spectrum(self.f0), self.f90)
            return reflection_sample(wo, pdf, ok, f)

        def traverse(self, callback: Any) -> None:
            return None

        def to_string(self) -> str:
            return f"GltfTextured[{self.mat.name}]"

    return GltfTextured


_CLASS: list[type] = []


def textured_bsdf(mat: GltfMaterial, tangents: bool = False) -> Any:
    """A ``gltf_textured`` BSDF object for ``mat`` (``tangents``: the mesh carries vertex_tangent/_bitangent)."""
    import mitsuba as mi

    from ..backend import init

    init()
    if not _CLASS:
        _CLASS.append(_plugin_class())
    b = _CLASS[0](mi.Properties())
    b.configure(mat, tangents)
    return b


# ---------------------------------------------------------------- the scene

def area_emitter(mat: GltfMaterial) -> dict[str, Any] | None:
    """Mitsuba ``area`` emitter of the material's emission (module docstring), None when it emits nothing."""
    import mitsuba as mi

    k = np.asarray(mat.emissive, np.float64) * mat.emissive_strength
    if not k.any():
        return None
    if mat.emissive_texture is None:
        return {"type": "area", "radiance": {"type": "rgb", "value": k.tolist()}}
    tex = mat.emissive_texture
    texels = np.ascontiguousarray(np.asarray(tex.texels, np.float64)[..., :3] * k, np.float32)
    return {"type": "area", "radiance": {"type": "bitmap", "bitmap": mi.Bitmap(texels), "raw": True,
                                         "filter_type": "bilinear" if tex.filter == "linear" else "nearest",
                                         "wrap_mode": tex.wrap[0]}}


def mitsuba_mesh(part: MeshPart, mat: GltfMaterial) -> Any:
    """The ``mi.Mesh`` of one primitive with its BSDF (and area emitter)."""
    import mitsuba as mi

    props = mi.Properties()
    tangents = part.tangents is not None and mat.normal_texture is not None and part.normals is not None
    props["bsdf"] = textured_bsdf(mat, tangents)
    em = area_emitter(mat)
    if em is not None:
        props["emitter"] = mi.load_dict(em)
    mesh = mi.Mesh(part.name, len(part.positions), len(part.triangles), props, part.normals is not None,
                   part.uvs is not None)
    p = mi.traverse(mesh)
    p["vertex_positions"] = mi.Float(np.ascontiguousarray(part.positions, np.float32).ravel())
    if part.normals is not None:
        p["vertex_normals"] = mi.Float(np.ascontiguousarray(part.normals, np.float32).ravel())
    if part.uvs is not None:
        p["vertex_texcoords"] = mi.Float(np.ascontiguousarray(part.uvs, np.float32).ravel())
    p["faces"] = mi.UInt32(np.ascontiguousarray(part.triangles, np.uint32).ravel())
    p.update()
    if tangents:
        t, w = part.tangents[:, :3], part.tangents[:, 3:]
        b = np.cross(part.normals, t) * w
        mesh.add_attribute("vertex_tangent", 3, mi.Float(np.ascontiguousarray(t, np.float32).ravel()))
        mesh.add_attribute("vertex_bitangent", 3, mi.Float(np.ascontiguousarray(b, np.float32).ravel()))
    return mesh


def mitsuba_scene(scene: GltfScene, env: np.ndarray | None, transport: str) -> Any:
    """The loaded Mitsuba scene: meshes, lights, the environment, the integrator of ``transport``."""
    import mitsuba as mi

    d: dict[str, Any] = {"type": "scene", "integrator": dict(TRANSPORTS[transport])}
    for k, part in enumerate(scene.meshes):
        if len(part.triangles):
            d[f"mesh{k}"] = mitsuba_mesh(part, scene.material_of(part))
    for k, li in enumerate(scene.lights):
        d[f"light{k}"] = mitsuba_light(li)
    if env is not None:
        d["environment"] = mitsuba_environment(Environment("env", texels=np.asarray(env, np.float64)))
    return mi.load_dict(d)


@dataclass
class GltfTruth(RenderReference):
    """:class:`RenderReference` of a glTF scene: (H, W, 3) mean and standard error (NaN where the centre ray misses),
    the (H, W) hit mask, the transport traced, and the passes themselves, (P, N, 3) over the N hit pixels in row
    order (pass i seeded seed·MAX_PASSES + i, so two truths of one seed pair pass by pass; a figure summed over many
    pixels takes its uncertainty from them: within one pass Mitsuba's samples of different pixels are not
    independent enough for Σ stderr², :mod:`validate.metrics.transport_share`)."""

    transport: str = "direct"
    pass_values: np.ndarray | None = field(default=None, repr=False)


def render_gltf_truth(scene: GltfScene, width: int, height: int, env: np.ndarray | None = None, spp: int = 64,
                      passes: int = 8, seed: int = 0, transport: str = "direct") -> GltfTruth:
    """P passes of ``spp`` samples along every pixel-centre ray of the first camera (module docstring); cached on
    the file's content, the environment's texels, the image size and the settings."""
    import mitsuba as mi

    from ..backend import init

    if transport not in TRANSPORTS:
        raise ValidateError(f"--transport {transport}: not one of {', '.join(TRANSPORTS)}")
    if spp < 1:
        raise ValidateError(f"{scene.path}: spp={spp}: need at least 1 sample per pixel")
    if not MIN_PASSES <= passes <= MAX_PASSES:
        raise ValidateError(f"{scene.path}: passes={passes}: need {MIN_PASSES}..{MAX_PASSES}")
    origins, dirs = scene.pixel_rays(width, height)

    def compute() -> dict[str, np.ndarray]:
        init()
        sc = mitsuba_scene(scene, env, transport)
        ray = mi.Ray3f(mi.Point3f(*(mi.Float(origins[:, k]) for k in range(3))),
                       mi.Vector3f(*(mi.Float(dirs[:, k]) for k in range(3))))
        hit = np.asarray(sc.ray_intersect(ray).is_valid(), bool)
        o, dd = origins[hit], dirs[hit]
        if not len(o):
            return {"hit": hit, "passes": np.zeros((passes, 0, 3))}
        rep = [np.repeat(a, spp, axis=0) for a in (o, dd)]
        rays = mi.RayDifferential3f(mi.Point3f(*(mi.Float(rep[0][:, k]) for k in range(3))),
                                    mi.Vector3f(*(mi.Float(rep[1][:, k]) for k in range(3))))
        return {"hit": hit, "passes": np.stack([trace_pass({}, o, spp, seed * MAX_PASSES + i, (sc, rays))
                                                for i in range(passes)])}

    parts = {"scene": scene.key(), "size": [width, height], "spp": spp, "passes": passes, "seed": seed,
             "integrator": TRANSPORTS[transport], "environment": None if env is None else array_digest(
                 np.asarray(env, np.float32)), "version": GLTF_TRUTH_VERSION, "rays": "pixel centres, first camera"}
    out = cached("gltf_truth", parts, compute)
    hit = out["hit"].astype(bool).reshape(height, width)
    p = out["passes"]
    if not hit.any():
        raise ValidateError(f"{scene.path}: no pixel-centre ray of the camera meets a mesh: nothing to judge")
    if not np.all(np.isfinite(p)) or p.min() < 0:
        raise ValidateError(f"{scene.path}: the truth has NaN/Inf or negative pixels")
    m, s = mean_and_stderr(p, axis=0)
    mean, stderr = np.full((height, width, 3), np.nan), np.full((height, width, 3), np.nan)
    mean[hit], stderr[hit] = m, s
    return GltfTruth(mean, stderr, hit, spp, passes, seed, transport, p)

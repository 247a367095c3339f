"""Blender's side of the Blender engines: run by Blender's own Python (the ``bpy`` venv), never imported by the suite.

    <blender-venv>/bin/python blender_worker.py JOBS.json RESULT.json

One process renders a batch of scenes (start-up once). ``JOBS.json``::

    {"jobs": [{"glb": ".../scene.glb", "out": ".../scene",  # frames go to <out>_<k>.exr
               "engine": "CYCLES" | "BLENDER_EEVEE", "resolution": 64, "samples": 16, "seeds": [0, 1, 2, 3],
               "lighting_mode": "SPEC" | "COMPAT" | "RAW",    # the glTF importer's light conversion
               "world": [1, 1, 1] | null,                      # a constant world radiance (the furnace), else black
               "punctual": true}]}                             # lights made punctual (radius 0, sun angle 0)

Each job: factory settings (empty), ``bpy.ops.import_scene.gltf`` with the stated light conversion, the file's
camera made the scene camera, the render settings below, one still per seed written as an RGBA float32 OpenEXR
(row 0 = top, alpha = coverage: film transparent). ``RESULT.json`` holds per job what the importer made of every
light (type, energy in W or W/m², radius, sun angle, spot size and blend: the conversion is *read back*, not
assumed), the seconds per frame, and Blender's version; on an error, the job's one-line error.

Render settings (what makes Blender's images comparable with the suite's pixel-centre truth):
* Colour: view transform Standard, exposure 0, gamma 1 (an EXR is written scene-linear either way).
* Cycles: CPU, ``samples`` per frame with adaptive sampling and denoising off, the seed of the frame; the pixel
  filter a box of the minimum width 0.01 px (one ray through the pixel centre, as the truth traces); light
  threshold 0 and no clamping (both bias the estimate); Filter Glossy 0.
* EEVEE: ``taa_render_samples`` = samples, film filter 0.01 px; shadows on.
This file imports nothing of the suite and no numpy (Blender's venv has its own numpy < 2).
"""

from __future__ import annotations

import json
import math
import sys
import time


def _light_info(obj: object) -> dict:
    li = obj.data  # type: ignore[attr-defined]
    out = {"name": obj.name, "type": li.type, "energy": float(li.energy),  # type: ignore[attr-defined]
           "color": [float(c) for c in li.color]}
    if li.type in ("POINT", "SPOT"):
        out["radius"] = float(li.shadow_soft_size)
        out["soft_falloff"] = bool(getattr(li, "use_soft_falloff", False))
    if li.type == "SPOT":
        out["spot_size"] = float(li.spot_size)
        out["spot_blend"] = float(li.spot_blend)
    if li.type == "SUN":
        out["angle"] = float(li.angle)
    return out


def _settings(scene: object, job: dict) -> None:
    import bpy  # noqa: F401  (the settings below are bpy's)

    r = scene.render  # type: ignore[attr-defined]
    r.engine = job["engine"]
    r.resolution_x = r.resolution_y = int(job["resolution"])
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = True
    r.use_compositing = False
    r.use_sequencer = False
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_mode = "RGBA"
    r.image_settings.color_depth = "32"
    r.image_settings.exr_codec = "ZIP"
    vs = scene.view_settings  # type: ignore[attr-defined]
    vs.view_transform = "Standard"
    vs.look = "None"
    vs.exposure = 0.0
    vs.gamma = 1.0
    if job["engine"] == "CYCLES":
        c = scene.cycles  # type: ignore[attr-defined]
        c.device = "CPU"
        c.samples = int(job["samples"])
        c.use_adaptive_sampling = False
        c.use_denoising = False
        c.pixel_filter_type = "BOX"
        c.filter_width = 0.01
        c.light_sampling_threshold = 0.0
        c.sample_clamp_direct = 0.0
        c.sample_clamp_indirect = 0.0
        c.blur_glossy = 0.0
    else:
        scene.eevee.taa_render_samples = int(job["samples"])  # type: ignore[attr-defined]
        r.filter_size = 0.01
    built = job.get("scene") or {}
    if "filter_px" in built:  # a bpy-built scene states its pixel filter (the truth's box over the footprint)
        if job["engine"] == "CYCLES":
            scene.cycles.filter_width = float(built["filter_px"])  # type: ignore[attr-defined]
        else:
            r.filter_size = float(built["filter_px"])
    for k, v in built.get("eevee", {}).items():
        setattr(scene.eevee, k, v)  # type: ignore[attr-defined]
    if job["engine"] == "CYCLES":
        for k, v in built.get("cycles", {}).items():
            setattr(scene.cycles, k, v)  # type: ignore[attr-defined]


def _world(scene: object, rgb: list | None) -> None:
    import bpy

    w = bpy.data.worlds.new("validate_world")
    w.use_nodes = True
    bg = w.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*(rgb or (0.0, 0.0, 0.0)), 1.0)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = w  # type: ignore[attr-defined]


def _lambert(albedo: float) -> object:
    import bpy

    mat = bpy.data.materials.new("validate_lambert")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    d.inputs["Roughness"].default_value = 0.0  # Lambert (non-zero: Oren–Nayar)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    return mat


def _env_world(path: str, attrs: dict) -> object:
    import bpy

    w = bpy.data.worlds.new("validate_world")
    w.use_nodes = True
    nodes, links = w.node_tree.nodes, w.node_tree.links
    bg = nodes["Background"]
    tex = nodes.new("ShaderNodeTexEnvironment")
    tex.image = bpy.data.images.load(path)
    for cs in ("Linear Rec.709", "Linear"):
        try:
            tex.image.colorspace_settings.name = cs
            break
        except TypeError:
            continue
    tex.interpolation = "Linear"
    tex.projection = "EQUIRECTANGULAR"
    links.new(tex.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 1.0
    for k, v in attrs.items():
        setattr(w, k, v)
    return w


def _glossy(roughness: float, distribution: str) -> object:
    """Cycles' and EEVEE's Glossy BSDF, white (F = 1: the node applies no Fresnel), α = roughness²."""
    import bpy

    mat = bpy.data.materials.new("validate_glossy")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    g = nt.nodes.new("ShaderNodeBsdfGlossy")
    g.distribution = distribution  # "GGX": single scattering ("MULTI_GGX" adds the multiple-scattering lobe)
    g.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    g.inputs["Roughness"].default_value = roughness
    g.inputs["Anisotropy"].default_value = 0.0
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(g.outputs[0], out.inputs["Surface"])
    return mat


def _material(spec: dict, albedo: float) -> object:
    if spec.get("type") == "glossy":
        return _glossy(float(spec["roughness"]), str(spec.get("distribution", "GGX")))
    return _lambert(albedo)


def _probes(scene: object, probes: list, sphere: object) -> None:
    """EEVEE light-probe objects: ``{"type": "SPHERE", "location", "radius" (influence), "hide_sphere",
    "parallax"}`` (captured at render; ``parallax``: a custom spherical parallax volume of that radius) or
    ``{"type": "VOLUME", "location", "scale", "resolution", "samples"}`` baked now
    (``lightprobe_cache_bake``)."""
    import bpy

    for p in probes:
        bpy.ops.object.lightprobe_add(type=p["type"], location=p.get("location", (0.0, 0.0, 0.0)))
        o = bpy.context.active_object
        if p["type"] == "SPHERE":
            o.data.influence_distance = float(p.get("radius", 2.5))
            sphere.hide_probe_sphere = bool(p.get("hide_sphere", True))  # type: ignore[attr-defined]
            if "parallax" in p:
                o.data.use_custom_parallax = True
                o.data.parallax_type = "ELIPSOID"
                o.data.parallax_distance = float(p["parallax"])
        elif p["type"] == "VOLUME":
            o.scale = tuple(p["scale"])
            o.data.resolution_x, o.data.resolution_y, o.data.resolution_z = (int(v) for v in p["resolution"])
            o.data.bake_samples = int(p.get("samples", 256))
            if scene.render.engine != "CYCLES":  # type: ignore[attr-defined]
                r = bpy.ops.object.lightprobe_cache_bake(subset="ALL")
                if "FINISHED" not in r:
                    raise RuntimeError(f"lightprobe_cache_bake returned {sorted(r)}")


def build(job: dict) -> object:
    """A bpy-built scene (``job["scene"]``); kind ``world_sphere``: a smooth UV sphere of radius 1 at the origin,
    Lambertian of ``albedo`` (or ``bsdf`` = {"type": "glossy", "roughness", "distribution"}), lit only by the
    equirectangular world ``env_exr`` (Blender's own mapping), seen by an orthographic camera of ``ortho_scale`` with
    the 4 × 4 ``camera`` matrix (row-major, Blender world); ``plane`` [z, size, albedo]: a Lambertian square below
    it; ``cycles``: Cycles settings (e.g. bounces; :func:`_settings`); ``probes``: EEVEE light-probe objects
    (:func:`_probes`, added after the render settings)."""
    import bpy
    from mathutils import Matrix

    sc = job["scene"]
    if sc["kind"] != "world_sphere":
        raise RuntimeError(f"unknown built scene kind {sc['kind']!r}")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_uv_sphere_add(segments=int(sc["segments"]), ring_count=int(sc["rings"]), radius=1.0)
    obj = bpy.context.active_object
    for poly in obj.data.polygons:
        poly.use_smooth = True
    obj.data.materials.append(_material(sc.get("bsdf") or {}, float(sc["albedo"])))
    if sc.get("plane"):
        z, size, albedo = (float(v) for v in sc["plane"])
        bpy.ops.mesh.primitive_plane_add(size=size, location=(0.0, 0.0, z))
        bpy.context.active_object.data.materials.append(_lambert(albedo))
        bpy.context.view_layer.objects.active = obj
    cd = bpy.data.cameras.new("validate_camera")
    cd.type = "ORTHO"
    cd.ortho_scale = float(sc["ortho_scale"])
    cd.clip_start, cd.clip_end = 0.01, 100.0
    cam = bpy.data.objects.new("validate_camera", cd)
    scene.collection.objects.link(cam)
    cam.matrix_world = Matrix([list(r) for r in sc["camera"]])
    scene.camera = cam
    scene.world = _env_world(sc["env_exr"], sc.get("world", {}))
    return scene


def run_job(job: dict) -> dict:
    import bpy

    t0 = time.perf_counter()
    if job.get("scene"):
        scene = build(job)
        _settings(scene, job)
        if job["scene"].get("probes"):
            _probes(scene, job["scene"]["probes"], bpy.data.objects["Sphere"])
        return _render(job, scene, [], [], t0, scene.camera)  # type: ignore[attr-defined]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=job["glb"], export_import_convert_lighting_mode=job["lighting_mode"])
    scene = bpy.context.scene
    cams = [o for o in scene.objects if o.type == "CAMERA"]
    if len(cams) != 1:
        raise RuntimeError(f"{job['glb']}: {len(cams)} cameras after import (need 1)")
    scene.camera = cams[0]
    lights = [o for o in scene.objects if o.type == "LIGHT"]
    imported = [_light_info(o) for o in lights]
    if job.get("punctual", True):
        for o in lights:
            if o.data.type in ("POINT", "SPOT"):
                o.data.shadow_soft_size = 0.0
            if o.data.type == "SUN":
                o.data.angle = 0.0
    _settings(scene, job)
    _world(scene, job.get("world"))
    _extras(scene, lights, job.get("extras") or {})
    return _render(job, scene, lights, imported, t0, cams[0])


def _extras(scene: object, lights: list, ex: dict) -> None:
    """What the .glb cannot carry, added after import: ``boxes`` ([[centre], [size]] in Blender's frame; black
    Lambert, never seen), ``light_radius`` (every light a sphere of that radius, soft falloff off: a uniform sphere
    emitter), ``area_disc`` ({"radius", "power"}: every light an AREA light of shape DISK, spread 180°), ``light``
    (bpy Light attributes, e.g. use_shadow_jitter), ``eevee`` (SceneEEVEE attributes, e.g. light_threshold),
    ``direct_only`` (Cycles max_bounces 0)."""
    import bpy

    for centre, size in ex.get("boxes", []):
        bpy.ops.mesh.primitive_cube_add(size=2.0, location=centre, scale=[0.5 * v for v in size])
        bpy.context.active_object.data.materials.append(_lambert(0.0))
    for o in lights:
        if "area_disc" in ex:  # the light re-typed as a one-sided disc emitter along its −Z (the spot's direction)
            o.data.type = "AREA"
            area = bpy.data.lights[o.data.name]  # re-fetched: the wrapper refines to AreaLight
            area.shape = "DISK"
            area.size = 2.0 * float(ex["area_disc"]["radius"])
            area.energy = float(ex["area_disc"]["power"])
            area.spread = math.pi
        elif "light_radius" in ex:
            o.data.shadow_soft_size = float(ex["light_radius"])
            o.data.use_soft_falloff = False
        for k, v in ex.get("light", {}).items():
            setattr(o.data, k, v)
    if scene.render.engine != "CYCLES":  # type: ignore[attr-defined]
        for k, v in ex.get("eevee", {}).items():
            setattr(scene.eevee, k, v)  # type: ignore[attr-defined]
    if ex.get("direct_only") and scene.render.engine == "CYCLES":  # type: ignore[attr-defined]
        scene.cycles.max_bounces = 0  # type: ignore[attr-defined]


def _render(job: dict, scene: object, lights: list, imported: list, t0: float, cam: object) -> dict:
    import bpy

    t_setup = time.perf_counter() - t0
    frames = []
    for k, seed in enumerate(job["seeds"]):
        if job["engine"] == "CYCLES":
            scene.cycles.seed = int(seed)
        scene.render.filepath = f"{job['out']}_{k}.exr"
        t1 = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        frames.append(time.perf_counter() - t1)
    return {"lights": imported, "rendered_lights": [_light_info(o) for o in lights], "setup_s": t_setup,
            "frame_s": frames, "camera": {"type": cam.data.type, "ortho_scale": float(cam.data.ortho_scale)},
            "files": [f"{job['out']}_{k}.exr" for k in range(len(job["seeds"]))]}


def main(argv: list[str]) -> int:
    t0 = time.perf_counter()
    import bpy

    t_import = time.perf_counter() - t0
    jobs = json.loads(open(argv[1], encoding="utf-8").read())["jobs"]
    results = []
    for job in jobs:
        try:
            results.append(run_job(job))
        except Exception as exc:  # one line per failed job; the batch goes on
            results.append({"error": f"{type(exc).__name__}: {' '.join(str(exc).split())[:300]}"})
    out = {"version": bpy.app.version_string, "import_s": t_import, "total_s": time.perf_counter() - t0,
           "pi": math.pi, "jobs": results}
    with open(argv[2], "w", encoding="utf-8") as fh:
        json.dump(out, fh)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv))

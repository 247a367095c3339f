"""``babylon``: Babylon.js 9.35 — PBRMaterial, its HDR prefilter, a TEXTURETYPE_FLOAT target (``babylon.html`` +
``babylon_render.mjs``, shadows ``babylon_shadows.mjs``, CDF irradiance ``babylon_cdf.mjs``), hosted in the run's
Chromium (:mod:`.hosted`).

Known defects and differences, each stated with its source and measurement (the renders claims keep them as
regressions, their power checks the corrected behaviour):

* furnace (``furnace``), measured here (64², 16 spp × 8 passes): Babylon 9.35's white dielectric returns 1.045 /
  1.017 / 0.981 at roughness 0.25 / 0.5 / 1 (its metal returns 1 to 6e-8; three.js 0.187 returns 1 to 1.4e-9).
* diffuse IBL (``probe_lambert``), measured (64², 1024 spp × 8): its Lambertian sphere under the probe is 1.085 ×
  Mitsuba on average (bias +8.5 %, 68 % of pixels accepted; its white metal in the constant furnace is 1 to 6e-8);
  three.js 0.187's is within 0.1 % — the corrected behaviour (``probe_lambert.corrected_by``).
* metalness mix (``probe_material.mix``), measured (64², FULL): its image at metalness 0.5 against the mix of its own
  metalness-0 and -1 images has bias −0.19 / −2.4 / −13.4 % at roughness 0.25 / 0.5 / 1 (67.6 / 0 / 0 % of pixels
  within the budget) — the defect three.js fixed in PR 32190; in the furnace (``furnace_material``), measured (64²,
  FULL): 1.019 / 0.980 / 0.859 at roughness 0.25 / 0.5 / 1 (its dielectric 1.045 / 1.017 / 0.981, its metal 1).
* rectangular area light (ltcHelperFunctions, three's LTC code): the clipped-sphere form factor
  (:data:`.hosted.LTC_CLIPPED_SPHERE`) on the sphere and on the plane — its V is normalize(eye position − P) even
  under an orthographic camera (vEyePosition), so the frame is defined and the plane gets the clipped-sphere value
  (measured 0.9999 ± 4e-4). Its unit: light.js _getPhotometricScale is 1 for LIGHTTYPEID_RECT_AREALIGHT in every
  intensity mode, the diffuse term areaLightDiffuse · diffuse · intensity with areaLightDiffuse the form factor.
  Rendered with a substitution (``notes["rect"]``): Babylon 9.35's RectAreaLight loads its LTC tables from
  assets.babylonjs.com (Lights/LTC/ltcTextureTool.js: Tools.LoadFileAsync of areaLightsLTC.bin) and the render
  machine has no network; babylon_render.mjs puts Heitz et al. 2016's GGX tables (three.js's
  RectAreaLightTexturesLib LTC_MAT_1 / LTC_MAT_2) where AreaLight looks for them (scene._ltcTextures, @internal:
  9.35 has no public LTC provider) in the channel layout its ltcHelperFunctions reads. The Lambertian scenes'
  diffuse term is LTCEvaluate with the identity matrix (the rectangle's form factor) and their specular term is 0
  (R0 = 0), so their pixels do not depend on the table (measured: bit-identical with a constant table; a dielectric
  with F0 = 0.04 at roughness 0.5 is not).
* PCSS shadows (``shadows.pcss.umbra``), measured (FULL, 64²): PCSS lights 100 % of the umbra, mean shadow factor
  14.8 % (directional) and 12.0 % (spot) (three issue 23551's kind of leak); its penumbra is wider than the path
  tracer's (3.3× directional, 1.4× spot; every other type's is narrower).

Variants: ``babylon_lambert`` (the diffuse model set to Lambert, MATERIAL_DIFFUSE_MODEL_LAMBERT = 2, instead of its
default energy-preserving Oren–Nayar); ``babylon_cdf<size>_<variant>`` — Babylon's CDF irradiance
(babylon_cdf.mjs; :mod:`validate.scenes.render_cdf_scenes`): the Lambert diffuse model, the cube of <size>,
supersampling as shipped (forced by Babylon PR 16247) or as before it. Variants render only where asked for by name.
"""

from __future__ import annotations

from .hosted import LTC_CLIPPED_SPHERE, BrowserEngine

PAGE = dict(page="babylon.html", entry="renderBabylon", package="@babylonjs/core",
            scripts=("babylon_render.mjs", "babylon_shadows.mjs", "babylon_cdf.mjs", "babylon_scene.mjs"))
SUPPORTS = ("furnace", "directional", "point", "spot", "hemisphere", "environment", "rect", "shadows")
RECT_LTC_LABEL = ("Babylon's RectAreaLight shader with Heitz's tables (Babylon's own areaLightsLTC.bin is not "
                  "obtainable offline)")
CDF_SIZES = (32, 64, 128, 256, 512)
CDF_VARIANTS = ("shipped", "pre16247")

ENGINE = BrowserEngine(
    name="babylon", product="Babylon.js", precision="float", supports=SUPPORTS,
    shadow_types=("pcf", "pcss", "esm", "blur_esm"),
    defects={
        "furnace": "white dielectric sphere not energy-conserving in the white furnace",
        "probe_lambert": "its diffuse IBL of the probe is ≈ 8 % brighter than the probe's exact irradiance",
        "probe_material.mix": "its white sphere at metalness 0.5 under the probe is darker than glTF's mix of its own "
                              "metalness-0 and metalness-1 images (up to −13 % at roughness 1): energy lost at "
                              "intermediate metalness, the defect three.js fixed in PR 32190",
        "furnace_material": "white spheres at metalness 0.5 not energy-conserving in the white furnace (−14 % at "
                            "roughness 1: energy lost at intermediate metalness, three PR 32190)",
        "rect_plane": LTC_CLIPPED_SPHERE + " (Babylon's V points at the camera's position even under an "
                                           "orthographic camera, so the plane is lit)",
        "rect_sphere": LTC_CLIPPED_SPHERE,
        "shadows.pcss.umbra": "PCSS lets light into the umbra: its shader mixes the filtered shadow towards 1 by the "
                              "blocker–receiver depth gap (computeShadowWithPCSS: mix(shadow, 1, depthMetric − "
                              "avgBlockerDepth))"},
    notes={"rect": RECT_LTC_LABEL},
    facts={"probe_lambert.corrected_by": "three", "rect_units": "Babylon light.js _getPhotometricScale",
           "shadows.pcss.penumbra": "wider"},
    **PAGE)

VARIANTS = (
    BrowserEngine(name="babylon_lambert", product="Babylon.js", precision="float", supports=SUPPORTS,
                  variant_of="babylon", options={"diffuseModel": 2}, **PAGE),
    *(BrowserEngine(name=f"babylon_cdf{n}_{v}", product="Babylon.js", precision="float", supports=("environment",),
                    variant_of="babylon",
                    options={"diffuseModel": 2, "irradiance": "cdf", "cubeSize": n, "supersample": v}, **PAGE)
      for n in CDF_SIZES for v in CDF_VARIANTS))

__all__ = ["ENGINE", "VARIANTS", "RECT_LTC_LABEL"]

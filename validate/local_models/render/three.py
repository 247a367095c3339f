"""``three``: three.js 0.187 — MeshPhysicalMaterial, PMREMGenerator, a FloatType target (``three.html`` +
``three_render.mjs``, shadows ``three_shadows.mjs``), hosted in the run's Chromium (:mod:`.hosted`).

Known differences, each stated with its source (the renders claims keep them as regressions):

* spot (``spot.khr_falloff``): three.js 0.187 lights_pars_begin.glsl getSpotAttenuation = smoothstep(coneCos,
  penumbraCos, angleCos), not KHR_lights_punctual's reference falloff; it is judged against the smoothstep profile
  (``facts["spot_reference"]``).
* rectangular area light (three.js r187 RectAreaLight, lights_physical_pars_fragment.glsl): on the plane seen along
  its normal (V = N: the orthographic camera over the plane) LTC_Evaluate's frame T1 = normalize(V − N(V·N)) =
  normalize(0) and the light contributes 0 (measured: every pixel 0; the corrected behaviour is the truth itself);
  on the sphere the clipped-sphere form factor (:data:`.hosted.LTC_CLIPPED_SPHERE`). Its unit: three issue 19214
  (RectAreaLight.intensity is luminance; .power = π·A·intensity).
* VSM shadows (``shadows.vsm.lit``), measured (FULL, 64², SwiftShader): three 0.187's VSM darkens whole columns of
  the fully lit plane far from any shadow (directional: 3 columns, s ≥ 0.956, 95.7 % of the lit pixels accepted;
  spot: 2 columns, s ≥ 0.892, 96.9 %; QUICK, 32²: directional 0 columns, 100 %; spot 2 columns, 93.9 %).
  Deterministic (the same pixels in the same page, after the other types, and in a fresh browser); the runs differ by
  resolution only. Cause (docs/experiments/renders.md, "three.js VSM columns"): three's VSM renders every receiving
  mesh into its shadow map (WebGLShadowMap.renderObject: castShadow || (receiveShadow && VSM)), so the plane
  self-shadows at bias 0 against its own moments, stored as RG16F: where the half-float mean rounds below the
  fragment's depth, Chebyshev's bound with the light-bleeding remap (p − 0.3)/0.65 darkens it. Switched off one at a
  time, each removes every dark pixel of both scenes (64² and 32²): the receiver kept out of the map, RG32F moments,
  or bias −2e-4 (< one half-float ulp at depth ½).

Variant ``three_probe``: three.js with a hemisphere light given as a LightProbe whose SH is built as three's
HemisphereLightProbe built it (removed from three; three issue 26668) instead of a HemisphereLight; rendered beside
``three`` on the hemisphere scenes.
"""

from __future__ import annotations

from .hosted import LTC_CLIPPED_SPHERE, BrowserEngine

PAGE = dict(page="three.html", entry="renderThree", package="three",
            scripts=("three_render.mjs", "three_shadows.mjs", "three_target.mjs"))
SUPPORTS = ("furnace", "directional", "point", "spot", "hemisphere", "environment", "rect", "shadows")

ENGINE = BrowserEngine(
    name="three", product="three.js", precision="float", supports=SUPPORTS,
    shadow_types=("basic", "pcf", "pcfsoft", "vsm"),
    defects={
        "spot.khr_falloff": "spot penumbra is smoothstep in cos θ, not KHR_lights_punctual's reference "
                            "clamp((cos θ − cos θ_o)/(cos θ_i − cos θ_o))²",
        "rect_plane": "a surface seen along its normal (V = N) receives nothing from a RectAreaLight (LTC frame "
                      "T1 = normalize(V − N(V·N)) = normalize(0))",
        "rect_sphere": LTC_CLIPPED_SPHERE,
        "shadows.vsm.lit": "VSM darkens full-height columns of the fully lit plane far from any shadow (s down to "
                           "0.89): it renders the receiver into its map (receiveShadow under VSM) and the plane, at "
                           "bias 0, self-shadows where its half-float mean depth rounds below the fragment's"},
    facts={"spot_reference": "smoothstep", "rect_plane.corrected_by": "truth",
           "rect_units": "three.js RectAreaLight: intensity is luminance (nits), power = π·A·intensity"},
    **PAGE)

VARIANTS = (BrowserEngine(name="three_probe", product="three.js", precision="float", supports=("hemisphere",),
                          variant_of="three", with_kinds=("hemisphere",), options={"hemisphereProbe": True},
                          **PAGE),)

__all__ = ["ENGINE", "VARIANTS"]

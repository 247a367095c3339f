"""``filament``: Filament 1.53.4 (npm, WebAssembly) — a glTF binary of the geometry through gltfio's ubershader, its
LightManager lights (``filament.html`` + ``filament_render.mjs``, shadows ``filament_shadows.mjs``), hosted in the
run's Chromium (:mod:`.hosted`).

Punctual lights only: the package ships no IBL prefilter (cmgen), no area lights, and its JS Renderer has no
``readPixels``; the canvas (RGBA8, post-processing off: linear, no OETF) is read with WebGL2's own ``gl.readPixels``.
The 8-bit readback is decoded as radiance = q/(255·e) (e = the exposure the page picked) and carries its
quantisation as a per-pixel standard uncertainty ``EngineRender.stderr`` = 1/(255·√12·e) (±½ LSB uniform, rounding
to nearest: OpenGL ES 3.0 §2.1.6.1) — precision ``unorm8``.

Spot: Filament 1.53 light_punctual.fs getAngleAttenuation: saturate(cd·scale + offset)², KHR's reference — but with
cos θ_i, cos θ_o from its fast::cos (FLightManager::setSpotLightCone; 20°/30° shade as 19.94°/29.93°): its penumbra
is ≈ 4 % darker (tests/experiments/test_render_filament.py), inside the 0.25 %-of-peak budget at 64² and 32².

Scenes lit by the furnace, a hemisphere or the probe are not rendered (``lacks``): the glTF material scenes are lit
by the furnace / the probe only — Filament was rendered there and failed each with "black image" after its exposure
search (no IBL), 12 page calls of waste.

Known defect (``shadows.pcf.shadow_spot.umbra``), measured (FULL, 64²): Filament 1.53.4 PCF's spot lights 100 % of
the umbra, mean shadow factor 100.02 ± 0.01 % (no shadow drawn; its directional umbra: 0 %); its PCF penumbra is
narrower than the path tracer's (0.19× directional).
"""

from __future__ import annotations

from .hosted import BrowserEngine

NO_IBL = ("Filament 1.53.4's npm package has no IBL prefilter (cmgen/libibl are not in the WebAssembly build): "
          "IndirectLight.Builder takes only precomputed irradianceSh and a prefiltered reflections cubemap, so an "
          "environment cannot go through Filament's own pipeline")
# the report's paragraph on what Filament renders (facts["report"])
REPORT_NOTE = ("Filament (npm 1.53.4) renders the punctual lights (c) only: a glTF binary of the geometry through "
               "gltfio's ubershader and its LightManager lights (Φ = 4π·cd point, π·cd spot), post-processing off, "
               "the 8-bit canvas read with WebGL2's gl.readPixels (its JS Renderer has no readPixels). The "
               "exposure e is picked from Filament's own frames so the image fills the 8-bit range; the "
               "quantisation, ±½ LSB uniform (σ = 1/(255·√12·e) in radiance), is added in quadrature to Mitsuba's "
               "standard error in the z-test. Not rendered: the furnace, probe and hemisphere (the package has no "
               "IBL prefilter — cmgen/libibl — so an environment cannot go through Filament's own pipeline) and "
               "the rectangular light (Filament has no area lights). Its spot penumbra is ≈ 4 % darker than KHR's "
               "reference: FLightManager::setSpotLightCone takes the cone's cosines from fast::cos (20°/30° shade "
               "as 19.94°/29.93°), inside the budget.")

ENGINE = BrowserEngine(
    name="filament", product="Filament", precision="unorm8", supports=("directional", "point", "spot", "shadows"),
    shadow_types=("pcf",),
    lacks={"rect": "Filament has no area lights (LightManager types: SUN, DIRECTIONAL, POINT, FOCUSED_SPOT, SPOT)",
           "furnace": NO_IBL, "hemisphere": NO_IBL, "environment": NO_IBL},
    defects={"shadows.pcf.shadow_spot.umbra": "its spot light casts no shadow from a caster outside the camera's view "
                                              "(the whole umbra lit; with the view widened to take the box in, it "
                                              "casts: filament_shadows.mjs)"},
    facts={"report": REPORT_NOTE},
    page="filament.html", entry="renderFilament", package="filament",
    scripts=("filament_render.mjs", "filament_shadows.mjs", "filament_frames.mjs"))

__all__ = ["ENGINE", "NO_IBL"]

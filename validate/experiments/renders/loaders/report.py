"""(g) Loaders: the table loader path vs hand-built path per engine × scene, the findings with their causes, data."""

from __future__ import annotations

from typing import Any

from ...base import Section, Table
from .compute import LoaderMeasurements, LoaderScene, agree

NOTE = ("(g) Loaders. The scenes exported as files (python -m validate scenes export: manifest.json, one .glb per "
        "scene, the environment as EXR) are rendered by the engines through their own loaders — three.js GLTFLoader "
        "+ EXRLoader (scene.environment turned by environmentRotation so the image centre faces +z), Filament gltfio "
        "(its lights and camera; the page only picks the exposure of the 8-bit canvas and corrects gltfio's "
        "orthographic projection) — written as <scene>.exr and judged by validate judge, the road an outside team "
        "takes. Each judgement is set beside the hand-built path's (the engine page fed the suite's own scene JSON) "
        "for the same scene and reference. 'agree': the same verdict and fractions accepted within 2σ (binomial, "
        "pooled). max |Δ|: the largest difference between the two engines' images over the judged pixels, as a share "
        "of the truth's peak.")

# Causes found by experiment (docs/experiments/renders.md, "(g) Loaders"): what makes a loader path differ
CAUSES = {
    ("filament_gltf", "orthographic"): (
        "gltfio 1.53.4 reads an orthographic camera's xmag/ymag as the full width/height: its projection scaled x by "
        "2/xmag = 1.818 for xmag = 1.1 where glTF 2.0 §3.10.3 says 1/xmag = 0.909, so every orthographic scene came "
        "out at twice the magnification (lambert_directional {raw} accepted with gltfio's projection); the page sets "
        "glTF's projection from the file's camera, after which the loader path agrees with the hand-built one"),
    ("three_gltf", "spot_plane"): (
        "three's SpotLight penumbra is a smoothstep between the cones where KHR_lights_punctual specifies a quadratic "
        "falloff; GLTFLoader maps penumbra = 1 − inner/outer exactly as the hand-built page does, so both paths fail "
        "KHR's truth alike (the renders experiment's known difference, its 'smoothstep' reference)"),
}


def _accepted_text(j: Any) -> str:
    return "" if j is None else f"{100 * j.fraction_accepted:.2f}"


def _pass_word(j: Any, passed: bool | None = None) -> str:
    if j is None:
        return ""
    from ....metrics.pixel_z import MIN_ACCEPTED

    return "pass" if (passed if passed is not None else j.fraction_accepted >= MIN_ACCEPTED) else "FAIL"


def row(ls: LoaderScene) -> list[Any]:
    a = agree(ls)
    return [ls.engine, ls.scene, ls.judged_by, _accepted_text(ls.loader), _pass_word(ls.loader, ls.loader_passed),
            _accepted_text(ls.hand_judgement), _pass_word(ls.hand_judgement),
            "" if a is None else ("yes" if a else "NO"),
            "" if ls.max_diff_of_peak != ls.max_diff_of_peak else f"{100 * ls.max_diff_of_peak:.3f}"]


def loader_sections(pm: LoaderMeasurements, ctx: Any = None) -> list[Section]:
    if not pm.scenes and not pm.skipped:
        return []
    t = Table(["engine", "scene", "reference", "loader accepted (%)", "loader passes?", "hand-built accepted (%)",
               "hand-built passes?", "agree?", "max |Δ| of peak (%)"], [row(ls) for ls in pm.scenes],
              "each engine through its own glTF loader (export → engine → judge) beside the hand-built path")
    paras = [NOTE] + [f"{e}: not run — {why}" for e, why in pm.skipped.items()]
    paras += [f"{e} {r['version']}: {len(r['frame_ms'])} scenes in {r['wall_s']:.1f} s (page {r['startup_s']:.1f} s)"
              + (f"; skipped: {', '.join(sorted(r['skipped']))} ({next(iter(r['skipped'].values()))})"
                 if r["skipped"] else "") for e, r in pm.renders.items()]
    return [Section("(g) Loaders: the engines' own glTF loaders, export → engine → judge", paras, tables=[t])]


def loader_findings(pm: LoaderMeasurements) -> list[str]:
    out = []
    for eng in sorted({ls.engine for ls in pm.scenes}):
        mine = [ls for ls in pm.scenes if ls.engine == eng]
        paired = [ls for ls in mine if agree(ls) is not None]
        same = [ls for ls in paired if agree(ls)]
        out.append(f"renders (g) loaders: {eng} through its own loader agrees with the hand-built path on "
                   f"{len(same)}/{len(paired)} scenes ({', '.join(ls.scene for ls in same) or 'none'})"
                   + (f"; differs on {', '.join(ls.scene for ls in paired if not agree(ls))}"
                      if len(same) < len(paired) else "")
                   + f"; {sum(ls.loader_passed for ls in mine)}/{len(mine)} scenes pass the judge")
    raw = next((v for ls in pm.scenes if ls.engine == "filament_gltf" for k, v in ls.power.items()
                if "orthographic" in k), None)
    if raw is not None:
        out.append("renders (g) loaders: " + CAUSES[("filament_gltf", "orthographic")].format(raw=f"{100 * raw:.1f} %"))
    if any(ls.engine == "three_gltf" and ls.scene == "spot_plane" for ls in pm.scenes):
        out.append("renders (g) loaders: " + CAUSES[("three_gltf", "spot_plane")])
    for ls in pm.scenes:
        if ls.loader is not None and not ls.loader_passed and ls.scene not in ("spot_plane",):
            texts = "; ".join(d["text"] for d in ls.diagnoses.values() if isinstance(d, dict) and "text" in d)
            out.append(f"renders (g) loaders: {ls.engine} fails {ls.scene} ({100 * ls.loader.fraction_accepted:.2f} % "
                       f"accepted vs {ls.judged_by})" + (f": {texts}" if texts else ""))
    return out


def data(pm: LoaderMeasurements) -> dict[str, Any]:
    scenes: dict[str, Any] = {}
    for ls in pm.scenes:
        scenes.setdefault(ls.scene, {})[ls.engine] = {
            "judged_by": ls.judged_by, "passed": ls.loader_passed, "hand_built_engine": ls.hand,
            # under "judgements" (keyed by the reference, as the parent's): ``validate compare`` reads it there
            "judgements": {} if ls.loader is None else {ls.judged_by: ls.loader.to_json()},
            "hand_built": None if ls.hand_judgement is None else ls.hand_judgement.to_json(),
            "agree": agree(ls), "power": ls.power, "diagnoses": ls.diagnoses}
    return {"loaders": {"scenes": scenes, "skipped": pm.skipped, "missing": pm.missing,
                        "renders": {e: {k: v for k, v in r.items() if k != "info"} for e, r in pm.renders.items()},
                        "export_s": round(pm.export_s, 3), "judge_s": round(pm.judge_s, 3), "quick": pm.quick}}


__all__ = ["loader_sections", "loader_findings", "data", "row"]

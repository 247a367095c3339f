"""The hosted engines through their own glTF loaders: one page per engine renders an exported scene file.

``python -m validate scenes export`` writes ``manifest.json``, one ``.glb`` per scene and the environment files
(:mod:`validate.scenes.manifest`). A :class:`GltfPageEngine` renders the named scenes of such a folder the way the
engine's users load a glTF: the page (``<engine>_gltf.html`` + ``.mjs``) fetches the ``.glb`` and the environment
file over the run's loopback server (:func:`validate.gl.browser_page.publish`: the bytes, served under a name that
carries their digest) and hands them to the engine's own loader — three.js ``GLTFLoader`` + ``EXRLoader``,
Babylon.js ``@babylonjs/loaders`` (``SceneLoader``) + ``EXRCubeTexture``, Filament ``gltfio`` — with the glTF's
own camera and lights, tone mapping and exposure off, a float render target (Filament: its 8-bit canvas) and
writes ``<scene>.exr`` (float32 R, G, B, A = coverage, row 0 = top) into the output folder: what an outside team
hands to ``python -m validate judge``.

An 8-bit readback (Filament) is decoded as radiance q/(255·e) (e = the page's exposure) and its quantisation step
1/(255·e) is written into the EXR header as ``validate_quantisation_step`` (radiance per step): the judge adds
σ = step/√12 (±½ LSB uniform) per value, as the renders experiment does (:func:`.decode_unorm8`).
"""

from __future__ import annotations

import hashlib
import json
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import ValidateError
from ...setup import paths
from .engine import Engine, FolderRender, Unavailable

QUANTISATION_ATTRIBUTE = "validate_quantisation_step"  # EXR header: radiance per readback step (8-bit canvases)


def write_exr_rgba(path: Path, rgba: np.ndarray, step: float | None = None) -> None:
    """(H, W, 4) float32 radiance + coverage as a float OpenEXR (ZIP); ``step``: the readback's quantisation step
    in radiance, written as :data:`QUANTISATION_ATTRIBUTE`."""
    import OpenEXR

    chans = {c: np.ascontiguousarray(rgba[..., k], np.float32) for k, c in enumerate("RGBA")}
    header: dict[str, Any] = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    if step is not None:
        header[QUANTISATION_ATTRIBUTE] = float(step)
    tmp = path.with_name(path.name + ".part.exr")
    with OpenEXR.File(header, chans) as f:
        f.write(str(tmp))
    tmp.replace(path)


def scene_features(entry: dict[str, Any]) -> set[str]:
    """What a manifest entry needs of an engine: its light types, ``environment``, ``perspective``."""
    out = {lt["type"] for lt in entry.get("lights", [])}
    if entry.get("environment"):
        out.add("environment")
    if entry["camera"]["type"] == "perspective":
        out.add("perspective")
    return out


def _publish(path: Path) -> str:
    """Serve the file's bytes under a name carrying their digest (a changed file is a new URL)."""
    from ...gl import browser_page

    data = path.read_bytes()
    return browser_page.publish(f"{hashlib.sha256(data).hexdigest()[:16]}-{path.name}", data)


@dataclass(frozen=True)
class GltfPageEngine(Engine):
    """An engine whose page loads exported scene files with the engine's own glTF loader (module docstring)."""

    page: str = ""  # <engine>_gltf.html of this folder
    packages: tuple[str, ...] = ()  # the npm packages it loads; the first one's version is the engine's
    options: dict[str, Any] = field(default_factory=dict)  # what the page reads besides the scene
    skip_reasons: dict[str, str] = field(default_factory=dict)  # scene feature the engine lacks → why

    def version(self) -> str | None:
        return paths.installed_version(self.packages[0])

    def unavailable(self) -> Unavailable | None:
        pinned = paths.pinned_versions()
        absent = [p for p in self.packages if paths.installed_version(p) is None
                  or (p in pinned and paths.installed_version(p) != pinned[p])]
        if absent:
            return Unavailable("npm engines", f"{', '.join(absent)} not installed (pinned) in "
                                              f"{paths.node_modules()}", "python -m validate setup --engines")
        from ...gl import runtime

        ok, why = runtime.available("webgl2")
        if not ok:
            return Unavailable("Chromium (WebGL2)", why.splitlines()[0][:200] if why else "unavailable",
                               "python -m validate setup --system")
        return None

    def skip_reason(self, entry: dict[str, Any]) -> str | None:
        """Why the engine does not render this scene (a feature it lacks), or None."""
        lacking = sorted(f for f in scene_features(entry) if f not in self.supports)
        return "; ".join(self.skip_reasons.get(f, f"{self.product} does not render {f}") for f in lacking) or None

    def render_folder(self, scenes_dir: Path, names: Sequence[str], out_dir: Path) -> FolderRender:
        from ...gl import browser_page

        t_start = time.perf_counter()
        scenes_dir, out_dir = Path(scenes_dir), Path(out_dir)
        doc = json.loads((scenes_dir / "manifest.json").read_text(encoding="utf-8"))
        entries = {e["name"]: e for e in doc["scenes"] + doc.get("gltf_scenes", [])}
        unknown = [n for n in names if n not in entries]
        if unknown:
            raise ValidateError(f"{scenes_dir / 'manifest.json'}: no scene {', '.join(unknown)}")
        out_dir.mkdir(parents=True, exist_ok=True)
        res = FolderRender(self.version() or "", {})
        t0 = time.perf_counter()
        browser_page.open_page(self.page)
        res.startup_s = time.perf_counter() - t0
        for name in names:
            e = entries[name]
            why = self.skip_reason(e)
            if why:
                res.skipped[name] = why
                continue
            w, h = e["image"]["width"], e["image"]["height"]
            arg = {"glb": _publish(scenes_dir / e["glb"]), "image": {"width": w, "height": h},
                   "environment": _publish(scenes_dir / e["environment"]["file"]) if e["environment"] else None,
                   "options": self.options, "name": name, "camera": e["camera"]}
            r = browser_page.call(self.page, "renderGltf", arg)
            if r.get("encoding") == "unorm8_linear":  # an 8-bit canvas: q = round(255·e·L), alpha 255 = covered
                import base64

                q = np.frombuffer(base64.b64decode(r["data"]), np.uint8).reshape(h, w, 4).astype(np.float32)
                img, step = q / 255.0, 1.0 / (255.0 * float(r["exposure"]))
                img[..., :3] /= float(r["exposure"])
            else:
                img, step = browser_page.decode_f32(r["data"], (h, w, 4)), None
            img = img[::-1].copy()  # readPixels row 0 = bottom
            img[..., 3] = np.clip(img[..., 3], 0.0, 1.0)
            img[..., :3] = np.maximum(img[..., :3], 0.0)
            path = out_dir / e["image"]["expected"]
            write_exr_rgba(path, img, step)
            res.images[name] = path
            res.frame_ms[name] = float(r.get("frame_ms", np.nan))
            res.info[name] = dict(r.get("info") or {})
            if r.get("version"):
                res.version = str(r["version"])
        res.wall_s = time.perf_counter() - t_start
        return res


__all__ = ["GltfPageEngine", "QUANTISATION_ATTRIBUTE", "scene_features", "write_exr_rgba"]

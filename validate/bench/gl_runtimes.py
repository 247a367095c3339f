"""The GL runtimes in ``python -m validate bench``: start-up cost and per-receiver cost, side by side.

* Start-up (one fresh child process per runtime kind, so nothing is warm): seconds to import the
  bindings, to create the context (llvmpipe: EGL display + 4.5 context; webgl2: Chromium + a WebGL2
  page), and to compile the first program.
* Per receiver (this process, runtime already started, program compiled): each built-in GLSL
  transcription against its Python original on the same N receivers, run alternately
  (:func:`validate.bench.timing.best_pair`), best of 5; the ratio GLSL / Python is the figure. The GLSL time
  includes uploading the inputs as float textures, the draw and the float32 read-back.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from typing import Any

import numpy as np

from .timing import best_pair

N_RECEIVERS = 100_000
PAIRS = (  # (family, GLSL technique, its Python original)
    ("brdf", "glsl_blinn_phong_normalized", "blinn_phong_normalized"),
    ("light", "glsl_point_inverse_square", "point_inverse_square"),
    ("irradiance", "glsl_sh9", "sh9"),
    ("shadow", "glsl_shadow_hard", "hard"),
    ("arealight", "glsl_inverse_square", "inverse_square"),
    ("specular", "glsl_split_sum_ggx", "split_sum_ggx"),
    ("specular_arealight", "glsl_representative_point", "representative_point"),
    ("uberlight", "glsl_uberlight_inverse_square", "uberlight_inverse_square"),
)


def startup_child(kind: str) -> dict[str, Any]:
    """Cold start of one runtime in this (fresh) process: import, context, first compile (seconds)."""
    t0 = time.perf_counter()
    from ..gl import egl, runtime  # noqa: PLC0415

    if kind == "webgl2":
        from ..gl import webgl  # noqa: F401, PLC0415
    else:
        import moderngl  # noqa: F401, PLC0415
        from OpenGL import EGL  # noqa: F401, PLC0415
    t1 = time.perf_counter()
    rt = runtime.get(kind)
    t2 = time.perf_counter()
    frag = ("#version 450 core\nout vec4 o;\nvoid main() { o = vec4(1.0); }\n" if kind != "webgl2" else
            "#version 300 es\nprecision highp float;\nout vec4 o;\nvoid main() { o = vec4(1.0); }\n")
    if kind == "webgl2":
        rt.compile("#version 300 es\nin vec2 a_pos;\nvoid main() { gl_Position = vec4(a_pos, 0.0, 1.0); }\n", frag)
    else:
        vert = egl.FULLSCREEN_VERTEX_CORE if kind == "llvmpipe" else egl.FULLSCREEN_VERTEX_COMPAT
        compat = "#version 120\nvoid main() { gl_FragColor = vec4(1.0); }\n"
        with rt:
            rt.program(vert, frag if kind == "llvmpipe" else compat)
    t3 = time.perf_counter()
    runtime.close_all()
    return {"kind": kind, "import_s": t1 - t0, "start_s": t2 - t1, "first_compile_s": t3 - t2,
            "renderer": rt.info.get("GL_RENDERER", ""), "version": rt.info.get("GL_VERSION", "")}


def startup_records(kinds: tuple[str, ...] = ("llvmpipe", "llvmpipe-compat", "webgl2")) -> list[dict[str, Any]]:
    out = []
    for kind in kinds:
        proc = subprocess.run([sys.executable, "-m", "validate.bench.gl_runtimes", kind], capture_output=True,
                              text=True, timeout=300)
        if proc.returncode != 0:
            last = (proc.stderr.strip().splitlines() or [f"exit status {proc.returncode}"])[-1]
            out.append({"kind": kind, "error": last[:200]})
        else:
            out.append(json.loads(proc.stdout.strip().splitlines()[-1]))
    return out


def _inputs(fam: str, n: int) -> tuple[Any, ...]:
    rng = np.random.default_rng(11)
    unit = lambda a: a / np.linalg.norm(a, axis=1, keepdims=True)  # noqa: E731
    normals = unit(rng.standard_normal((n, 3)))
    if fam == "brdf":
        return ({"albedo": [0.8, 0.5, 0.2], "ks": 0.3, "exponent": 40.0}, normals,
                unit(rng.standard_normal((n, 3))), unit(rng.standard_normal((n, 3))))
    if fam == "light":
        return ({"type": "point", "position": np.array([0.3, 2.0, 0.1]), "intensity": 5.0},
                rng.uniform(-1.0, 1.0, (n, 3)), normals)
    if fam == "shadow":
        return _shadow_inputs(rng, n)
    if fam == "arealight":
        pts = np.c_[rng.uniform(-2, 2, n), rng.uniform(-2, 0.5, n), rng.uniform(-2, 2, n)]
        return ({"shape": "disc", "center": np.array([0.1, 1.5, 0.2]), "normal": np.array([0.0, -1.0, 0.0]),
                 "radius": 0.3, "radiance": 4.0}, pts, normals)
    if fam == "specular_arealight":  # the sphere above a ground patch, views toward the upper hemisphere
        pts = np.c_[rng.uniform(-2, 2, n), np.zeros(n), rng.uniform(-2, 2, n)]
        return ({"shape": "sphere", "center": np.array([0.1, 2.5, 0.2]), "radius": 0.4, "radiance": 3.0},
                {"alpha": 0.3, "f0": 1.0}, pts, np.tile([0.0, 1.0, 0.0], (n, 1)),
                unit(np.abs(rng.standard_normal((n, 3)))))
    if fam == "uberlight":  # a downward überlight over a ground patch, soft edges, no distance shaping
        from ..local_models.uberlight.common import NO_DISTANCE_SHAPING  # noqa: PLC0415

        light = {"position": np.array([0.0, 2.0, 0.0]), "axes": np.array([[1.0, 0, 0], [0, 0, 1.0], [0, -1.0, 0]]),
                 "intensity": 50.0, "width": 0.5, "height": 0.3, "width_edge": 0.1, "height_edge": 0.05,
                 "roundness": 1.0, **NO_DISTANCE_SHAPING}
        pts = np.c_[rng.uniform(-2, 2, n), np.zeros(n), rng.uniform(-2, 2, n)]
        return (light, pts, np.tile([0.0, 1.0, 0.0], (n, 1)), unit(np.abs(rng.standard_normal((n, 3)))),
                {"albedo": 0.5, "ks": 0.3, "specular_exponent": 20.0})
    if fam == "specular":  # the maps are built on the first of the 5 repeats (cached): the lookups are timed
        views = unit(rng.standard_normal((n, 3)))
        views = np.where(np.sum(views * normals, axis=1, keepdims=True) < 0, -views, views)
        return (rng.uniform(0.0, 2.0, (32, 64, 3)), {"model": "ggx", "alpha": 0.3}, normals, views)
    return (rng.uniform(0.0, 2.0, (128, 256, 3)).astype(np.float32), normals)


def _shadow_inputs(rng: np.random.Generator, n: int) -> tuple[Any, ...]:
    """A synthetic 512² D24 map over a ground plane under a disc light (no ray casting: the lookup is timed)."""
    from ..backend import float_type  # noqa: PLC0415
    from ..local_models.shadow import shadow_map as smod  # noqa: PLC0415
    from ..scenes.shadow_scenes import DiscLight  # noqa: PLC0415

    F, r = float_type(), 512
    light = DiscLight((0.0, 3.0, 0.0), (0.0, 0.0, 0.0), 0.5, 10.0)
    pts = np.c_[rng.uniform(-2, 2, n), np.zeros(n), rng.uniform(-2, 2, n)]
    view = smod.fit_light_view(light, pts)
    view.near, view.far = 0.5, 3.5
    depth = smod.quantise_depth(F(rng.uniform(0.3, 1.0, r * r).astype(np.float32)))
    sm = smod.ShadowMap(view, r, depth, F(np.full(r * r, 1e-5, dtype=np.float32)))
    return (sm, light, pts, np.tile([0.0, 1.0, 0.0], (n, 1)))


def per_receiver_rows(n: int = N_RECEIVERS) -> list[dict[str, Any]]:
    """GLSL vs Python per receiver for each built-in transcription (module docstring)."""
    from ..local_models import family  # noqa: PLC0415

    rows = []
    for fam_name, glsl, py in PAIRS:
        fam = family(fam_name)
        if glsl not in fam:
            rows.append({"family": fam_name, "glsl": glsl, "python": py, "skipped": "GLSL technique not registered"})
            continue
        args = _inputs(fam_name, n)
        tg, tp = best_pair(lambda a=args, f=fam, g=glsl: f.call(g, *a), lambda a=args, f=fam, p=py: f.call(p, *a),
                            repeats=5)
        rows.append(_row(fam_name, glsl, py, n, tg, tp))
    rows.append(_webgl_row(n))
    return rows


def _row(fam: str, glsl: str, py: str, n: int, tg: float, tp: float) -> dict[str, Any]:
    return {"family": fam, "glsl": glsl, "python": py, "receivers": n, "glsl_s": tg, "python_s": tp,
            "glsl_ns_per_receiver": tg / n * 1e9, "python_ns_per_receiver": tp / n * 1e9, "ratio": tg / tp}


def _webgl_row(n: int) -> dict[str, Any]:
    """The built-in sh9.glsl on Chromium WebGL2 vs the Python sh9 (skipped with the reason without chromium)."""
    from ..errors import ValidateError  # noqa: PLC0415
    from ..local_models import family  # noqa: PLC0415
    from ..local_models import glsl_technique as gt  # noqa: PLC0415

    try:
        tech = gt.technique_from_file(gt.BUILTIN_DIR / "irradiance" / "sh9.glsl", "irradiance", runtime="webgl2",
                                      name="glsl_sh9@webgl2")
    except ValidateError as exc:
        return {"family": "irradiance", "glsl": "glsl_sh9@webgl2", "python": "sh9", "skipped": str(exc)}
    fam, args = family("irradiance"), _inputs("irradiance", n)
    tg, tp = best_pair(lambda: fam.call(tech, *args), lambda: fam.call("sh9", *args), repeats=5)
    return _row("irradiance", "glsl_sh9@webgl2", "sh9", n, tg, tp)


def tables(starts: list[dict[str, Any]], rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    st = [[s["kind"], round(s["import_s"] * 1e3, 1), round(s["start_s"] * 1e3, 1), round(s["first_compile_s"] * 1e3, 1),
           f"{s['renderer']}, {s['version']}"] if "start_s" in s else [s["kind"], None, None, None, s.get("error")]
          for s in starts]
    pr = [[f"{r['family']}: {r['glsl']} vs {r['python']}", round(r["glsl_ns_per_receiver"], 1),
           round(r["python_ns_per_receiver"], 1), round(r["ratio"], 2)] if "ratio" in r
          else [f"{r['family']}: {r['glsl']}", None, None, r["skipped"]] for r in rows]
    return [
        {"caption": "GL runtimes: cold start in a fresh process (ms)",
         "headers": ["runtime", "import (ms)", "context (ms)", "first compile (ms)", "renderer"], "rows": st},
        {"caption": f"GLSL technique vs its Python transcription, per receiver ({N_RECEIVERS} receivers; ns; "
                    "best of 5, alternating; GLSL includes upload, draw and read-back)",
         "headers": ["technique", "GLSL per receiver (ns)", "Python per receiver (ns)", "GLSL / Python (×)"],
         "rows": pr},
    ]


if __name__ == "__main__":  # child process: python -m validate.bench.gl_runtimes KIND
    print(json.dumps(startup_child(sys.argv[1])))

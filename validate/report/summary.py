"""The picture each experiment page opens with, and its three-line verdict, read from results.json alone.

One small function per experiment name (:data:`SUMMARIES`) turns that experiment's JSON entry into a
plot description — numbers only, drawn by :mod:`.summary_plots`:

* :class:`Matrix` — technique × input (environment, sky, material, luminaire), each cell the headline
  error ± its uncertainty, coloured by the error (sh9, engines, hemisphere, ibl, uberlight);
* :class:`Bars` — one bar per technique on its own input, ± σ, coloured by the input (ibl);
* :class:`Curves` — headline error against the swept parameter, one line per technique with a ±1σ
  band where the JSON carries σ (lights: distance; arealights: light size; brdfs, multiscatter:
  roughness; shadows: map size).

An experiment without a function of its own (a plug-in experiment, or one renamed) gets
:func:`generic`: a matrix built from ``techniques.<t>.metrics``, whatever their nesting. A function
that finds its data missing or malformed returns None and the generic one is tried; a page whose
JSON has no technique metrics at all has no summary figure.

Every headline is an error (lower is better): the verdict ranks techniques by their worst value over
the inputs or the sweep (:meth:`Matrix.ranking`, :meth:`Curves.ranking`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ..format import pm

Entry = Mapping[str, Any]
FIGURE_VERSION = 2  # part of a summary figure's file name: bump when the drawing changes
FONT_PT = 11.5  # every text of a summary figure (points): at FIG_DPI 100, 16 px on screen ≥ the pages' 15-px body
FIG_DPI = 100.0  # pixels per inch of the summary PNGs (validate.figures.plots.FIG_DPI)
FONT_PX = FONT_PT * FIG_DPI / 72.0  # the smallest text of a summary PNG shown at its own size, in pixels


@dataclass(frozen=True)
class Matrix:
    """rows × cols headline values (NaN = not measured) and their 1σ uncertainties (0 = exact)."""

    title: str
    metric: str  # what a cell holds, with its unit ("max flux-normalised error, % of Φ")
    rows: list[str]
    cols: list[str]
    values: list[list[float]]
    sigmas: list[list[float]]
    unit: str = "%"
    over: str = "inputs"  # what a row's worst value is taken over, for the verdict

    def ranking(self) -> list[tuple[str, float, float]]:
        """(row, worst value over the columns, its σ), best first; rows with no finite value left out."""
        out = []
        for name, vs, ss in zip(self.rows, self.values, self.sigmas, strict=True):
            finite = [(v, s) for v, s in zip(vs, ss, strict=True) if math.isfinite(v)]
            if finite:
                v, s = max(finite)
                out.append((name, v, s))
        return sorted(out, key=lambda r: r[1])


@dataclass(frozen=True)
class Curves:
    """Series of headline values against one swept parameter; ``bands`` holds ±1σ per point (or none)."""

    title: str
    metric: str
    xlabel: str
    x: list[float]
    series: dict[str, list[float]]
    bands: dict[str, list[float]] = field(default_factory=dict)
    unit: str = "%"
    logx: bool = False
    logy: bool = True
    hlines: dict[str, float] = field(default_factory=dict)

    def ranking(self) -> list[tuple[str, float, float]]:
        """(series, worst value over the sweep, its σ), best first."""
        out = []
        for name, ys in self.series.items():
            sig = self.bands.get(name) or [0.0] * len(ys)
            finite = [(y, s) for y, s in zip(ys, sig, strict=True) if math.isfinite(y)]
            if finite:
                y, s = max(finite)
                out.append((name, y, s))
        return sorted(out, key=lambda r: r[1])


@dataclass(frozen=True)
class Bars:
    """One headline value ± σ per (technique, input) pair, coloured by input: for sparse matrices, where
    each technique was measured on its own input (ibl: diffuse techniques on a Lambertian sphere,
    specular ones on their BSDF)."""

    title: str
    metric: str
    labels: list[str]
    groups: list[str]
    values: list[float]
    sigmas: list[float]
    unit: str = "%"
    over: str = "materials"

    def ranking(self) -> list[tuple[str, float, float]]:
        """(technique, worst value over the inputs it was measured on, its σ), best first."""
        worst: dict[str, tuple[float, float]] = {}
        for lab, v, s in zip(self.labels, self.values, self.sigmas, strict=True):
            if math.isfinite(v) and (lab not in worst or v > worst[lab][0]):
                worst[lab] = (v, s)
        return sorted(((lab, v, s) for lab, (v, s) in worst.items()), key=lambda r: r[1])


@dataclass(frozen=True)
class Spread:
    """Per technique (row), its values over every input (columns), one panel per statistic: a box per row (the
    spread over the inputs) with each input a dot, rows sorted by their median in the last panel; ``marked``
    inputs drawn apart (the paper's probes); ``hlines``: per panel, labelled reference levels; ``matrix``: the full
    technique × input matrix, drawn as a second figure further down the page."""

    title: str
    metric: str  # the x axis ("|ΔE|/Φ over the sphere's normals, %")
    rows: list[str]
    cols: list[str]
    panels: dict[str, list[list[float]]]  # panel title → rows × cols values (NaN = not measured)
    hlines: dict[str, dict[str, float]] = field(default_factory=dict)  # panel title → {label: level}
    marked: list[str] = field(default_factory=list)
    marked_label: str = ""
    unit: str = "%"
    over: str = "environments"
    matrix: Matrix | None = None

    def ranking(self) -> list[tuple[str, float, float]]:
        """(row, worst value of the last panel over the inputs, 0), best first."""
        last = list(self.panels.values())[-1]
        out = [(r, max(v for v in vs if math.isfinite(v)), 0.0) for r, vs in zip(self.rows, last, strict=True)
               if any(math.isfinite(v) for v in vs)]
        return sorted(out, key=lambda r: r[1])


@dataclass(frozen=True)
class Worst:
    """Per technique: its certificate (the largest error any non-negative lighting can cause) beside the worst
    error a search found, each ± σ (NaN: not computed), and the worst lighting found as a small equirect map
    (rows θ = 0 … π, columns φ = 0 … 2π, luminance relative to its largest texel; None: no search) with the
    certificate's worst light (a delta) at ``star`` = (φ/2π, θ/π)."""

    title: str
    metric: str
    rows: list[str]
    certificate: list[tuple[float, float]]
    search: list[tuple[float, float]]
    maps: list[list[list[float]] | None]
    stars: list[tuple[float, float] | None]
    unit: str = "%"
    over: str = "techniques (certificate)"

    def ranking(self) -> list[tuple[str, float, float]]:
        """(technique, certificate ± σ — the search's value where there is no certificate), best first."""
        out = []
        for r, c, f in zip(self.rows, self.certificate, self.search, strict=True):
            v, sg = c if math.isfinite(c[0]) else f
            if math.isfinite(v):
                out.append((r, v, sg if math.isfinite(sg) else 0.0))
        return sorted(out, key=lambda r: r[1])


@dataclass(frozen=True)
class Listings:
    """Per listing (row): its status (as printed / with an edit / not runnable), and its largest relative error
    against its float64 transcription and against Mitsuba, ± σ (NaN: not measured; ``why``: the reason shown
    instead)."""

    title: str
    metric: str
    rows: list[str]
    status: list[str]
    transcription: list[tuple[float, float]]
    mitsuba: list[tuple[float, float]]
    why: list[str]
    bound: float = 1e-5  # the transcription claim's bound
    unit: str = ""
    over: str = "listings"

    def ranking(self) -> list[tuple[str, float, float]]:
        return []

    def lines(self) -> list[str]:
        counts = {w: self.status.count(w) for w in dict.fromkeys(self.status)}
        return ["Listings: " + ", ".join(f"{n} {w}" for w, n in counts.items()) + f" ({len(self.rows)} catalogued)."]


@dataclass(frozen=True)
class Acceptance:
    """Engine (row) × scene (column): the fraction of pixels accepted against one reference (named per cell,
    ``refs``; the others in ``others``), NaN where the engine did not render the scene (``skipped`` says why);
    ``strips``: per scene, the report-relative path of its image strip (truth | engine | error), or ""."""

    title: str
    metric: str
    rows: list[str]
    cols: list[str]
    values: list[list[float]]
    refs: list[list[str]]
    others: list[list[str]]
    skipped: list[list[str]]
    strips: list[str]
    unit: str = "%"
    over: str = "scenes"

    def ranking(self) -> list[tuple[str, float, float]]:
        """(engine, its lowest fraction accepted over the scenes, 0), best (highest) first."""
        out = [(r, min(v for v in vs if math.isfinite(v)), 0.0) for r, vs in zip(self.rows, self.values, strict=True)
               if any(math.isfinite(v) for v in vs)]
        return sorted(out, key=lambda r: -r[1])


Summary = Matrix | Curves | Bars | Spread | Worst | Listings | Acceptance


def _f(x: Any) -> float:
    """A JSON number as float; None, text, NaN → NaN."""
    try:
        return float(x) if x is not None and not isinstance(x, bool) else math.nan
    except (TypeError, ValueError):
        return math.nan


def _ordered(keys: Iterable[str]) -> list[str]:
    seen: dict[str, None] = {}
    for k in keys:
        seen.setdefault(k, None)
    return list(seen)


def _matrix(title: str, metric: str, cells: Mapping[tuple[str, str], tuple[float, float]], over: str,
            unit: str = "%") -> Matrix | None:
    """A Matrix from {(row, col): (value, σ)}; None when no cell is finite."""
    if not any(math.isfinite(v) for v, _ in cells.values()):
        return None
    rows = _ordered(r for r, _ in cells)
    cols = _ordered(c for _, c in cells)
    values = [[cells.get((r, c), (math.nan, 0.0))[0] for c in cols] for r in rows]
    sigmas = [[cells.get((r, c), (math.nan, 0.0))[1] for c in cols] for r in rows]
    return Matrix(title, metric, rows, cols, values, sigmas, unit, over)


# ---------------------------------------------------------------------------------------------------
# One function per experiment
# ---------------------------------------------------------------------------------------------------

def _env_stat_cells(by_env: Mapping[str, Mapping[str, Any]], stat: str = "max",
                    metric: str = "flux_luminance") -> dict[tuple[str, str], tuple[float, float]]:
    """{(technique, env): (stat, σ)} from techniques.<t>.metrics.<env>.<metric>.<stat>, a measured value
    (:class:`validate.stats.Measured`), or in a file from before it the number beside ``<stat>_uncertainty``."""
    cells = {}
    for tech, envs in by_env.items():
        for env, metrics in (envs or {}).items():
            m = (metrics or {}).get(metric) or {}
            v = m.get(stat)
            cells[(tech, env)] = ((_f(v.get("value")), _f(v.get("uncertainty", 0.0))) if isinstance(v, Mapping)
                                  else (_f(v), _f(m.get(f"{stat}_uncertainty", 0.0))))
    return cells


def _tech_metrics(e: Entry) -> dict[str, Any]:
    return {k: (v or {}).get("metrics") or {} for k, v in (e.get("techniques") or {}).items()}


PAPER_LEVELS = {"mean": {"R&H: mean < 1 %": 0.01}, "max": {"R&H: max < 5 %": 0.05}}  # R&H 2001, §4


def sh9(e: Entry) -> Summary | None:
    """Per technique, its mean and max flux-normalised error |E′ − E| / Φ over the sphere's normals, spread over
    the environments (techniques sorted by their median max), R&H's 1 % / 5 % lines, the paper's probes marked;
    the full technique × environment matrix of the max below it."""
    metrics = _tech_metrics(e)
    cells = {stat: _env_stat_cells(metrics, stat) for stat in ("mean", "max")}
    full = _matrix("Irradiance techniques against the Mitsuba quadrature", "max flux-normalised error |ΔE|/Φ, %",
                   cells["max"], "environments")
    if full is None:
        return None
    panels = {f"{stat} over the normals": [[cells[stat].get((r, c), (math.nan, 0.0))[0] for c in full.cols]
                                           for r in full.rows] for stat in ("mean", "max")}
    order = sorted(range(len(full.rows)), key=lambda i: _median(panels["max over the normals"][i]))
    panels = {k: [v[i] for i in order] for k, v in panels.items()}
    envs = e.get("environments") or {}
    paper = [c for c in full.cols if isinstance(envs.get(c), Mapping) and "published" in envs[c]]
    return Spread("Irradiance error over the environments (techniques by median)",
                  "flux-normalised error |E′ − E| / Φ, %", [full.rows[i] for i in order], full.cols, panels,
                  {f"{stat} over the normals": PAPER_LEVELS[stat] for stat in ("mean", "max")}, paper,
                  "the paper's probes" + (f" ({', '.join(paper)})" if paper else ""), matrix=full)


def _median(vs: list[float]) -> float:
    f = sorted(v for v in vs if math.isfinite(v))
    if not f:
        return math.inf
    n = len(f)
    return f[n // 2] if n % 2 else 0.5 * (f[n // 2 - 1] + f[n // 2])


def engines(e: Entry) -> Summary | None:
    """The engines' SH (three.js, Babylon.js) beside the suite's SH9, per environment."""
    metrics = _tech_metrics(e)
    keep = [t for t in metrics if t == "sh9" or "three" in t or "babylon" in t]
    cells = _env_stat_cells({t: metrics[t] for t in keep or metrics})
    return _matrix("Engine irradiance (three.js, Babylon.js) beside SH9",
                   "max flux-normalised error |ΔE|/Φ, %", cells, "environments")


def hemisphere(e: Entry) -> Summary | None:
    """Technique × sky (two-tone and sun-sky): worst flux-normalised error."""
    skies = e.get("skies") or {}
    cells = {(t, sky): v for sky, techs in skies.items()
             for (t, _), v in _env_stat_cells({t: {sky: m} for t, m in (techs or {}).items()}).items()}
    return _matrix("Every irradiance technique under hemisphere skies",
                   "max flux-normalised error |ΔE|/Φ, %", cells, "skies")


def ibl(e: Entry) -> Summary | None:
    """Approximation on its material: mean relative error on the rendered sphere ± the reference's MC σ."""
    rows = [(str(c.get("approximation")), f"{c.get('group', '')} {c.get('parameter', '')}".strip(),
             _f(c.get("mean")), _f(c.get("mean_uncertainty", 0.0))) for c in e.get("comparisons") or []]
    rows = [r for r in rows if math.isfinite(r[2])]
    if not rows:
        return None
    return Bars("Image-based lighting on a rendered sphere", "mean relative error |ΔL|/L, %",
                [r[0] for r in rows], [r[1] for r in rows], [r[2] for r in rows], [r[3] for r in rows])


def uberlight(e: Entry) -> Summary | None:
    """Technique × barn-door luminaire: RMS relative error of the path-traced beam."""
    cells = {(t, size): (_f(v.get("rms_rel")), _f(v.get("uncertainty", 0.0)))
             for t, sizes in (e.get("barndoor_techniques") or {}).items() for size, v in (sizes or {}).items()}
    return _matrix("Überlight against barn-door luminaires (path-traced)", "RMS relative error, %", cells,
                   "luminaires")


def arealights(e: Entry) -> Summary | None:
    """Error vs the light's half-angle α: max_θ |E′ − E| / Φ per technique (closed forms: no σ)."""
    s = e.get("alpha_sweep") or {}
    x = [_f(a) for a in s.get("alpha_deg") or []]
    series = {t: [_f(v) for v in ys] for t, ys in (s.get("errors") or {}).items() if len(ys) == len(x)}
    if not x or not series:
        return None
    return Curves("Area lights: error vs light size", "max |ΔE|/Φ, %", "half-angle α (°)", x, series,
                  logx=True, hlines={"5 % (Sloan's statement)": 0.05})


def lights(e: Entry) -> Summary | None:
    """Error vs distance: |E/E_(1/d²) − 1| per point-light falloff (closed forms: no σ)."""
    a = e.get("attenuation") or {}
    x = [_f(d) for d in a.get("distances") or []]
    series = {t: [abs(_f(r) - 1.0) for r in v.get("ratio") or []] for t, v in (a.get("techniques") or {}).items()}
    series = {t: ys for t, ys in series.items() if len(ys) == len(x) and any(y > 1e-9 for y in ys)}
    if not x or not series:
        return None
    return Curves("Point-light falloff against 1/d²", "|E/E(1/d²) − 1|, %", "distance d (m)", x, series,
                  logx=True)


def brdfs(e: Entry) -> Summary | None:
    """Error vs roughness: |A − A_Mitsuba| of the white-furnace albedo at normal incidence."""
    s = e.get("energy_sweep") or {}
    x = [_f(a) for a in s.get("alpha") or []]
    ref = [_f((r or [math.nan])[0]) for r in s.get("mitsuba") or []]
    if not x or len(ref) != len(x):
        return None
    series = {t: [abs(_f((v or [math.nan])[0]) - r) for v, r in zip(vals, ref, strict=False)]
              for t, vals in (s.get("techniques") or {}).items() if len(vals) == len(x)}
    return Curves("Classic BRDFs: white-furnace albedo error vs roughness", "|A − A_Mitsuba| at θ_v = 0",
                  "Beckmann roughness α", x, series, unit="") if series else None


def multiscatter(e: Entry) -> Summary | None:
    """Error vs roughness: worst over μ_v of |W − 1| in the white furnace (F = 1); band = |W − W_half|,
    the change when the quadrature runs on half the nodes (the experiment's own uncertainty)."""
    alphas = [_f(a) for a in (e.get("settings") or {}).get("alphas") or []]
    series, bands = {}, {}
    for t, w in (e.get("w") or {}).items():
        f1 = (w or {}).get("f0_1") or {}
        rows, half = f1.get("value"), f1.get("half")
        if not isinstance(rows, list) or len(rows) != len(alphas) or not any(any(_f(v) > 0 for v in r) for r in rows):
            continue
        idx = [max(range(len(r)), key=lambda j, r=r: abs(_f(r[j]) - 1.0)) for r in rows]
        series[t] = [abs(_f(r[j]) - 1.0) for r, j in zip(rows, idx, strict=True)]
        if isinstance(half, list) and len(half) == len(rows):  # quadrature at half the nodes: its σ
            bands[t] = [abs(_f(r[j]) - _f(h[j])) for r, h, j in zip(rows, half, idx, strict=True)]
    if not alphas or not series:
        return None
    return Curves("Multiple scattering: white-furnace energy loss vs roughness", "max over μ_v of |W − 1|, %",
                  "GGX roughness α", alphas, series, bands)


def shadows(e: Entry) -> Summary | None:
    """Error vs shadow-map size for the smallest light: total |ΔY| / L_norm ± σ per technique."""
    sweep = e.get("resolution_sweep") or {}
    sizes = sorted(sweep, key=_f)
    radii = sorted({r for s in sizes for r in (sweep[s] or {})}, key=_f)
    if not sizes or not radii:
        return None
    radius = radii[0]
    series: dict[str, list[float]] = {}
    bands: dict[str, list[float]] = {}
    for s in sizes:
        for t, v in ((sweep[s] or {}).get(radius) or {}).items():
            total = (v or {}).get("total") or {}
            series.setdefault(t, []).append(_f(total.get("mean")))
            bands.setdefault(t, []).append(_f(total.get("uncertainty", 0.0)))
    series = {t: ys for t, ys in series.items() if len(ys) == len(sizes)}
    return Curves(f"Shadow maps: error vs map size (light radius {radius} m)", "total |ΔY| / L_norm, %",
                  "shadow-map size (texels per side)", [_f(s) for s in sizes], series,
                  {t: bands[t] for t in series}, logx=True) if series else None


def _measured(v: Any) -> tuple[float, float]:
    """(value, σ) of a measured value's JSON (or a bare number); (NaN, 0) when absent."""
    if isinstance(v, Mapping):
        return _f(v.get("value")), _f(v.get("uncertainty", 0.0))
    return _f(v), 0.0


def _direction_fraction(d: Any) -> tuple[float, float] | None:
    """A unit direction [x, y, z] → (φ/2π, θ/π) on the equirect map (θ from +y, φ = atan2(x, −z);
    :mod:`validate.scenes.latlong`)."""
    if not isinstance(d, list) or len(d) != 3:
        return None
    x, y, z = (_f(c) for c in d)
    if not all(math.isfinite(c) for c in (x, y, z)):
        return None
    theta = math.acos(max(-1.0, min(1.0, y)))
    phi = math.atan2(x, -z) % (2.0 * math.pi)
    return phi / (2.0 * math.pi), theta / math.pi


def worstcase(e: Entry) -> Summary | None:
    """Per technique, the certificate of max |E′ − E| / Φ beside the worst the search found (± σ), and the worst
    lighting found as a small equirect map with the certificate's worst light on it."""
    certs, searches = e.get("certificates") or {}, e.get("searches") or {}
    lights = e.get("worst_lighting") or {}
    key = "flux_luminance.max"
    rows = [t for t in _ordered([*certs, *searches]) if key in (certs.get(t) or {}) or key in (searches.get(t) or {})]
    if not rows:
        return None
    maps: list[list[list[float]] | None] = []
    for t in rows:
        lum = (lights.get(t) or {}).get("luminance")
        ok = isinstance(lum, list) and lum and all(isinstance(r, list) and len(r) == len(lum[0]) for r in lum)
        maps.append([[_f(v) for v in r] for r in lum] if ok else None)
    return Worst("Worst case over any lighting: certificate and search",
                 "max over normals of |E′ − E| / Φ, %", rows,
                 [_measured((certs.get(t) or {}).get(key)) for t in rows],
                 [_measured((searches.get(t) or {}).get(key)) for t in rows], maps,
                 [_direction_fraction(((certs.get(t) or {}).get(key) or {}).get("direction")) for t in rows])


_SEEDS = {"forejune": "Fore June", "usc420": "USC 420", "orange": "Orange Book", "ganovelli": "Ganovelli",
          "redbook": "Red Book"}


def _listing_label(x: Mapping[str, Any]) -> str:
    """"Red Book 7.4", "Fore June 20.4 disc": the seed and the listing's catalogue name (numbers joined by a dot)."""
    seed, name = str(x.get("seed") or ""), str(x.get("name") or x.get("listing") or "")
    rest = name[len(seed) + 1:] if seed and name.startswith(seed + "_") else name
    rest = re.sub(r"(\d+)_(\d+)", r"\1.\2", rest).replace("_", " ")
    return f"{_SEEDS.get(seed, seed)} {rest}".strip()[:24]


def listings(e: Entry) -> Summary | None:
    """Per catalogued listing: its status and its error against its transcription and against Mitsuba."""
    index = [x for x in e.get("index") or [] if isinstance(x, Mapping)]
    if not index:
        return None
    gl = (e.get("gl") or {}).get("available", True)
    why = []
    for x in index:
        if x.get("status") == "not runnable" or not x.get("runs"):
            why.append("not run")
        elif x.get("transcription") is None:
            why.append("no GL here" if not gl else "—")
        else:
            why.append("")
    return Listings("Listings: status, against the transcription and against Mitsuba",
                    "largest relative error (–)", [_listing_label(x) for x in index],
                    [str(x.get("status") or "") for x in index], [_measured(x.get("transcription")) for x in index],
                    [_measured(x.get("mitsuba")) for x in index], why)


REFERENCE_ORDER = ("mitsuba", "gltf", "model", "energy")  # the reference a renders cell is coloured by


def renders(e: Entry) -> Summary | None:
    """Engine × scene: the fraction of pixels accepted against the scene's first reference of
    :data:`REFERENCE_ORDER` (any other after them), each cell linking to the scene's image strip."""
    scenes = {k: v for k, v in (e.get("scenes") or {}).items() if isinstance(v, Mapping)}
    rows = _ordered(en for sc in scenes.values() for en in [*(sc.get("engines") or {}), *(sc.get("skipped") or {})])
    cols = [k for k, sc in scenes.items() if sc.get("engines") or sc.get("skipped")]
    if not rows or not cols:
        return None
    figs = [str(f.get("path") or "") for sec in (e.get("report") or {}).get("sections") or []
            for f in (sec or {}).get("figures") or [] if isinstance(f, Mapping)]
    values, refs, others, skipped = [], [], [], []
    for en in rows:
        vr, rr, orr, sr = [], [], [], []
        for sc in cols:
            js = ((scenes[sc].get("engines") or {}).get(en) or {}).get("judgements") or {}
            kinds = sorted(js, key=lambda k: REFERENCE_ORDER.index(k) if k in REFERENCE_ORDER else len(REFERENCE_ORDER))
            ref = kinds[0] if kinds else ""
            vr.append(_measured((js.get(ref) or {}).get("fraction_accepted"))[0] if ref else math.nan)
            rr.append(ref)
            orr.append("; ".join(f"{k} {100 * _measured(js[k].get('fraction_accepted'))[0]:.1f} %"
                                 for k in kinds[1:] if isinstance(js[k], Mapping)))
            sr.append(str((scenes[sc].get("skipped") or {}).get(en) or ""))
        values.append(vr)
        refs.append(rr)
        others.append(orr)
        skipped.append(sr)
    strips = [next((f for f in figs if f.rsplit("/", 1)[-1].startswith(f"{sc}_r")), "") for sc in cols]
    return Acceptance("Engines against Mitsuba: pixels accepted per scene", "pixels accepted, %", rows, cols,
                      values, refs, others, skipped, strips)


# ---------------------------------------------------------------------------------------------------
# Generic: any experiment's techniques.<t>.metrics
# ---------------------------------------------------------------------------------------------------

def _leaf(v: Any) -> tuple[float, float] | None:
    """(value, σ) of a metric leaf: a measured value ({"value", "uncertainty", "unit"}), or in a file from before
    it {"value", "uncertainty"} or {"mean", "max", "max_uncertainty"} (max)."""
    if not isinstance(v, Mapping):
        return None
    if "value" in v:
        return _f(v["value"]), _f(v.get("uncertainty", 0.0))
    if "max" in v:
        return _f(v["max"]), _f(v.get("max_uncertainty", 0.0))
    return None


def _leaves(metrics: Mapping[str, Any], prefix: tuple[str, ...] = ()) -> Iterable[tuple[tuple[str, ...], Any]]:
    """(key path, (value, σ)) of every metric leaf, at most three levels down."""
    for k, v in metrics.items():
        leaf = _leaf(v)
        if leaf is not None:
            yield (*prefix, str(k)), leaf
        elif isinstance(v, Mapping) and len(prefix) < 2:
            yield from _leaves(v, (*prefix, str(k)))


def _metric_and_input(path: tuple[str, ...]) -> tuple[str, str]:
    """{"metric.input": leaf} → (metric, input); {"metric": leaf} → (metric, "all");
    {input: {metric: leaf}} → (metric, input); deeper paths keep every level above the metric."""
    if len(path) == 1:
        metric, _, col = path[0].partition(".")
        return metric, col or "all"
    return path[-1], " / ".join(path[:-1])


def generic(e: Entry) -> Summary | None:
    """Technique × input from ``techniques.<t>.metrics`` (any nesting, :func:`_metric_and_input`): the
    first metric name found, its inputs as columns, values as stored (no unit is assumed)."""
    cells: dict[str, dict[tuple[str, str], tuple[float, float]]] = {}
    for tech, metrics in _tech_metrics(e).items():
        for path, leaf in _leaves(metrics):
            metric, col = _metric_and_input(path)
            cells.setdefault(metric, {})[(tech, col)] = leaf
    for metric, c in cells.items():
        m = _matrix(str(e.get("title") or "Registered techniques"), metric, c, "inputs", unit="")
        if m is not None:
            return m
    return None


SUMMARIES: dict[str, Callable[[Entry], Summary | None]] = {
    "sh9": sh9, "engines": engines, "hemisphere": hemisphere, "ibl": ibl, "uberlight": uberlight,
    "arealights": arealights, "lights": lights, "brdfs": brdfs, "multiscatter": multiscatter, "shadows": shadows,
    "worstcase": worstcase, "listings": listings, "renders": renders,
}


def summary_for(name: str, e: Entry) -> Summary | None:
    """The experiment's own summary, else :func:`generic`; a malformed entry falls through, never raises."""
    for fn in (SUMMARIES.get(name), generic):
        if fn is None:
            continue
        try:
            s = fn(e)
        except (TypeError, ValueError, KeyError, AttributeError, IndexError):
            s = None
        if s is not None:
            return s
    return None


def verdict(s: Summary | None, claims: list[Mapping[str, Any]]) -> list[str]:
    """Three lines: best and worst technique by the headline (worst over inputs / the sweep), and the
    claims passed with their power checks ("fails ✓" is the power check doing its job)."""
    lines = []
    rank = s.ranking() if s is not None else []
    over = s.xlabel.split(" (")[0] if isinstance(s, Curves) else (s.over if s is not None else "")
    if rank:
        for label, (name, v, sig) in (("Best", rank[0]), ("Worst", rank[-1])):
            lines.append(f"{label}: {name} — {pm(v, sig, s.unit)} ({s.metric.split(',')[0]}, worst over {over})")
    if isinstance(s, Listings):
        lines += s.lines()
    n = len(claims)
    passed = sum(bool(c.get("passed")) for c in claims)
    power = [c.get("power") for c in claims]
    fails = sum(bool((p or {}).get("fails")) for p in power)
    weak = sum(p is not None and not p.get("fails") for p in power)
    missing = sum(p is None for p in power)
    tail = "".join([f"; {weak} still pass under their perturbation" if weak else "",
                    f"; {missing} without a power check" if missing else ""])
    lines.append(f"Claims: {passed}/{n} pass; power checks: {fails}/{n} fail under their perturbation, as they "
                 f"must{tail}." if n else "Claims: none recorded.")
    return lines

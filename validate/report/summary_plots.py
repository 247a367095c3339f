"""Drawing of the summary figures described by :mod:`.summary` (matplotlib, Agg canvas, no pyplot).

* A :class:`~.summary.Matrix` is a heat map: one row per technique, one column per input, the colour the
  headline error on a log scale (errors span orders of magnitude; the scale's floor is 10⁻⁴ of its
  top, lower and zero values take the floor's colour), and in each cell the value ± σ written by
  :func:`validate.format.pm` (the unit is on the colour bar). Unmeasured cells are grey with "—".
* A :class:`~.summary.Curves` is a line plot: one line per technique, a ±1σ band where σ is known,
  log y (non-positive values leave gaps), per cent axis for fractions.
* A :class:`~.summary.Bars` is horizontal bars ± σ, coloured by input.
* A :class:`~.summary.Spread` is a box per technique over the inputs, each input a dot, log x, one panel
  per statistic, the marked inputs (the paper's probes) as red diamonds, the reference levels as lines.
* A :class:`~.summary.Worst` is per technique the certificate and the search's worst ± σ as bars, and
  beside each the worst lighting found as a small equirect map (the certificate's delta light a star).
* A :class:`~.summary.Listings` is one row per listing: its status, then its error against its
  transcription and against Mitsuba as dots ± σ on log axes (or why there is none).
* An :class:`~.summary.Acceptance` is an engine × scene heat map of the fraction of pixels accepted
  (red 50 % or less → green 100 %), each cell naming its reference (the page draws it as HTML).

Figures are sized for a 1280-px window — at most :data:`MAX_WIDTH_IN` × :data:`MAX_HEIGHT_IN` inches at
100 dpi — and every text is :data:`FONT` points (``summary.FONT_PT``): shown at its own size it is no
smaller than the page's body text. :func:`figure` returns the drawing, :func:`draw` writes it;
:func:`text_boxes` lists its texts' sizes and boxes (the tests check sizes and overlaps).
"""

from __future__ import annotations

import math
import os
import textwrap

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.ticker import FuncFormatter

from ..atomic import atomic_path
from ..figures import plots
from ..format import pm, sig
from . import summary
from .summary import Acceptance, Bars, Curves, Listings, Matrix, Spread, Summary, Worst

MAX_WIDTH_IN = 11.0  # 1100 px at plots.FIG_DPI: fits the page column of a 1280-px window
MAX_HEIGHT_IN = 5.8  # 580 px: below the page's title, still above the fold of an 800-px window
LOG_RANGE = 1e-4  # colour-scale floor relative to its top
ROW_IN, COL_IN = 0.27, 1.0  # inches per matrix row and column
BAR_IN = 0.2  # inches per bar (one line of FONT_PT text)
CURVES_SIZE = (10.0, 4.6)  # inches
FONT = summary.FONT_PT  # every text of a summary figure: as large as the page's body text on screen
_CMAP = "magma_r"
_ACCEPT_CMAP = "RdYlGn"
ACCEPT_FLOOR = 0.5  # fraction accepted at the red end of the acceptance colours (1 at the green end)


def _percent(unit: str) -> float:
    return 100.0 if unit == "%" else 1.0


def _cell_text(v: float, s: float, unit: str, with_sigma: bool = True) -> str:
    """value ± σ (:func:`validate.format.pm`); a σ below 10⁻⁴ of the value as "± <σ's leading digit>" after 4
    significant digits (no 10-digit mantissas in a figure); the value alone without ``with_sigma``."""
    if not math.isfinite(v):
        return "—"
    k = _percent(unit)
    s = s if math.isfinite(s) else 0.0
    if not with_sigma:
        return sig(v * k, 3)
    if 0.0 < abs(s) < 1e-4 * abs(v):
        return f"{sig(v * k, 4)} ± {sig(s * k, 1)}"
    return pm(v * k, s * k)


def _fmt_axis(unit: str) -> FuncFormatter:
    suffix = " %" if unit == "%" else ""
    return FuncFormatter(lambda v, _: f"{sig(v, 2)}{suffix}")


def _style(ax: object, title: str = "") -> None:
    ax.tick_params(labelsize=FONT)  # type: ignore[attr-defined]
    if title:
        ax.set_title(title, fontsize=FONT)  # type: ignore[attr-defined]


def figure_matrix(m: Matrix) -> object:
    """Heat map of ``m``: value ± σ in each cell when the cells are wide enough, the value alone when not,
    colour alone below that; column names turned upright when there are many."""
    vals = np.array(m.values, dtype=np.float64) * _percent(m.unit)
    positive = vals[np.isfinite(vals) & (vals > 0)]
    top = float(positive.max()) if positive.size else 1.0
    floor = max(float(positive.min()) if positive.size else top * LOG_RANGE, top * LOG_RANGE)
    shown = np.where(np.isfinite(vals), np.clip(vals, floor, top), np.nan)
    width = min(MAX_WIDTH_IN, 3.2 + COL_IN * len(m.cols))
    col_in = (width - 3.4) / max(len(m.cols), 1)
    upright = col_in < 1.3 or len(m.cols) > 6
    label_in = 0.09 * max((len(c) for c in m.cols), default=1) if upright else 0.5
    height = min(MAX_HEIGHT_IN, 0.9 + label_in + ROW_IN * len(m.rows))
    fig = plots._new_figure((width, height))
    ax = fig.add_subplot()
    norm = LogNorm(vmin=floor, vmax=top) if top > floor else None
    im = ax.imshow(np.ma.masked_invalid(shown), cmap=plots_cmap(), norm=norm, aspect="auto", interpolation="nearest")
    with_sigma = col_in >= 1.25
    if col_in >= 0.5 and (height - 0.9 - label_in) / max(len(m.rows), 1) >= 0.22:
        for i in range(len(m.rows)):
            for j in range(len(m.cols)):
                v = shown[i, j]
                light = math.isfinite(v) and norm is not None and norm(v) > 0.55
                ax.text(j, i, _cell_text(m.values[i][j], m.sigmas[i][j], m.unit, with_sigma), ha="center",
                        va="center", fontsize=FONT, color="white" if light else "black")
    ax.set_xticks(range(len(m.cols)), [c.replace("_", " ") for c in m.cols], rotation=90 if upright else 25,
                  ha="center" if upright else "right", fontsize=FONT)
    ax.set_yticks(range(len(m.rows)), m.rows, fontsize=FONT)
    _style(ax, textwrap.fill(f"{m.title} — {m.metric}", int(width * 8.5)))
    bar = fig.colorbar(im, ax=ax, fraction=0.035, pad=0.01)
    bar.set_label(m.metric.rsplit(", ", 1)[-1] if ", " in m.metric else "", fontsize=FONT)
    bar.ax.tick_params(labelsize=FONT)
    bar.ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: sig(v, 2)))
    bar.ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    return fig


def _save(path: str | os.PathLike[str], fig: object) -> None:
    """Write ``fig`` at ``path`` atomically, in the format its suffix names: .png (raster, :data:`plots.FIG_DPI`),
    .pdf or .svg (vector: the same drawing, text as text)."""
    suffix = os.fspath(path).rsplit(".", 1)[-1].lower()
    if suffix == "png":
        plots._save_figure(path, fig)
        return
    with plots.FIGURE_LOCK, atomic_path(path, suffix=f".{suffix}") as tmp:
        fig.savefig(tmp, format=suffix, dpi=plots.FIG_DPI)  # type: ignore[attr-defined]


def plots_cmap() -> object:
    """The matrix colour map with unmeasured (masked) cells in the report's mask grey."""
    from matplotlib import colormaps

    return colormaps[_CMAP].with_extremes(bad=plots.MASK_COLOUR)


def accept_cmap() -> object:
    """The acceptance colour map (red → yellow → green), unrendered cells in the mask grey."""
    from matplotlib import colormaps

    return colormaps[_ACCEPT_CMAP].with_extremes(bad=plots.MASK_COLOUR)


def accept_colour(fraction: float) -> str:
    """The cell colour of a fraction accepted (hex, light enough for black text): :data:`ACCEPT_FLOOR` or less
    red, 1 green; the mask grey when not measured."""
    from matplotlib.colors import to_hex

    if not math.isfinite(fraction):
        return plots.MASK_COLOUR
    t = min(1.0, max(0.0, (fraction - ACCEPT_FLOOR) / (1.0 - ACCEPT_FLOOR)))
    r, g, b, _ = accept_cmap()(0.15 + 0.7 * t)  # type: ignore[operator]
    return to_hex((0.45 + 0.55 * r, 0.45 + 0.55 * g, 0.45 + 0.55 * b))  # lightened: the text stays black


def figure_curves(c: Curves) -> object:
    """Line plot of ``c`` (±1σ bands where known), the legend beside it."""
    k = _percent(c.unit)
    fig = plots._new_figure(CURVES_SIZE)
    ax = fig.add_subplot()
    x = np.asarray(c.x, dtype=np.float64)
    for i, (name, ys) in enumerate(c.series.items()):
        y = np.asarray(ys, dtype=np.float64) * k
        if c.logy:
            y = np.where(y > 0, y, np.nan)
        (line,) = ax.plot(x, y, marker=plots._MARKERS[i % len(plots._MARKERS)], markersize=5, linewidth=1.6,
                          label=name)
        band = c.bands.get(name)
        if band:
            b = np.asarray(band, dtype=np.float64) * k
            lo = np.maximum(y - b, np.nanmin(y[y > 0]) * 0.5) if c.logy and np.any(y > 0) else y - b
            ax.fill_between(x, lo, y + b, color=line.get_color(), alpha=0.2, linewidth=0)
    for i, (name, level) in enumerate(c.hlines.items()):
        ax.axhline(level * k, linestyle="--", linewidth=1.2, color=plots._HLINE_COLOURS[i % 4], label=name)
    if c.logx:
        ax.set_xscale("log")
        plots._plain_log_ticks(ax.xaxis, x)
    if c.logy:
        ax.set_yscale("log")
    ax.yaxis.set_major_formatter(_fmt_axis(c.unit))
    ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    ax.set_xlabel(c.xlabel, fontsize=FONT)
    ax.set_ylabel(c.metric, fontsize=FONT)
    _style(ax, c.title)
    ax.grid(True, which="major", alpha=0.35)
    n = len(c.series) + len(c.hlines)
    ax.legend(fontsize=FONT, framealpha=0.85, loc="center left", bbox_to_anchor=(1.01, 0.5),
              ncol=1 if n <= 14 else 2, handlelength=1.6, labelspacing=0.3)
    return fig


def figure_bars(b: Bars) -> object:
    """Horizontal bars of ``b`` with ±σ error bars (log x), one colour per input, the value beside each bar."""
    k = _percent(b.unit)
    fig = plots._new_figure((MAX_WIDTH_IN, min(MAX_HEIGHT_IN, 1.0 + BAR_IN * len(b.labels))))
    ax = fig.add_subplot()
    groups = list(dict.fromkeys(b.groups))
    colours = {g: f"C{i % 10}" for i, g in enumerate(groups)}
    y = np.arange(len(b.labels))
    vals = np.asarray(b.values, dtype=np.float64) * k
    errs = np.nan_to_num(np.asarray(b.sigmas, dtype=np.float64) * k)
    ax.barh(y, vals, xerr=errs, color=[colours[g] for g in b.groups], height=0.75,
            error_kw={"elinewidth": 0.8, "capsize": 2})
    for yi, v, s in zip(y, b.values, b.sigmas, strict=True):
        right = (v + (s if math.isfinite(s) else 0.0)) * k
        ax.text(right * 1.06, yi, _cell_text(v, s, b.unit), va="center", fontsize=FONT)
    ax.set_yticks(y, b.labels, fontsize=FONT)
    ax.set_ylim(len(b.labels) - 0.5, -0.5)
    ax.set_xscale("log")
    finite = vals[np.isfinite(vals) & (vals > 0)]
    if finite.size:
        ax.set_xlim(finite.min() / 2, finite.max() * 12)  # room for the value beside the longest bar
    ax.xaxis.set_major_formatter(_fmt_axis(b.unit))
    ax.xaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    ax.set_xlabel(b.metric, fontsize=FONT)
    _style(ax, b.title)
    ax.grid(True, axis="x", alpha=0.3)
    handles = [ax.barh([0], [0], color=colours[g], label=g) for g in groups]
    ax.legend(handles=handles, fontsize=FONT, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return fig


def figure_spread(s: Spread) -> object:
    """One panel per statistic: a box per technique over the inputs (log x), every input a dot, the marked
    inputs red diamonds, the reference levels dashed lines; the techniques in the spec's order, top down."""
    k = _percent(s.unit)
    n = len(s.rows)
    height = min(MAX_HEIGHT_IN, 1.55 + 0.26 * n)
    fig = plots._new_figure((MAX_WIDTH_IN, height))
    axes = fig.subplots(1, len(s.panels), sharey=True, squeeze=False)[0]
    marked = [j for j, c in enumerate(s.cols) if c in s.marked]
    rng = np.random.default_rng(0)
    jitter = rng.uniform(-0.18, 0.18, size=len(s.cols))
    handles: dict[str, object] = {}
    levels = [label for lv in s.hlines.values() for label in lv]
    for ax, (title, values) in zip(axes, s.panels.items(), strict=True):
        v = np.array(values, dtype=np.float64) * k
        v = np.where(v > 0, v, np.nan)
        data = [row[np.isfinite(row)] for row in v]
        keep = [i for i, d in enumerate(data) if d.size]
        ax.boxplot([data[i] for i in keep], positions=keep, orientation="horizontal", widths=0.6, showfliers=False,
                   patch_artist=True, boxprops={"facecolor": "#dbe6f3", "edgecolor": "#4a6d94"},
                   medianprops={"color": "#1f3b5c", "linewidth": 1.8}, whiskerprops={"color": "#4a6d94"},
                   capprops={"color": "#4a6d94"})
        others = [j for j in range(len(s.cols)) if j not in marked]
        for i in range(n):
            handles["environment"] = ax.scatter(v[i, others], i + jitter[others], s=9, color="0.35", alpha=0.7,
                                                zorder=3, linewidths=0)
            if marked:
                handles[s.marked_label or "marked"] = ax.scatter(v[i, marked], i + jitter[marked], s=42,
                                                                 marker="D", color="#d62728", edgecolors="white",
                                                                 linewidths=0.6, zorder=4)
        for label, level in s.hlines.get(title, {}).items():
            handles[label] = ax.axvline(level * k, linestyle="--", linewidth=1.6, zorder=2,
                                        color=plots._HLINE_COLOURS[(levels.index(label) + 1) % 4])
        ax.set_xscale("log")
        ax.xaxis.set_major_formatter(_fmt_axis(s.unit))
        ax.xaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
        ax.grid(True, axis="x", which="major", alpha=0.35)
        ax.set_xlabel(f"{title}, {s.unit}" if s.unit else title, fontsize=FONT)
        _style(ax)
    axes[0].set_yticks(range(n), s.rows, fontsize=FONT)
    axes[0].set_ylim(n - 0.5, -0.5)
    fig.get_layout_engine().set(w_pad=0.12, wspace=0.06)  # type: ignore[union-attr]
    fig.suptitle(s.title, fontsize=FONT)
    fig.legend(list(handles.values()), list(handles), loc="outside lower center", ncol=len(handles), fontsize=FONT,
               frameon=False, handlelength=1.4, columnspacing=1.2)
    return fig


def _equirect(ax: object, lum: list[list[float]] | None, star: tuple[float, float] | None) -> None:
    """A small equirect map (φ across, θ down from +y): the luminance on a log scale over 5 decades, the star
    at (φ/2π, θ/π); a dark field when there is no map."""
    grid = np.zeros((8, 16)) if lum is None else np.asarray(lum, dtype=np.float64)
    shown = np.log10(np.clip(grid, 1e-5, 1.0)) if lum is not None else np.full(grid.shape, -5.0)
    ax.imshow(shown, cmap="inferno", vmin=-5.0, vmax=0.0, extent=(0.0, 1.0, 1.0, 0.0), aspect="auto",  # type: ignore[attr-defined]
              interpolation="nearest")
    if star is not None:
        ax.plot([star[0]], [star[1]], marker="*", color="#00e5ff", markersize=9, markeredgecolor="black",  # type: ignore[attr-defined]
                markeredgewidth=0.5)
    ax.set_xticks([])  # type: ignore[attr-defined]
    ax.set_yticks([])  # type: ignore[attr-defined]
    ax.set_xlim(0.0, 1.0)  # type: ignore[attr-defined]
    ax.set_ylim(1.0, 0.0)  # type: ignore[attr-defined]


def figure_worst(w: Worst) -> object:
    """Bars: per technique the certificate and the search's worst ± σ (log x); beside each row its worst
    lighting found (a small equirect map) with the certificate's worst light as a star."""
    k = _percent(w.unit)
    n = len(w.rows)
    pitch = min(0.75, max(0.3, 4.4 / max(n, 1)))
    height = min(MAX_HEIGHT_IN, 1.25 + pitch * n)
    fig = plots._new_figure((MAX_WIDTH_IN, height), layout=None)
    top, bottom = 1.0 - 0.6 / height, 0.75 / height  # inches kept for the legend above, the x axis below
    ax = fig.add_axes((0.2, bottom, 0.56, top - bottom))
    labels = pitch >= 0.5  # room for "value ± σ" beside each bar
    y = np.arange(n)
    for off, (label, vals, colour) in zip((-0.2, 0.2), (("certificate (any lighting)", w.certificate, "#4a6d94"),
                                                        ("worst found by the search", w.search, "#e08214")),
                                          strict=True):
        v = np.array([a for a, _ in vals]) * k
        e = np.nan_to_num(np.array([b for _, b in vals]) * k)
        ax.barh(y + off, v, height=0.38, xerr=e, color=colour, label=label, error_kw={"elinewidth": 1.0,
                                                                                     "capsize": 3})
        for yi, (a, b) in zip(y, vals, strict=True):
            if labels and math.isfinite(a):
                ax.text((a + (b if math.isfinite(b) else 0.0)) * k, yi + off, "  " + _cell_text(a, b, w.unit),
                        va="center", fontsize=FONT)
    ax.set_yticks(y, w.rows, fontsize=FONT)
    ax.set_ylim(n - 0.5, -0.5)
    allv = np.array([a for a, _ in (*w.certificate, *w.search)]) * k
    allv = allv[np.isfinite(allv) & (allv > 0)]
    if allv.size and allv.max() > 30 * allv.min():  # orders of magnitude apart: a log axis
        ax.set_xscale("log")
        ax.set_xlim(allv.min() / 3, allv.max() * (8 if labels else 2))
    elif allv.size:
        ax.set_xlim(0.0, allv.max() * (1.6 if labels else 1.1))
    ax.xaxis.set_major_formatter(_fmt_axis(w.unit))
    ax.xaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    ax.set_xlabel(w.metric, fontsize=FONT)
    ax.grid(True, axis="x", alpha=0.3)
    _style(ax)
    ax.legend(fontsize=FONT, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=2, frameon=False, borderaxespad=0.2)
    # the maps: one per row, centred on its bars, 2:1 like the equirect
    axis_h = (top - bottom) * height / n  # inches per row
    map_h = min(0.85 * axis_h, 0.7)
    for i, (lum, star) in enumerate(zip(w.maps, w.stars, strict=True)):
        cy = top - (i + 0.5) * (top - bottom) / n
        mh = map_h / height
        mw = 2 * map_h / MAX_WIDTH_IN
        sub = fig.add_axes((0.79, cy - mh / 2, mw, mh))
        _equirect(sub, lum, star)
    fig.text(0.79, top + 0.05 / height, "worst lighting found\n★ the certificate's light", fontsize=FONT,
             va="bottom", linespacing=1.1)
    return fig


_STATUS_COLOURS = {"as printed": "#1a7f37", "with an edit": "#b45309", "not runnable": "#6b7280"}


def figure_listings(li: Listings) -> object:
    """One row per listing: its name, its status (coloured text), then its error against its transcription
    (with the claim's bound) and against Mitsuba as dots ± σ on log axes; the reason instead where none."""
    n = len(li.rows)
    pitch = 0.24
    height = min(MAX_HEIGHT_IN, 1.25 + pitch * n)
    fig = plots._new_figure((MAX_WIDTH_IN, height), layout=None)
    top, bottom = 1.0 - 0.45 / height, 0.8 / height
    left, status_w, gap = 0.19, 0.105, 0.04
    pw = (0.985 - left - status_w - 2 * gap) / 2
    st = fig.add_axes((left, bottom, status_w, top - bottom))
    a1 = fig.add_axes((left + status_w + gap, bottom, pw, top - bottom), sharey=st)
    a2 = fig.add_axes((left + status_w + 2 * gap + pw, bottom, pw, top - bottom), sharey=st)
    st.set_xlim(0, 1)
    st.set_ylim(n - 0.5, -0.5)
    st.set_yticks(range(n), li.rows, fontsize=FONT)
    st.set_xticks([])
    for side in ("top", "right", "bottom"):
        st.spines[side].set_visible(False)
    for i, status in enumerate(li.status):
        st.text(0.04, i, status, va="center", fontsize=FONT, color=_STATUS_COLOURS.get(status, "black"))
    for ax, vals, title, colour in ((a1, li.transcription, "GLSL vs its transcription", "#4a6d94"),
                                    (a2, li.mitsuba, "vs Mitsuba", "#d62728")):
        v = np.array([a for a, _ in vals], dtype=np.float64)
        e = np.nan_to_num(np.array([b for _, b in vals], dtype=np.float64))
        ok = np.isfinite(v) & (v > 0)
        ax.set_xscale("log")
        if ok.any():
            ax.errorbar(v[ok], np.flatnonzero(ok), xerr=np.minimum(e[ok], v[ok] * 0.99), fmt="o", color=colour,
                        markersize=6, capsize=3)
            lo, hi = float(v[ok].min()), float(v[ok].max())
            if ax is a1:
                lo, hi = min(lo, li.bound), max(hi, li.bound)
            ax.set_xlim(lo / 6, hi * 6)
        for i in np.flatnonzero(~ok):
            ax.text(0.5, i, li.why[i] or "not measured", transform=ax.get_yaxis_transform(), ha="center",
                    va="center", fontsize=FONT, color="0.45")
        if ax is a1:
            ax.axvline(li.bound, linestyle="--", linewidth=1.2, color="#b2182b")
            ax.text(li.bound, -0.6, " claim's bound", fontsize=FONT, color="#b2182b", va="bottom", ha="left")
        ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: sig(x, 1)))
        ax.xaxis.set_minor_formatter(FuncFormatter(lambda x, _: ""))
        ax.grid(True, axis="x", alpha=0.3)
        ax.tick_params(axis="y", left=False, labelleft=False)
        ax.set_xlabel(f"{title}: {li.metric}", fontsize=FONT)
        _style(ax)
    for i in range(n):
        if i % 2:
            for ax in (st, a1, a2):
                ax.axhspan(i - 0.5, i + 0.5, color="#f3f4f6", zorder=0, linewidth=0)
    fig.suptitle(li.title, fontsize=FONT, x=left, ha="left", y=1.0 - 0.06 / height, va="top")
    return fig


def figure_acceptance(a: Acceptance) -> object:
    """Engine × scene heat map of the fraction accepted (the thumbnail and the vector export of the page's
    HTML grid): scenes down, engines across, each cell its per cent and reference."""
    vals = np.array(a.values, dtype=np.float64).T  # scenes × engines
    n, m = vals.shape
    height = min(MAX_HEIGHT_IN, 1.0 + 0.24 * n)
    fig = plots._new_figure((min(MAX_WIDTH_IN, 3.2 + 1.9 * m), height))
    ax = fig.add_subplot()
    from matplotlib.colors import to_rgb

    rgb = np.array([[to_rgb(accept_colour(v)) for v in row] for row in vals])
    ax.imshow(rgb, aspect="auto", interpolation="nearest")
    for i in range(n):
        for j in range(m):
            v = vals[i, j]
            text = (f"{100 * v:.1f} % {a.refs[j][i]}" if math.isfinite(v) else
                    "skipped" if a.skipped[j][i] else "—")
            ax.text(j, i, text, ha="center", va="center", fontsize=FONT)
    ax.set_xticks(range(m), a.rows, fontsize=FONT)
    ax.xaxis.tick_top()
    ax.set_yticks(range(n), a.cols, fontsize=FONT)
    ax.set_title(a.title, fontsize=FONT)
    return fig


def figure(s: Summary) -> object:
    """The matplotlib Figure of the summary ``s`` (not yet written)."""
    if isinstance(s, Matrix):
        return figure_matrix(s)
    if isinstance(s, Bars):
        return figure_bars(s)
    if isinstance(s, Spread):
        return figure_spread(s)
    if isinstance(s, Worst):
        return figure_worst(s)
    if isinstance(s, Listings):
        return figure_listings(s)
    if isinstance(s, Acceptance):
        return figure_acceptance(s)
    return figure_curves(s)


def draw(s: Summary, path: str | os.PathLike[str]) -> None:
    """Write the summary figure ``s`` at ``path`` (atomically; PNG, PDF or SVG by the suffix)."""
    _save(path, figure(s))


def draw_matrix(m: Matrix, path: str | os.PathLike[str]) -> None:
    """The full matrix of ``m`` (a :class:`~.summary.Spread`'s), written at ``path``."""
    _save(path, figure_matrix(m))


def text_boxes(fig: object) -> list[tuple[str, float, tuple[float, float, float, float]]]:
    """(text, size in points, (x0, y0, x1, y1) in pixels) of every visible non-empty text of the drawn
    ``fig``, tick labels included."""
    from matplotlib.text import Text

    with plots.FIGURE_LOCK:
        fig.canvas.draw()  # type: ignore[attr-defined]
        renderer = fig.canvas.get_renderer()  # type: ignore[attr-defined]
        hidden = set()  # labels of ticks outside their axis' view: matplotlib keeps them but does not draw them
        for ax in fig.axes:  # type: ignore[attr-defined]
            for axis in (ax.xaxis, ax.yaxis):
                lo, hi = sorted(axis.get_view_interval())
                tol = 1e-9 * max(abs(lo), abs(hi), 1.0)
                for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                    if not lo - tol <= tick.get_loc() <= hi + tol:
                        hidden.update((id(tick.label1), id(tick.label2)))
        out = []
        for t in fig.findobj(Text):  # type: ignore[attr-defined]
            if not t.get_visible() or not t.get_text().strip() or not t.get_figure() or id(t) in hidden:
                continue
            ax = t.axes
            if ax is not None and not ax.get_visible():
                continue
            bb = t.get_window_extent(renderer)
            if bb.width <= 0 or bb.height <= 0:
                continue
            if not (bb.x1 > 0 and bb.y1 > 0 and bb.x0 < fig.bbox.width and bb.y0 < fig.bbox.height):  # type: ignore[attr-defined]
                continue  # clipped away (a tick label outside its axis' range is not drawn)
            out.append((t.get_text(), float(t.get_fontsize()), (bb.x0, bb.y0, bb.x1, bb.y1)))
    return out


def text_problems(fig: object, font_pt: float = summary.FONT_PT) -> list[str]:
    """What would make the drawn ``fig`` hard to read: a text smaller than ``font_pt``, a text reaching past the
    figure's edge, two texts overlapping (more than a pixel). Empty when there is nothing."""
    boxes = text_boxes(fig)
    w, h = fig.bbox.width, fig.bbox.height  # type: ignore[attr-defined]
    out = [f"{t!r} at {size:g} pt" for t, size, _ in boxes if size < font_pt - 1e-9]
    out += [f"{t!r} past the edge" for t, _, (x0, y0, x1, y1) in boxes
            if x0 < -1 or y0 < -1 or x1 > w + 1 or y1 > h + 1]
    for i, (ta, _, a) in enumerate(boxes):
        for tb, _, b in boxes[i + 1:]:
            if a[0] < b[2] - 1 and b[0] < a[2] - 1 and a[1] < b[3] - 1 and b[1] < a[3] - 1:
                out.append(f"{ta!r} overlaps {tb!r}")
    return out

"""Drawing of the summary figures described by :mod:`.summary` (matplotlib, Agg canvas, no pyplot).

* A :class:`~.summary.Matrix` is a heat map: one row per technique, one column per input, the colour the
  headline error on a log scale (errors span orders of magnitude; the scale's floor is 10⁻⁴ of its
  top, lower and zero values take the floor's colour), and in each cell the value ± σ written by
  :func:`validate.format.pm` (the unit is on the colour bar). Unmeasured cells are grey with "—".
* A :class:`~.summary.Curves` is a line plot: one line per technique, a ±1σ band where σ is known,
  log y (non-positive values leave gaps), per cent axis for fractions.
Figures are sized for a 1280-px window: at most :data:`MAX_WIDTH_IN` inches wide at 100 dpi.
"""

from __future__ import annotations

import math
import os

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.ticker import FuncFormatter

from ..atomic import atomic_path
from ..figures import plots
from ..format import pm, sig
from .summary import Bars, Curves, Matrix, Summary

MAX_WIDTH_IN = 11.0  # 1100 px at plots.FIG_DPI: fits the page column of a 1280-px window
LOG_RANGE = 1e-4  # colour-scale floor relative to its top
ROW_IN, COL_IN = 0.3, 1.05  # inches per matrix row and column
CURVES_SIZE = (9.5, 4.2)  # inches
_CMAP = "magma_r"


def _percent(unit: str) -> float:
    return 100.0 if unit == "%" else 1.0


def _cell_text(v: float, s: float, unit: str) -> str:
    if not math.isfinite(v):
        return "—"
    k = _percent(unit)
    return pm(v * k, s * k if math.isfinite(s) else 0.0)


def draw_matrix(m: Matrix, path: str | os.PathLike[str]) -> None:
    """Heat map of ``m`` with value ± σ in each cell, written as a PNG at ``path``."""
    vals = np.array(m.values, dtype=np.float64) * _percent(m.unit)
    positive = vals[np.isfinite(vals) & (vals > 0)]
    top = float(positive.max()) if positive.size else 1.0
    floor = max(float(positive.min()) if positive.size else top * LOG_RANGE, top * LOG_RANGE)
    shown = np.where(np.isfinite(vals), np.clip(vals, floor, top), np.nan)
    width = min(MAX_WIDTH_IN, 2.6 + COL_IN * len(m.cols))
    fig = plots._new_figure((width, 1.5 + ROW_IN * len(m.rows)))
    ax = fig.add_subplot()
    cmap = plots_cmap()
    norm = LogNorm(vmin=floor, vmax=top) if top > floor else None
    im = ax.imshow(np.ma.masked_invalid(shown), cmap=cmap, norm=norm, aspect="auto", interpolation="nearest")
    font = 7.0 if len(m.cols) <= 8 else 6.0
    for i in range(len(m.rows)):
        for j in range(len(m.cols)):
            v = shown[i, j]
            light = math.isfinite(v) and norm is not None and norm(v) > 0.55
            ax.text(j, i, _cell_text(m.values[i][j], m.sigmas[i][j], m.unit), ha="center", va="center",
                    fontsize=font, color="white" if light else "black")
    ax.set_xticks(range(len(m.cols)), [c.replace("_", " ") for c in m.cols], rotation=25, ha="right", fontsize=8)
    ax.set_yticks(range(len(m.rows)), m.rows, fontsize=8)
    ax.set_title(m.title, fontsize=10)
    bar = fig.colorbar(im, ax=ax, fraction=0.035, pad=0.01)
    bar.set_label(m.metric, fontsize=8)
    bar.ax.tick_params(labelsize=7)
    bar.ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: sig(v, 2)))
    bar.ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    _save(path, fig)


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


def draw_curves(c: Curves, path: str | os.PathLike[str]) -> None:
    """Line plot of ``c`` (±1σ bands where known), written as a PNG at ``path``."""
    k = _percent(c.unit)
    fig = plots._new_figure(CURVES_SIZE)
    ax = fig.add_subplot()
    x = np.asarray(c.x, dtype=np.float64)
    for i, (name, ys) in enumerate(c.series.items()):
        y = np.asarray(ys, dtype=np.float64) * k
        if c.logy:
            y = np.where(y > 0, y, np.nan)
        (line,) = ax.plot(x, y, marker=plots._MARKERS[i % len(plots._MARKERS)], markersize=4, linewidth=1.5,
                          label=name)
        band = c.bands.get(name)
        if band:
            b = np.asarray(band, dtype=np.float64) * k
            lo = np.maximum(y - b, np.nanmin(y[y > 0]) * 0.5) if c.logy and np.any(y > 0) else y - b
            ax.fill_between(x, lo, y + b, color=line.get_color(), alpha=0.2, linewidth=0)
    for i, (name, level) in enumerate(c.hlines.items()):
        ax.axhline(level * k, linestyle="--", linewidth=1.0, color=plots._HLINE_COLOURS[i % 4], label=name)
    if c.logx:
        ax.set_xscale("log")
        plots._plain_log_ticks(ax.xaxis, x)
    if c.logy:
        ax.set_yscale("log")
    unit = " %" if c.unit == "%" else ""
    ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{sig(v, 2)}{unit}"))
    ax.set_xlabel(c.xlabel, fontsize=9)
    ax.set_ylabel(c.metric, fontsize=9)
    ax.set_title(c.title, fontsize=10)
    ax.tick_params(labelsize=8)
    ax.grid(True, which="major", alpha=0.35)
    ax.legend(fontsize=7.5, framealpha=0.85, loc="center left", bbox_to_anchor=(1.01, 0.5))
    _save(path, fig)


def draw_bars(b: Bars, path: str | os.PathLike[str]) -> None:
    """Horizontal bars of ``b`` with ±σ error bars (log x), one colour per input, as a PNG at ``path``."""
    k = _percent(b.unit)
    fig = plots._new_figure((9.5, 1.2 + 0.24 * len(b.labels)))
    ax = fig.add_subplot()
    groups = list(dict.fromkeys(b.groups))
    colours = {g: f"C{i % 10}" for i, g in enumerate(groups)}
    y = np.arange(len(b.labels))
    vals = np.asarray(b.values, dtype=np.float64) * k
    errs = np.nan_to_num(np.asarray(b.sigmas, dtype=np.float64) * k)
    ax.barh(y, vals, xerr=errs, color=[colours[g] for g in b.groups], error_kw={"elinewidth": 0.8, "capsize": 2})
    for yi, v, s in zip(y, b.values, b.sigmas, strict=True):
        right = (v + (s if math.isfinite(s) else 0.0)) * k
        ax.text(right * 1.04, yi, _cell_text(v, s, b.unit), va="center", fontsize=6.5)
    ax.set_yticks(y, b.labels, fontsize=7.5)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{sig(v, 2)}{' %' if b.unit == '%' else ''}"))
    ax.set_xlabel(b.metric, fontsize=9)
    ax.set_title(b.title, fontsize=10)
    ax.tick_params(labelsize=8)
    ax.grid(True, axis="x", alpha=0.3)
    handles = [ax.barh([0], [0], color=colours[g], label=g) for g in groups]
    ax.legend(handles=handles, fontsize=7.5, loc="center left", bbox_to_anchor=(1.01, 0.5))
    _save(path, fig)


def draw(s: Summary, path: str | os.PathLike[str]) -> None:
    """Write the summary figure ``s`` as a PNG at ``path`` (atomically)."""
    if isinstance(s, Matrix):
        draw_matrix(s, path)
    elif isinstance(s, Bars):
        draw_bars(s, path)
    else:
        draw_curves(s, path)

"""Report figures: tone-mapped HDR images, error heatmaps and line plots, written as small PNGs.

Everything draws on :class:`matplotlib.figure.Figure` objects with the Agg canvas, never on pyplot, so
importing this module changes no global matplotlib state (backend, rcParams, open figures). Every PNG
is written atomically (:func:`validate.atomic.atomic_path`): a reader never sees a half-written figure.

Tone mapping (:func:`tonemap`), for an HDR linear-RGB image L (Rec. 709 primaries, as Mitsuba):

1. exposure k (a linear scale factor). Auto exposure picks k so that the 99th percentile of the
   luminance Y = 0.2126 R + 0.7152 G + 0.0722 B [2] is displayed at 0.9 of white after steps 2–3:
   f(k·Y₉₉) = sRGB⁻¹(0.9) = 0.787, i.e. k = f⁻¹(0.787)/Y₉₉ = 0.928/Y₉₉. The brightest per cent
   (highlights, the sun) rolls off into white; half of Y₉₉ shows at 0.79, a tenth at 0.37;
2. the ACES filmic fit f(x) = x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clipped to [0, 1] [1],
   applied per channel to k·max(L, 0) (negative radiance, e.g. SH ringing, shows as black);
3. the sRGB transfer function [2]: 12.92 v for v ≤ 0.0031308, else 1.055 v^(1/2.4) − 0.055;
4. 8-bit quantisation (round(255 v)). Pixels with any non-finite channel become mid grey (128).

References
----------
[1] K. Narkowicz, "ACES Filmic Tone Mapping Curve", 2016 (fit of the ACES RRT + ODT).
[2] IEC 61966-2-1:1999, sRGB (transfer function); ITU-R BT.709 (luminance weights).
"""

from __future__ import annotations

import os
import threading
from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.axis import Axis
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.image import AxesImage
from matplotlib.patches import Rectangle
from matplotlib.ticker import FuncFormatter, NullFormatter

from ..atomic import atomic_path
from ..errors import ValidateError
from ..scenes.latlong import luminance

AUTO_PERCENTILE = 99.0  # luminance percentile that auto exposure places at AUTO_TARGET
AUTO_TARGET = 0.9  # display value (after the curve and sRGB encoding) of that percentile
NAN_GREY = 128  # 8-bit value of pixels with a non-finite channel
MASK_COLOUR = "#d9d9d9"  # heatmap colour of masked (NaN) pixels
FIG_SIZE = (5.0, 3.5)  # inches; at FIG_DPI a plot is 500 × 350 px, small enough for a light report
FIG_DPI = 100
PNG_COMPRESS_LEVEL = 3
"""zlib level of every report PNG (Pillow's default 6). Measured on the 504 PNGs of a full report, re-encoded: level 6
7.68 s and 23.3 MB, level 3 4.18 s and 26.4 MB, level 1 3.77 s and 28.5 MB — level 3 takes 46 % of the encoding
time off a cold run for 13 % more bytes."""
FIGURE_LOCK = threading.RLock()
"""Held while a figure is drawn and written: matplotlib's drawing (text layout, font caches) is not thread-safe,
and an experiment may run on a thread beside the others (:mod:`validate.run.schedule`)."""
_ACES = (2.51, 0.03, 2.43, 0.59, 0.14)  # a, b, c, d, e of f(x) = x(ax + b) / (x(cx + d) + e) [1]
_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "*")
_HLINE_COLOURS = ("0.25", "#b2182b", "#2166ac", "#1b7837")


def aces_filmic(x: np.ndarray) -> np.ndarray:
    """ACES filmic fit f(x) = x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14) clipped to [0, 1] [1]; x ≥ 0."""
    a, b, c, d, e = _ACES
    return np.clip(x * (a * x + b) / (x * (c * x + d) + e), 0.0, 1.0)


def aces_filmic_inverse(t: float) -> float:
    """The x ≥ 0 with f(x) = t for 0 ≤ t < a/c ≈ 1.033: positive root of (a − ct)x² + (b − dt)x − et = 0."""
    a, b, c, d, e = _ACES
    qa, qb, qc = a - c * t, b - d * t, -e * t
    return float((-qb + np.sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa))


def srgb_encode(v: np.ndarray) -> np.ndarray:
    """sRGB transfer function [2]: 12.92 v if v ≤ 0.0031308 else 1.055 v^(1/2.4) − 0.055 (v in [0, 1])."""
    v = np.clip(v, 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1.0 / 2.4) - 0.055)


def srgb_decode(s: np.ndarray | float) -> np.ndarray:
    """Inverse sRGB transfer function [2]: s/12.92 if s ≤ 0.04045 else ((s + 0.055)/1.055)^2.4."""
    s = np.clip(np.asarray(s, dtype=np.float64), 0.0, 1.0)
    return np.where(s <= 0.04045, s / 12.92, np.power((s + 0.055) / 1.055, 2.4))


def _as_rgb(rgb: np.ndarray) -> np.ndarray:
    a = np.asarray(rgb, dtype=np.float64)
    if a.ndim == 2:
        a = np.repeat(a[..., None], 3, axis=-1)
    if a.ndim != 3 or a.shape[-1] != 3 or a.shape[0] == 0 or a.shape[1] == 0:
        raise ValidateError(f"image of shape {np.shape(rgb)}: expected (H, W, 3) or (H, W)")
    return a


def auto_exposure(rgb: np.ndarray) -> float:
    """Scale k = f⁻¹(sRGB⁻¹(0.9)) / Y₉₉ over finite pixels (1 if Y₉₉ ≤ 0 or none is finite).

    Compute it once from a reference image and pass it to :func:`tonemap` for the approximations so
    that side-by-side images share one exposure.
    """
    a = _as_rgb(rgb)
    finite = np.all(np.isfinite(a), axis=-1)
    if not finite.any():
        return 1.0
    y = luminance(np.maximum(a[finite], 0.0))
    p = float(np.percentile(y, AUTO_PERCENTILE))
    if not p > 0.0:
        return 1.0
    return aces_filmic_inverse(float(srgb_decode(AUTO_TARGET))) / p


def tonemap(rgb: np.ndarray, exposure: float | None = None) -> np.ndarray:
    """HDR linear RGB (H, W, 3) or grey (H, W) → 8-bit sRGB (H, W, 3); see the module docstring.

    ``exposure`` is the linear scale k applied before the curve; None picks it with
    :func:`auto_exposure`. Non-finite pixels become mid grey.
    """
    a = _as_rgb(rgb)
    k = auto_exposure(a) if exposure is None else float(exposure)
    if not (np.isfinite(k) and k >= 0.0):
        raise ValidateError(f"exposure {exposure!r}: expected a finite scale factor ≥ 0")
    bad = ~np.all(np.isfinite(a), axis=-1)
    with np.errstate(invalid="ignore", over="ignore"):
        v = srgb_encode(aces_filmic(np.maximum(np.nan_to_num(a, nan=0.0, posinf=0.0), 0.0) * k))
    # a finite value so large that k·L overflows the tone curve (inf/inf) is white, not a NaN cast
    out = np.round(np.clip(np.nan_to_num(v, nan=1.0, posinf=1.0, neginf=0.0), 0.0, 1.0) * 255.0).astype(np.uint8)
    out[bad] = NAN_GREY
    return out


def _new_figure(figsize: tuple[float, float], layout: str | None = "constrained") -> Figure:
    """A Figure on its own Agg canvas (no pyplot, no global state), laid out by constrained layout unless
    ``layout`` is None (then the caller places every axes itself: the fixed layouts below are several
    times cheaper to draw, since constrained layout measures every artist's extent before the real draw)."""
    fig = Figure(figsize=figsize, dpi=FIG_DPI, layout=layout)
    FigureCanvasAgg(fig)
    return fig


def _save_figure(path: str | os.PathLike[str], fig: Figure) -> None:
    with FIGURE_LOCK, atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, format="png", dpi=FIG_DPI, pil_kwargs={"compress_level": PNG_COMPRESS_LEVEL})


def _panel_canvas(fig: Figure, width: float, height: float) -> Axes:
    """One invisible axes over the whole figure whose data coordinates are inches from the lower-left
    corner: small multiples are drawn as images (imshow ``extent``) and texts on it, so a grid of n panels
    costs one axes instead of n (creating and drawing an axes, with its ticks and spines, is most of a
    small-multiples figure's time)."""
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.set_axis_off()
    ax.set_xlim(0.0, width)
    ax.set_ylim(0.0, height)
    return ax


def _panel_box(x0: float, y0: float, cell_w: float, cell_h: float, title_h: float, aspect: float,
               pad: float = 0.05) -> tuple[float, float, float, float]:
    """Extent (left, right, bottom, top) in inches of an image of height/width ``aspect`` fitted, centred,
    into a cell at (x0, y0) of cell_w × cell_h inches, leaving ``pad`` around it and ``title_h`` above."""
    w = cell_w - 2.0 * pad
    h = w * aspect
    avail = cell_h - title_h - 2.0 * pad
    if h > avail:
        h, w = avail, avail / aspect
    left = x0 + 0.5 * (cell_w - w)
    bottom = y0 + pad + 0.5 * (avail - h)
    return left, left + w, bottom, bottom + h


def _draw_panel(ax: Axes, image: np.ndarray, box: tuple[float, float, float, float], title: str,
                fontsize: float, **imshow: object) -> AxesImage:
    """``image`` in ``box`` (as :func:`_panel_box`) with a thin frame and its title centred above."""
    left, right, bottom, top = box
    im = ax.imshow(image, extent=box, interpolation="nearest", aspect="auto", **imshow)
    ax.add_patch(Rectangle((left, bottom), right - left, top - bottom, fill=False, linewidth=0.8,
                           edgecolor="black"))
    ax.text(0.5 * (left + right), top + 0.06, title, ha="center", va="bottom", fontsize=fontsize)
    return im


def save_image(path: str | os.PathLike[str], rgb: np.ndarray, exposure: float | None = None,
               upscale: int = 1) -> None:
    """Tone-map ``rgb`` (:func:`tonemap`) and write it as a PNG, one pixel per texel.

    ``upscale`` > 1 repeats each pixel that many times (nearest neighbour) so tiny maps stay crisp
    when the browser enlarges them.
    """
    from PIL import Image

    img = tonemap(rgb, exposure)
    if upscale > 1:
        img = np.repeat(np.repeat(img, upscale, axis=0), upscale, axis=1)
    with atomic_path(path, suffix=".png") as tmp:
        # optimize=True took 5x the time of zlib level 6 for the same bytes (measured: the 130 tone-mapped images of
        # a full report, 2.15 s against 0.43 s, 1.7 MB either way)
        Image.fromarray(img, mode="RGB").save(tmp, format="PNG", compress_level=PNG_COMPRESS_LEVEL)


def save_image_grid(path: str | os.PathLike[str], images: Sequence[np.ndarray], titles: Sequence[str],
                    exposure: float | None = None, columns: int | None = None) -> None:
    """Write :func:`image_grid_figure` as a PNG."""
    try:
        fig = image_grid_figure(images, titles, exposure, columns)
    except ValidateError as exc:
        raise ValidateError(f"{os.fspath(path)}: {exc}") from None
    _save_figure(path, fig)


def image_grid_figure(images: Sequence[np.ndarray], titles: Sequence[str], exposure: float | None = None,
                      columns: int | None = None) -> Figure:
    """Images side by side with titles, all tone-mapped with one exposure (auto: from the first image,
    by convention the reference, so the panels are comparable); ``columns`` panels a row (default: one row).

    Fixed layout: each image gets a cell of p × (p·h/w + 0.45) in, p = min(2.6, 12/columns), with 0.3 in
    for its title; all panels are drawn on one invisible axes (:func:`_panel_canvas`)."""
    if not images or len(images) != len(titles):
        raise ValidateError(f"{len(images)} images for {len(titles)} titles; "
                            "expected one title per image and at least one image")
    k = auto_exposure(images[0]) if exposure is None else exposure
    tonemapped = [tonemap(im, k) for im in images]
    h, w = tonemapped[0].shape[:2]
    n = len(images)
    cols = n if columns is None else max(1, min(n, columns))
    rows = -(-n // cols)
    panel_w = min(2.6, 12.0 / cols)
    cell_h = panel_w * h / w + 0.45
    width, height = panel_w * cols, rows * cell_h
    fig = _new_figure((width, height), layout=None)
    ax = _panel_canvas(fig, width, height)
    fontsize = 9 if cols <= 6 else 8
    for i in range(n):
        r, c = divmod(i, cols)
        box = _panel_box(c * panel_w, height - (r + 1) * cell_h, panel_w, cell_h, 0.3, h / w)
        _draw_panel(ax, tonemapped[i], box, titles[i], fontsize)
    ax.set_xlim(0.0, width)
    ax.set_ylim(0.0, height)
    return fig


def save_heatmap_grid(path: str | os.PathLike[str], maps: Sequence[np.ndarray], titles: Sequence[str], label: str,
                      vmax: float | None = None, percent: bool = False, cmap: str = "magma",
                      columns: int = 6) -> None:
    """Write :func:`heatmap_grid_figure` as a PNG."""
    try:
        fig = heatmap_grid_figure(maps, titles, label, vmax, percent, cmap, columns)
    except ValidateError as exc:
        raise ValidateError(f"{os.fspath(path)}: {exc}") from None
    _save_figure(path, fig)


def heatmap_grid_figure(maps: Sequence[np.ndarray], titles: Sequence[str], label: str, vmax: float | None = None,
                        percent: bool = False, cmap: str = "magma", columns: int = 6) -> Figure:
    """Non-negative scalar maps as small multiples on one colour scale [0, vmax] (default: the largest finite
    value), one shared colour bar labelled ``label``; NaN pixels masked. Up to ``columns`` panels a row.

    Fixed layout: each map gets a cell of 1.9 × (1.9·h/w + 0.35) in with 0.25 in for its title, all drawn on
    one invisible axes (:func:`_panel_canvas`); the colour bar sits in the 0.9 in right of the grid."""
    import matplotlib

    if not maps or len(maps) != len(titles):
        raise ValidateError(f"{len(maps)} maps for {len(titles)} titles; "
                            "expected one title per map and at least one map")
    vs = [np.asarray(m, dtype=np.float64) for m in maps]
    finite = [v[np.isfinite(v)] for v in vs]
    if vmax is None:
        vmax = max((float(f.max()) for f in finite if f.size), default=1.0)
    if not (np.isfinite(vmax) and vmax > 0.0):
        vmax = 1.0
    colours = matplotlib.colormaps[cmap].with_extremes(bad=MASK_COLOUR)
    n = len(vs)
    cols = min(n, columns)
    rows = -(-n // cols)
    h, w = vs[0].shape[:2]
    panel = 1.9
    cell_h = panel * h / w + 0.35
    grid_w, height = panel * cols, rows * cell_h
    width = grid_w + 0.9
    fig = _new_figure((width, height), layout=None)
    ax = _panel_canvas(fig, width, height)
    norm = Normalize(vmin=0.0, vmax=vmax)  # one colour scale for every panel and the bar
    im = None
    for k in range(n):
        r, c = divmod(k, cols)
        box = _panel_box(c * panel, height - (r + 1) * cell_h, panel, cell_h, 0.25, h / w)
        im = _draw_panel(ax, np.ma.masked_invalid(vs[k]), box, titles[k], 8, cmap=colours, norm=norm)
    ax.set_xlim(0.0, width)
    ax.set_ylim(0.0, height)
    # The shared colour bar: 0.9 of the grid's height, centred, 0.12 in wide, 0.08 in right of the grid
    # (the remaining ≈ 0.7 in hold its tick labels and its label).
    bar_h = 0.9 * (height - 0.1)
    cax = fig.add_axes(((grid_w + 0.08) / width, 0.5 * (1.0 - bar_h / height), 0.12 / width, bar_h / height))
    cbar = fig.colorbar(im, cax=cax)
    cbar.set_label(label, fontsize=9)
    cbar.ax.tick_params(labelsize=8)
    if percent:
        cbar.ax.yaxis.set_major_formatter(FuncFormatter(_percent_label))
    return fig


def heatmap_size(height: int, width: int) -> tuple[float, float]:
    """Figure size (in) of a heatmap: FIG_SIZE's width; the height fits the map's aspect (≈ 4.1 in of
    image width beside the colour bar, plus ≈ 0.5 in for the title), within [2, 5] in."""
    return FIG_SIZE[0], float(np.clip(round(0.5 + 4.1 * height / width, 1), 2.0, 5.0))


def save_heatmap(path: str | os.PathLike[str], values: np.ndarray, title: str, label: str,
                 vmax: float | None = None, percent: bool = False, cmap: str = "magma") -> None:
    """Write :func:`heatmap_figure` as a PNG."""
    _save_figure(path, heatmap_figure(values, title, label, vmax, percent, cmap))


def heatmap_figure(values: np.ndarray, title: str, label: str, vmax: float | None = None,
                   percent: bool = False, cmap: str = "magma") -> Figure:
    """Scalar map (H, W) with a colour bar labelled ``label``; NaN pixels are masked (light grey).

    The figure is FIG_SIZE wide, its height follows the map's aspect (:func:`heatmap_size`).
    The colour range is [0, vmax] for non-negative data and [−vmax, vmax] when some value is negative
    (then the default cmap becomes the diverging "RdBu_r" so zero sits at white); vmax defaults to
    max |value|. ``percent`` shows the colour-bar ticks as per cent of fraction values (0.01 → 1 %).
    """
    import matplotlib

    v = np.asarray(values, dtype=np.float64)
    if v.ndim != 2 or v.size == 0:
        raise ValidateError(f"heatmap {title!r}: values of shape {v.shape}; expected (H, W)")
    finite = np.isfinite(v)
    signed = bool(finite.any() and np.min(v[finite]) < 0.0)
    if vmax is None:
        vmax = float(np.max(np.abs(v[finite]))) if finite.any() else 1.0
    if not (np.isfinite(vmax) and vmax > 0.0):
        vmax = 1.0
    if signed and cmap == "magma":
        cmap = "RdBu_r"
    colours = matplotlib.colormaps[cmap].with_extremes(bad=MASK_COLOUR)

    # Fixed layout (no constrained-layout pass): the map in a 4.05 in wide box 0.05 in from the left and
    # bottom edges, 0.33 in left above it for the title, ≈ 0.9 in right of it for the colour bar, its tick
    # labels and its label; imshow's equal aspect shrinks the box to the map, centred.
    fig_w, fig_h = heatmap_size(*v.shape)
    fig = _new_figure((fig_w, fig_h), layout=None)
    ax = fig.add_axes((0.05 / fig_w, 0.05 / fig_h, 4.05 / fig_w, (fig_h - 0.38) / fig_h))
    im = ax.imshow(np.ma.masked_invalid(v), cmap=colours, vmin=-vmax if signed else 0.0, vmax=vmax,
                   interpolation="nearest")
    ax.set_title(title, fontsize=10)
    ax.set_xticks([])
    ax.set_yticks([])
    # The colour bar sits in an inset beside the image so that it is exactly as tall as the map.
    cbar = fig.colorbar(im, cax=ax.inset_axes((1.03, 0.0, 0.04, 1.0)))
    cbar.set_label(label, fontsize=9)
    cbar.ax.tick_params(labelsize=8)
    if percent:
        cbar.ax.yaxis.set_major_formatter(FuncFormatter(_percent_label))
    return fig


def _percent_label(value: float, _pos: object = None) -> str:
    """Tick label of a fraction as per cent with up to 3 significant digits: 0.025 → "2.5%",
    0.2 → "20%", 1e-6 → "1e-4%" (matplotlib's PercentFormatter rounds small log-axis ticks to "0%")."""
    if value == 0.0:
        return "0%"
    text = f"{value * 100.0:.3g}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}e{int(exponent)}"
    return text.replace("-", "\u2212") + "%"


def _plain_log_ticks(axis: Axis, values: np.ndarray) -> None:
    """Log axis labelled with plain numbers (2, 8, 32 rather than 10⁰, 10¹); a sweep spanning less than
    two decades gets a tick at each sample."""
    pos = values[np.isfinite(values) & (values > 0)]
    if pos.size and pos.max() / pos.min() < 100.0 and np.unique(pos).size <= 12:
        axis.set_ticks(np.unique(pos))
        axis.set_minor_formatter(NullFormatter())
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))


def save_line_plot(path: str | os.PathLike[str], x: np.ndarray | Sequence[float],
                   series: Mapping[str, np.ndarray | Sequence[float]], xlabel: str, ylabel: str, title: str,
                   logx: bool = False, logy: bool = False, hlines: Mapping[str, float] | None = None,
                   percent: bool = False) -> None:
    """Write :func:`line_plot_figure` as a PNG."""
    _save_figure(path, line_plot_figure(x, series, xlabel, ylabel, title, logx, logy, hlines, percent))


def line_plot_figure(x: np.ndarray | Sequence[float], series: Mapping[str, np.ndarray | Sequence[float]],
                     xlabel: str, ylabel: str, title: str, logx: bool = False, logy: bool = False,
                     hlines: Mapping[str, float] | None = None, percent: bool = False) -> Figure:
    """FIG_SIZE plot: one line with markers per series (NaN values leave gaps), legend, grid; ``hlines``
    draws dashed horizontal reference lines (label → y); ``percent`` shows the y axis as per cent of
    fractions (0.01 → 1 %)."""
    xs = np.asarray(x, dtype=np.float64)
    if xs.ndim != 1 or xs.size == 0:
        raise ValidateError(f"line plot {title!r}: x of shape {xs.shape}; expected a non-empty 1-D array")
    fig = _new_figure(FIG_SIZE)
    ax = fig.add_subplot()
    for i, (name, ys) in enumerate(series.items()):
        y = np.asarray(ys, dtype=np.float64)
        if y.shape != xs.shape:
            raise ValidateError(f"line plot {title!r}: series {name!r} has shape {y.shape}; x has {xs.shape}")
        ax.plot(xs, y, marker=_MARKERS[i % len(_MARKERS)], markersize=4, linewidth=1.5, label=name)
    for i, (name, level) in enumerate((hlines or {}).items()):
        ax.axhline(level, linestyle="--", linewidth=1.0, color=_HLINE_COLOURS[i % len(_HLINE_COLOURS)],
                   label=name)
    if logx:
        ax.set_xscale("log")
        _plain_log_ticks(ax.xaxis, xs)
    if logy:
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    if percent:
        ax.yaxis.set_major_formatter(FuncFormatter(_percent_label))
        if logy:
            ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel(xlabel, fontsize=9)
    ax.set_ylabel(ylabel, fontsize=9)
    ax.set_title(title, fontsize=10)
    ax.tick_params(labelsize=8)
    ax.grid(True, which="major", alpha=0.35)
    if logx or logy:
        ax.grid(True, which="minor", alpha=0.12)
    if series or hlines:
        ax.legend(fontsize=8, framealpha=0.85)
    return fig

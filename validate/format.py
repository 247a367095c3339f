"""Numbers written for their meaning: per cent, value ± uncertainty, significant digits, units.

The ground floor (imports nothing of the project but :mod:`validate.errors`), used by every page of
the report and, after the experiments switch to it, by every finding.

Rules
-----
* **Significant digits** (:func:`sig`): ``n`` significant digits, trailing zeros dropped as ``%g``
  does; plain notation for 10⁻³ ≤ |x| < 10⁶, otherwise ``1.23e-5`` (no "+", no leading zeros in
  the exponent). None → "—", NaN → "NaN", ±∞ → "∞" / "−∞".
* **Uncertainty** (:func:`pm`): σ keeps 2 significant digits when its leading three digits are
  100–354 and 1 for 355–949 — the Particle Data Group rounding rule [1]; 950–999 rounds up to
  1000 and keeps two (0.0097 → 0.010). The value is rounded to the same decimal
  place as σ, so it never shows more digits than σ supports [2, §7.2.6]. Trailing zeros are kept
  (1.20 ± 0.07: the zero is significant). A σ of 0 or None prints the value alone (a deterministic
  figure) with :data:`DEFAULT_DIGITS` significant digits.
* **Per cent**: ``unit="%"`` marks a *fraction* shown as per cent (0.0086 → "0.86 %"): value and σ
  are multiplied by 100 before rounding; ``scale`` multiplies both for any other display unit.
* **Scientific**: when σ's decimal place is below 10⁻⁴, or |value| ≥ 10⁶, value and σ share one
  exponent: "(2.3 ± 1.1)e-6".
* **Units on every column** (:func:`col`, :func:`missing_units`): a table header ends with its unit,
  one of :data:`UNITS`, in parentheses ("max |z| (–)", "E (W/m²)"); a column of words is one of
  :data:`LABEL_COLUMNS` (any case: "Technique") or asks a question ("linear?"). A table whose rows differ in
  unit (the claims: "%" or "–") has a "Unit" column, and its numeric headers end with "(unit)":
  "Threshold (unit)" reads "in the row's unit, shown in the Unit column" (:data:`ROW_UNIT`).

References
----------
[1] Particle Data Group, "Review of Particle Physics", Introduction §5.3 (rounding of errors).
[2] JCGM 100:2008, "Guide to the expression of uncertainty in measurement" (GUM), §7.2.6.
"""

from __future__ import annotations

import math
from numbers import Integral, Real
from typing import Any

from .errors import ValidateError

DEFAULT_DIGITS = 3  # significant digits of a value without an uncertainty
PLAIN_MIN, PLAIN_MAX = 1e-3, 1e6  # |x| outside [PLAIN_MIN, PLAIN_MAX) is written 1.23e-5
SCI_DECIMALS = 4  # σ rounded below the 10⁻⁴ place → shared exponent "(a ± b)e-n"
PDG_TWO_DIGITS = 354  # σ whose leading three digits are ≤ 354 keeps two significant digits [1]
PDG_ROUND_UP = 950  # … 355–949 keeps one; 950–999 rounds up to 1000 and keeps two [1]
DASH = "—"


def _number(x: Any) -> float | None:
    """A finite-or-not float for a real number; None for anything else (None, text, bool)."""
    if isinstance(x, bool) or not isinstance(x, Real):
        return None
    return float(x)


def _special(v: float) -> str | None:
    if math.isnan(v):
        return "NaN"
    if math.isinf(v):
        return "∞" if v > 0 else "−∞"
    return None


def _exponent(v: float) -> int:
    """Decimal exponent of |v| > 0: floor(log10 |v|), robust to log10 rounding at powers of ten."""
    e = math.floor(math.log10(abs(v)))
    if abs(v) >= 10.0 ** (e + 1):
        e += 1
    return e


def _sci(v: float, n: int) -> str:
    mantissa, exponent = f"{v:.{max(n - 1, 0)}e}".split("e")
    if "." in mantissa:
        mantissa = mantissa.rstrip("0").rstrip(".")
    return f"{mantissa}e{int(exponent)}"


def sig(x: Any, n: int = DEFAULT_DIGITS) -> str:
    """``x`` with ``n`` significant digits: sig(0.012345, 2) → "0.012", sig(1.234e-5, 3) → "1.23e-5",
    sig(2.5e7, 3) → "2.5e7", sig(1234.4, 3) → "1234" (integers up to 10⁶ are not rounded away).
    Integers are written in full; None → "—"; text is returned as it is."""
    if x is None:
        return DASH
    if isinstance(x, Integral) and not isinstance(x, bool):
        return str(int(x))
    v = _number(x)
    if v is None:
        return str(x)
    if (s := _special(v)) is not None:
        return s
    if v == 0.0:
        return "0"
    r = float(f"{v:.{n}g}")  # rounded first: 999.9 → 1000 is plain, not "1e3"
    if not PLAIN_MIN <= abs(r) < PLAIN_MAX:
        return _sci(v, n)
    s = f"{v:.{max(n - 1 - _exponent(r), 0)}f}"
    return s.rstrip("0").rstrip(".") if "." in s else s


def pct(x: Any, digits: int = DEFAULT_DIGITS) -> str:
    """A fraction as per cent with ``digits`` significant digits: pct(0.0086) → "0.86 %",
    pct(0.01) → "1 %", pct(0.125, 2) → "12 %"; None / NaN → "—" (drop-in for the experiments' pct)."""
    v = _number(x)
    if v is None or math.isnan(v):
        return DASH
    return f"{sig(v * 100.0, digits)} %"


def pct_fixed(x: Any, digits: int = 2) -> str:
    """A fraction as per cent with ``digits`` decimals: pct_fixed(0.0086) → "0.86 %"; None / NaN → "n/a"
    (drop-in for the experiments' pct_fixed)."""
    v = _number(x)
    if v is None or not math.isfinite(v):
        return "n/a"
    return f"{100.0 * v:.{digits}f} %"


def _sigma_place(sigma: float) -> tuple[int, int]:
    """(significant digits, decimal exponent of the leading digit) of σ > 0 rounded by the PDG rule [1]
    on its leading three digits: 100–354 → two digits, 355–949 → one, 950–999 → up to 1000, two."""
    mantissa, exponent = f"{sigma:.2e}".split("e")  # decimal digits as printed: no 0.95 → 0.9499…
    lead3, e = round(float(mantissa) * 100), int(exponent)
    if lead3 <= PDG_TWO_DIGITS:
        return 2, e
    if lead3 < PDG_ROUND_UP:
        return 1, e
    return 2, e + 1


def round_sigma(sigma: float) -> float:
    """σ > 0 rounded to the digits :func:`sigma_digits` keeps: 0.00067 → 0.0007, 0.95 → 1.0."""
    n, e = _sigma_place(sigma)
    if e > _exponent(sigma):  # rounded up to the next decade
        return 10.0 ** e
    return float(f"{sigma:.{n - 1}e}")


def sigma_digits(sigma: float) -> int:
    """Significant digits shown of an uncertainty σ > 0: 2 when its leading three digits are 100–354,
    1 for 355–949, and 2 for 950–999, which round up to 1000 [1]."""
    return _sigma_place(sigma)[0]


def decimals_for(sigma: float) -> int:
    """Decimal place (digits after the point; negative = tens, hundreds) to which σ > 0 and its value
    are rounded: that of σ's last significant digit under :func:`sigma_digits`."""
    n, e = _sigma_place(sigma)
    return n - 1 - e


def _fixed(v: float, decimals: int) -> str:
    if decimals > 0:
        return f"{v:.{decimals}f}"
    step = 10.0 ** (-decimals)
    return f"{round(v / step) * step:.0f}"


def _unit_suffix(unit: str) -> str:
    return f" {unit}" if unit else ""


def pm(value: Any, sigma: Any, unit: str = "", scale: float = 1.0) -> str:
    """"value ± σ unit" with σ rounded by :func:`sigma_digits` and the value to σ's decimal:
    pm(0.012345, 0.00067, "%") → "1.23 ± 0.07 %"; pm(9.87654, 0.0234) → "9.877 ± 0.023";
    pm(2.3e-6, 1.1e-6) → "(2.3 ± 1.1)e-6"; pm(0.5, 0) → "0.5". ``unit="%"`` shows fractions as per
    cent (×100); ``scale`` multiplies value and σ for other display units. A negative σ is an error."""
    k = float(scale) * (100.0 if unit == "%" else 1.0)
    v, s = _number(value), _number(sigma)
    if v is None or math.isnan(v) or math.isinf(v):
        return sig(value if v is None else v * k) + _unit_suffix(unit) * (v is not None)
    if s is None or s == 0.0:
        return sig(v * k) + _unit_suffix(unit)
    if math.isnan(s) or s < 0.0:
        raise ValidateError(f"uncertainty {sigma!r} of value {value!r}: expected a number ≥ 0")
    if math.isinf(s):
        return f"{sig(v * k)} ± ∞{_unit_suffix(unit)}"
    v, s = v * k, s * k
    d = decimals_for(s)
    if d > SCI_DECIMALS or abs(v) >= PLAIN_MAX:
        e = _exponent(v) if v != 0.0 and abs(v) >= abs(s) else _exponent(s)
        m = 10.0 ** e
        dm = decimals_for(s / m)
        body = f"{_fixed(v / m, dm)} ± {_fixed(round_sigma(s / m), dm)}"
        return (body if e == 0 else f"({body})e{e}") + _unit_suffix(unit)
    return f"{_fixed(v, d)} ± {_fixed(round_sigma(s), d)}{_unit_suffix(unit)}"


def fmt_quantity(value: Any, unit: str = "", sigma: Any = None, digits: int = DEFAULT_DIGITS,
                 scale: float = 1.0) -> str:
    """One quantity with its unit: with a σ > 0 → :func:`pm`; otherwise ``digits`` significant digits
    ("%" → :func:`pct`; another unit appended: "0.5 sr"); None → "—" (no unit)."""
    if _number(sigma) not in (None, 0.0):
        return pm(value, sigma, unit, scale)
    v = _number(value)
    if v is None:
        return sig(value, digits)
    if unit == "%":
        return pct(v * scale, digits)
    return sig(v * scale, digits) + _unit_suffix(unit)


# --- table column headers -------------------------------------------------------------------------------------
# Every column of a report table says what its numbers are in: the header ends with its unit in parentheses,
# "max |z| (–)", "β (°)", "E (W/m²)", written by :func:`col`; a column of words carries none: names and verdicts
# (:data:`LABEL_COLUMNS`), or the answers to a header that asks a question ("faces > 65504?").
# :func:`missing_units` finds the headers that do neither (``tests/infra/test_table_units.py`` checks every table
# the experiments build).
#
# Radiometric units take the emitters' and the environment maps' values as radiance in W·m⁻²·sr⁻¹ (Mitsuba's
# convention: it renders radiance and integrates it over solid angle and area, so irradiance is in W/m²).
UNITS = frozenset({
    "%",          # a fraction shown as per cent (0.0086 → "0.86 %"), relative errors included
    "–",          # a dimensionless number shown as it is: z scores, p-values, χ²/d.o.f., a ratio such as E′/E
    "×",          # a factor that multiplies (a scale, a ratio written "1.02×")
    "°",          # an angle in degrees
    "m",          # a length in metres
    "px",         # pixels (a length or an area in pixels, or a count of them)
    "texels",     # the side of a texture (shadow map, cube face, lat-long map) in texels
    "s",          # seconds
    "ms",         # milliseconds
    "µs",         # microseconds
    "ns",         # nanoseconds
    "B",          # bytes
    "MiB",        # mebibytes (2²⁰ B)
    "count",      # a number of things (samples per normal, receivers, texels over a limit)
    "W/m²",       # irradiance
    "W/(m²·sr)",  # radiance
    "W/sr",       # radiant intensity
    "sr⁻¹",       # a BRDF value or a lobe's density over solid angle
    "sr",         # a solid angle
    "sr⁻²",       # a squared density over solid angle integrated over it: the LTC fit's ∫ |E·D − f cos|³ dω
    "lm",         # lumens: luminous flux (an engine light's `.power`, three.js)
})
# Columns that hold words, not quantities: names of things and verdicts.
LABEL_COLUMNS = frozenset({
    "technique", "environment", "light", "model", "scene", "shape", "side", "check", "case", "result", "status",
    "listing", "section", "file", "engine", "reference", "method", "metric", "setting", "step", "comparison",
    "kind", "probe", "seed", "reading", "BSDF", "parameter", "material", "pixel set",
    "power check", "table row",
    # the report's own pages (validate/report/): claims, techniques, settings, overview, changes; the bench tables
    "experiment", "title", "claim", "description", "family", "origin", "key", "unit",
    "task", "map", "fit", "data", "runtime", "renderer", "experiment uses",
    # the blender experiment: the importer's mode, the film's precision (words), and a light as glTF and Blender
    # store it, each cell with its own unit ("3 lx", "37.6991 W")
    "mode", "precision", "glTF", "Blender",
})
ROW_UNIT = "unit"  # "Threshold (unit)": in each row's own unit, which the table's "Unit" column shows


def col(name: str, unit: str) -> str:
    """A table column header: ``name`` and its ``unit`` (one of :data:`UNITS`) in parentheses:
    col("max |z|", "–") → "max |z| (–)". An empty or unknown unit is a :class:`ValidateError`."""
    if unit not in UNITS:
        raise ValidateError(f"table column {name!r}: unit {unit!r} is not one of {', '.join(sorted(UNITS))}")
    return f"{name} ({unit})"


def header_unit(header: str) -> str | None:
    """The unit a column header ends with; "" for a column of words: one of :data:`LABEL_COLUMNS`, or a question
    ("faces > 65504?") whose cells answer it; None otherwise (no final parentheses, or parentheses that hold no
    unit of :data:`UNITS`: "E (red)")."""
    h = header.strip()
    if h.casefold() in _LABELS or h.endswith("?"):
        return ""
    return next((u for u in UNITS if h.endswith(f" ({u})")), None)


_LABELS = frozenset(label.casefold() for label in LABEL_COLUMNS)


def missing_units(headers: list[str]) -> list[str]:
    """The headers of a table that name no unit (see :func:`header_unit`), in order. A header ending
    "(unit)" (:data:`ROW_UNIT`: each row in its own unit) names one only when the table has a "Unit" column."""
    row_unit = any(str(h).strip().casefold() == ROW_UNIT for h in headers)
    return [h for h in headers if header_unit(str(h)) is None
            and not (row_unit and str(h).strip().endswith(f" ({ROW_UNIT})"))]

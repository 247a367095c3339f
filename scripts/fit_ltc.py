"""Fit the GGX LTC table (Heitz, Dupuy, Hill, Neubelt 2016 §4) and write validate/local_models/data/ltc_ggx.npz.

Usage: .venv/bin/python scripts/fit_ltc.py [--size 16] [--out PATH] [--method scipy|ad]

Per (roughness r = √α, cos θ_v) on :func:`validate.local_models.specular_arealight.ltc.table_axes`, rows from
r = 1 down to r = 0 (each entry started from the rougher neighbour's solution, as the paper's code does), fit
M by Nelder–Mead (:func:`validate.local_models.specular_arealight.ltc.fit_entry`; ``--method ad``: by drjit
gradients, :func:`~validate.local_models.specular_arealight.ltc.fit_entry_ad` — not the shipped table's path:
on 64 entries it matches Nelder–Mead to 10⁻¹¹ except at α = 10⁻³, where it lands up to 0.5 % above or below,
in twice the time; ``python -m validate bench --only fits``); prints the fit error
∫ |E·D − f cos| dω / E
(mean, max, where).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from validate.local_models.specular_arealight import ltc  # noqa: E402


def fit_table(size: int, method: str = "scipy") -> list[list[ltc.Entry]]:
    r, mus = ltc.table_axes(size)
    rows: list[list[ltc.Entry] | None] = [None] * size
    prev: list[ltc.Entry] | None = None
    for i in range(size - 1, -1, -1):
        row = []
        for j, mu in enumerate(mus):
            init = prev[j].params if prev is not None else None
            prob = ltc.fit_problem(float(mu), ltc.alpha_of(float(r[i])), init)
            row.append(ltc.fit_entry_ad(prob) if method == "ad" else ltc.fit_entry_scipy(prob))
        rows[i] = prev = row
        print(f"r = {r[i]:.3f}: L1 max {max(e.l1_error for e in row):.4f}", flush=True)
    return [x for x in rows if x is not None]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--size", type=int, default=16)
    ap.add_argument("--out", default=str(ltc.DATA))
    ap.add_argument("--method", choices=("scipy", "ad"), default="scipy",
                    help="Nelder-Mead (the shipped table) or L-BFGS-B/BFGS with drjit gradients")
    a = ap.parse_args()
    t0 = time.time()
    arrays = ltc.pack(fit_table(a.size, a.method))
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(a.out, **arrays)
    err = arrays["l1_error"]
    i, j = np.unravel_index(np.argmax(err), err.shape)
    r, mus = ltc.table_axes(a.size)
    print(f"wrote {a.out}: {a.size}×{a.size}, fit error ∫|E·D − f cos|/E mean {err.mean():.4f}, max {err.max():.4f} "
          f"at r = {r[i]:.3f}, cos θ_v = {mus[j]:.4f}; {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()

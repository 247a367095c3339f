"""``python -m validate export``: every table as CSV (read back with the csv module) and LaTeX (compiled when a
TeX engine is on PATH), the summary figures as PDF/SVG, provenance; bad input is one line, exit 2, nothing
written. Input: the committed ``docs/results.json`` (no Mitsuba work; a few seconds)."""

from __future__ import annotations

import copy
import csv
import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

from validate.cli import main
from validate.format import header_unit, missing_units
from validate.report import export

REPO = Path(__file__).resolve().parents[2]
RESULTS = REPO / "docs" / "results.json"


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("export") / "out"
    assert main(["export", str(RESULTS), "--to", str(out), "--format", "csv,latex"]) == 0
    return out


def _read_csv(path: Path) -> list[dict[str, str]]:
    with path.open(encoding="utf-8", newline="") as f:
        return list(csv.DictReader(f))


def test_every_table_is_a_csv_with_units_and_separate_uncertainties(exported: Path) -> None:
    results = json.loads(RESULTS.read_text(encoding="utf-8"))
    manifest = json.loads((exported / export.MANIFEST).read_text(encoding="utf-8"))
    page_tables = sum(1 for e in results["experiments"].values() for s in (e.get("report") or {}).get("sections") or []
                      for t in s.get("tables") or [] if t.get("rows"))
    from_pages = [t for t in manifest["tables"] if ".report.sections[" in t["source"]]
    assert len(from_pages) == page_tables
    assert {t["experiment"] for t in manifest["tables"] if t["source"].endswith(".claims")} == {
        n for n, e in results["experiments"].items() if e.get("claims")}
    for t in manifest["tables"]:
        path = exported / next(f for f in t["files"] if f.endswith(".csv"))
        with path.open(encoding="utf-8", newline="") as f:
            rows = list(csv.reader(f))
        assert len(rows) == t["rows"] + 1, path
        head = rows[0]
        assert missing_units(head) == [], f"{path}: {missing_units(head)}"
        for i, h in enumerate(head):  # a "X ± (u)" column is numbers and follows its "X (u)" column
            if " ± (" in h:
                assert head[i - 1] == h.replace(" ± (", " ("), path
                assert all(r[i] == "" or float(r[i]) >= 0.0 for r in rows[1:]), path


def test_claims_csv_holds_the_stored_numbers(exported: Path) -> None:
    results = json.loads(RESULTS.read_text(encoding="utf-8"))
    claim = results["experiments"]["sh9"]["claims"][0]
    rows = {r["claim"]: r for r in _read_csv(exported / "tables" / "sh9" / "claims.csv")}
    row = rows[claim["id"]]
    k = 100.0 if claim.get("unit") == "%" else 1.0
    assert float(row["measured (unit)"]) == pytest.approx(claim["measured"] * k, rel=1e-12)
    assert float(row["measured ± (unit)"] or 0.0) == pytest.approx((claim.get("uncertainty") or 0.0) * k, abs=1e-15)
    assert row["result"] == ("pass" if claim["passed"] else "fail")


def test_technique_metrics_csv_has_every_measured_value(exported: Path) -> None:
    from validate.report.compare import metrics_of

    results = json.loads(RESULTS.read_text(encoding="utf-8"))
    n = sum(k.startswith("sh9/") for k in metrics_of(results))
    rows = _read_csv(exported / "tables" / "sh9" / "techniques.csv")
    assert len(rows) == n > 0
    assert header_unit("value ± (unit)") is None  # the row's unit: named by the table's "unit" column
    assert all(r["unit"] for r in rows)


def test_cells_written_for_reading_come_back_as_numbers() -> None:
    assert export.parse_cell("0.947 % ± 0.00323 %") == (0.947, 0.00323)
    assert export.parse_cell("9.375 %") == (9.375, None)
    assert export.parse_cell("(2.3 ± 1.1)e-6") == (pytest.approx(2.3e-6), pytest.approx(1.1e-6))
    assert export.parse_cell("−0.5") == (-0.5, None)
    assert export.parse_cell("—") == (None, None)
    assert export.parse_cell("sh9") is None
    assert export.latex_number(0.947, 0.00323) == "$0.9470 \\pm 0.0032$"  # σ's digits, PDG rounding
    assert export.latex_number(2.3e-6, 1.1e-6) == "$(2.3 \\pm 1.1)\\times 10^{-6}$"
    assert export.latex_number(29.687511, 3.5e-7) == "$29.68751100 \\pm 0.00000035$"


def _tex_engine() -> str | None:
    return next((e for e in ("pdflatex", "lualatex", "xelatex") if shutil.which(e)), None)


def test_one_latex_table_compiles(exported: Path, tmp_path: Path) -> None:
    tex = exported / "tables" / "worstcase" / "claims.tex"
    body = tex.read_text(encoding="utf-8")
    assert "\\toprule" in body and "\\bottomrule" in body and "\\pm" in body
    engine = _tex_engine()
    if engine is None:
        pytest.skip("no TeX engine (pdflatex, lualatex, xelatex) on PATH")
    doc = tmp_path / "table.tex"
    doc.write_text("\\documentclass{article}\n\\usepackage[T1]{fontenc}\n\\usepackage[utf8]{inputenc}\n"
                   "\\usepackage{booktabs}\n\\usepackage{array}\n\\usepackage{longtable}\n\\usepackage{amssymb}\n\\begin{document}\n"
                   f"\\input{{{tex.as_posix()}}}\n\\end{{document}}\n", encoding="utf-8")
    r = subprocess.run([engine, "-interaction=nonstopmode", "-halt-on-error", doc.name], cwd=tmp_path,
                       capture_output=True, text=True, timeout=120, check=False)
    assert r.returncode == 0, r.stdout[-3000:]
    assert (tmp_path / "table.pdf").is_file()


def test_summary_figures_leave_as_vector_and_provenance_is_written(tmp_path: Path) -> None:
    results = json.loads(RESULTS.read_text(encoding="utf-8"))
    small = copy.deepcopy(results)
    small["experiments"] = {"sh9": results["experiments"]["sh9"]}
    src = tmp_path / "run" / "results.json"
    src.parent.mkdir()
    src.write_text(json.dumps(small), encoding="utf-8")
    out = tmp_path / "out"
    assert main(["export", str(src), "--to", str(out), "--format", "pdf,svg"]) == 0
    assert (out / "figures" / "summary" / "exp-sh9.pdf").read_bytes().startswith(b"%PDF")
    assert b"<svg" in (out / "figures" / "summary" / "exp-sh9.svg").read_bytes()[:2000]
    assert not list(out.rglob("*.csv"))  # only the formats asked for
    prov = json.loads((out / export.PROVENANCE).read_text(encoding="utf-8"))
    assert prov["versions"] == results["meta"]["versions"]
    assert prov["backend"] == results["meta"].get("backend")
    assert prov["variant"] == results["meta"]["variant"]
    assert prov["command"] == results["meta"]["command"]
    assert "export" in prov["export"]["command"] and prov["export"]["date"]
    assert "commit" in prov and (prov["commit"] is None or len(prov["commit"]) == 40)
    assert not [p for p in out.rglob(".export-*")]  # the staging folder is gone


@pytest.mark.parametrize("case", ["missing", "not_results", "unwritable", "bad_format"])
def test_bad_input_is_one_line_exit_2_nothing_written(case: str, tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    src, out, fmt = RESULTS, tmp_path / "out", "csv"
    if case == "missing":
        src = tmp_path / "nope.json"
    elif case == "not_results":
        src = tmp_path / "x.json"
        src.write_text('{"hello": 1}', encoding="utf-8")
    elif case == "unwritable":
        if os.geteuid() == 0:
            out = tmp_path / "file"
            out.write_text("a file, not a folder", encoding="utf-8")
        else:
            locked = tmp_path / "locked"
            locked.mkdir(mode=0o500)
            out = locked / "out"
    else:
        fmt = "csv,docx"
    before = sorted(p.name for p in tmp_path.rglob("*"))
    assert main(["export", str(src), "--to", str(out), "--format", fmt]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("validate: error: "), err
    assert sorted(p.name for p in tmp_path.rglob("*")) == before

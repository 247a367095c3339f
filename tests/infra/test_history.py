"""``python -m validate history``: three runs, the second with one technique metric 2 % worse (beyond its
uncertainty) → that metric's plot exists and the regression is marked in the CSV and the page; the third
run, back to the first value, is an improvement. Input: copies of ``docs/results.json`` (about two seconds)."""

from __future__ import annotations

import copy
import csv
import json
from pathlib import Path

import pytest

from validate.cli import main
from validate.report import history

REPO = Path(__file__).resolve().parents[2]
RESULTS = REPO / "docs" / "results.json"
WORSE = 1.02  # the plug-in made 2 % worse in the second run


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> tuple[list[Path], str]:
    base = json.loads(RESULTS.read_text(encoding="utf-8"))
    metrics = base["experiments"]["sh9"]["techniques"]["sh9"]["metrics"]
    # an environment whose max error is known to better than 0.5 %: a 2 % change is beyond σ
    env = next(e for e, m in metrics.items()
               if m["flux_luminance"]["max"]["uncertainty"] < 0.005 * m["flux_luminance"]["max"]["value"])
    root = tmp_path_factory.mktemp("history")
    paths = []
    for i, factor in enumerate((1.0, WORSE, 1.0)):
        r = copy.deepcopy(base)
        r["meta"]["generated"] = f"2026-01-0{i + 1}T12:00:00+00:00"
        r["experiments"]["sh9"]["techniques"]["sh9"]["metrics"][env]["flux_luminance"]["max"]["value"] *= factor
        p = root / f"run{i + 1}" / "results.json"
        p.parent.mkdir()
        p.write_text(json.dumps(r), encoding="utf-8")
        paths.append(p)
    return paths, f"sh9/sh9/{env}/flux_luminance/max"


def test_the_regression_is_plotted_and_marked(runs: tuple[list[Path], str], tmp_path: Path) -> None:
    paths, key = runs
    out = tmp_path / "trend"
    assert main(["history", *map(str, paths), "--out", str(out)]) == 0
    assert (out / history.PLOT_DIR / f"{history._slug(key)}.png").is_file()
    with (out / history.CSV_FILE).open(encoding="utf-8", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["key"] == key]
    assert [r["run"] for r in rows] == ["1", "2", "3"]
    assert [r["status"] for r in rows] == ["", "regressed", "improved"]
    assert [r["regression"] for r in rows] == ["", "yes", ""]
    assert float(rows[1]["value"]) == pytest.approx(WORSE * float(rows[0]["value"]))
    page = (out / history.HTML_FILE).read_text(encoding="utf-8")
    assert "Regressions (1)" in page and key in page and "data:image/png;base64," in page
    assert "src='plots/" not in page and 'src="http' not in page  # self-contained
    unchanged = {r["key"] for r in csv.DictReader((out / history.CSV_FILE).open(encoding="utf-8"))}
    assert unchanged == {key}  # only what changed


def test_a_failing_claim_is_marked(runs: tuple[list[Path], str], tmp_path: Path) -> None:
    paths, _ = runs
    docs = [json.loads(p.read_text(encoding="utf-8")) for p in paths]
    claim = docs[1]["experiments"]["sh9"]["claims"][0]
    claim["passed"], claim["measured"] = False, claim["threshold"] * 2
    h = history.write_history(docs, tmp_path / "t")
    s = next(s for s in h.series if s.kind == "claim")
    assert s.passed == [True, False, True] and s.regressions == [1]


def test_bad_input_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["history", str(RESULTS), str(tmp_path / "missing.json"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "missing.json" in err[0]
    assert not (tmp_path / "o").exists()

"""The measured figures of ``docs/`` cannot drift from the results they were rendered from.

``docs/results.json`` is the committed subset of a ``results.json`` (:func:`validate.report.docs.doc_subset`)
and every generated block of ``docs/**/*.md`` must be exactly what :mod:`validate.report.docs` renders
from it. Claim ids that a page names in its prose (``sh9.paper.<probe>.mean``, ``….{a,b}``) must
match a claim of that results file, and the README's headline row must quote it. No Mitsuba work:
these tests read text files only (well under a second each).
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest

from validate.cli import main
from validate.errors import ValidateError
from validate.report.docs import block_names, fill_blocks, render_doc_blocks, update_docs
from validate.report.html import fmt_measured

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"
RESULTS = DOCS / "results.json"
PARTS = ("claims", "findings", "techniques", "settings")


@pytest.fixture(scope="module")
def results() -> dict:
    return json.loads(RESULTS.read_text(encoding="utf-8"))


def _prose(text: str) -> str:
    """``text`` without its generated blocks (what a person wrote)."""
    return re.sub(r"<!-- results:begin [^>]*-->.*?<!-- results:end -->", "", text, flags=re.S)


def test_committed_blocks_equal_what_the_committed_results_render() -> None:
    assert update_docs(RESULTS, DOCS, check=True) == []


def test_every_experiment_has_a_page_with_every_block(results: dict) -> None:
    for name in results["experiments"]:
        page = DOCS / "experiments" / f"{name}.md"
        assert page.is_file(), f"{page} missing"
        assert sorted(block_names(page.read_text(encoding="utf-8"))) == sorted(f"{name}.{p}" for p in PARTS)


def _pattern(token: str) -> re.Pattern[str]:
    """A prose claim id as a regex: ``<x>`` any dotted segment(s), ``{a,b}`` alternatives, ``…`` anything."""
    out, i = "", 0
    while i < len(token):
        ch = token[i]
        if ch == "<":
            j = token.index(">", i)
            out, i = out + r"[^ ]+?", j + 1
        elif ch == "{":
            j = token.index("}", i)
            out, i = out + "(?:" + "|".join(re.escape(a) for a in token[i + 1:j].split(",")) + ")", j + 1
        elif ch == "…":
            out, i = out + ".*", i + 1
        else:
            out, i = out + re.escape(ch), i + 1
    return re.compile(out)


def test_claim_ids_named_in_the_prose_exist(results: dict) -> None:
    ids = [c["id"] for exp in results["experiments"].values() for c in exp["claims"]]
    prefixes = tuple(f"{n}." for n in results["experiments"]) + ("reference.",)
    checked = 0
    for page in sorted((DOCS / "experiments").glob("*.md")):
        for token in re.findall(r"`([^`\s]+)`", _prose(page.read_text(encoding="utf-8"))):
            if not token.startswith(prefixes) or ".technique." in token or token.endswith((".md", ".py")):
                continue  # technique claims depend on declared thresholds (plug-ins); file names aren't ids
            pattern = _pattern(token)
            assert any(pattern.fullmatch(i) for i in ids), f"{page.name}: `{token}` names no claim in {RESULTS.name}"
            checked += 1
    assert checked > 40  # the pages do name their claims


def test_check_names_the_stale_file_and_a_rerender_fixes_it(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    docs = tmp_path / "docs"
    shutil.copytree(DOCS, docs)
    page = docs / "experiments" / "sh9.md"
    text = page.read_text(encoding="utf-8")
    page.write_text(text.replace("| yes |", "| **no** |", 1), encoding="utf-8")  # a hand edit inside a block
    assert main(["docs", "--results", str(docs / "results.json"), "--docs", str(docs), "--check"]) == 1
    captured = capsys.readouterr()
    assert f"stale: {page}" in captured.out and "differ from" in captured.err
    assert main(["docs", "--results", str(docs / "results.json"), "--docs", str(docs)]) == 0
    assert page.read_text(encoding="utf-8") == text
    assert main(["docs", "--results", str(docs / "results.json"), "--docs", str(docs), "--check"]) == 0


def test_unknown_block_and_missing_results_are_one_line_errors(tmp_path: Path, capsys: pytest.CaptureFixture,
                                                               results: dict) -> None:
    with pytest.raises(ValidateError, match=r"x\.md: unknown results block 'sh10\.claims'"):
        fill_blocks("<!-- results:begin sh10.claims -->\n<!-- results:end -->\n", render_doc_blocks(results), "x.md")
    with pytest.raises(ValidateError, match="has no"):
        fill_blocks("<!-- results:begin sh9.claims -->\n", render_doc_blocks(results), "x.md")
    docs = tmp_path / "docs"
    docs.mkdir()
    assert main(["docs", "--results", str(tmp_path / "none.json"), "--docs", str(docs)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("validate: error: ") and "none.json" in err[0]
    assert not any(docs.iterdir())  # nothing written


def test_readme_headline_row_quotes_the_docs_results(results: dict) -> None:
    kind = "quick" if results["meta"].get("quick") else "full"
    row = next(line for line in (REPO / "README.md").read_text(encoding="utf-8").splitlines()
               if line.startswith(f"| {kind}:"))
    claims = [c for exp in results["experiments"].values() for c in exp["claims"]]
    passed = sum(c["passed"] for c in claims)
    fails = sum(bool(c["power"] and c["power"]["fails"]) for c in claims)
    by_id = {c["id"]: c for c in claims}
    cells = [f"{passed}/{len(claims)}", f"{fails}/{len(claims)}"]
    for probe in ("grace_probe", "rnl_probe"):
        cells.append(" / ".join(fmt_measured(by_id[f"sh9.paper.{probe}.{s}"]) for s in ("mean", "max")))
    assert [c.strip() for c in row.strip("|").split("|")[1:]] == cells


def test_readme_names_every_subcommand_and_option() -> None:
    import argparse

    from validate.cli.commands import _parser

    readme = (REPO / "README.md").read_text(encoding="utf-8")
    sub = next(a for a in _parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name, parser in sub.choices.items():
        assert f"python -m validate {name}" in readme, f"README: no `python -m validate {name}`"
        for action in parser._actions:
            for opt in action.option_strings:
                if opt.startswith("--") and opt != "--help":
                    assert f"`{opt}" in readme or f"[{opt}" in readme, f"README: `{name} {opt}` not documented"

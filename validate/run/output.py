"""A run's output folder: staged, then committed in one transaction.

Work is staged in a temporary folder inside ``--out`` (:func:`output_folder`); when every experiment succeeded,
the new results.json and pages are written there too, and only then is everything renamed into place as one
:class:`~validate.atomic.Transaction` (:func:`commit`, rolled back if any step fails). So a failure — bad input, a
failed task, a full disk at any point, a signal — leaves the previous report byte for byte, and a fresh ``--out``
folder is removed again."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from ..atomic import OutputError, output_error
from ..errors import ValidateError
from . import interrupt


def _first_missing(path: Path) -> Path | None:
    """The topmost folder of ``path`` that does not exist yet (what a failed run must remove again)."""
    missing = None
    for p in [path, *path.parents]:
        if os.path.lexists(p):
            break
        missing = p
    return missing


def check_output_folder(out: Path) -> None:
    """Refuse at once an ``--out`` that is, or lies under, something other than a folder."""
    for p in [out, *out.parents]:
        if os.path.lexists(p):
            if not p.is_dir():
                where = "" if p == out else f" ({p})"
                raise OutputError(f"{out}: cannot create the output folder: a file is in the way{where}")
            return


@contextlib.contextmanager
def output_folder(out: Path) -> Iterator[tuple[Path, dict[str, bool]]]:
    """Create ``out`` and a staging folder in it; yield (staging, state). On the way out the staging
    folder is removed, and on failure a freshly created ``out`` too (unless ``state["committed"]``).
    OSErrors become one-line :class:`OutputError`; paths inside the staging folder are named as the
    outputs they were going to be."""
    check_output_folder(out)
    fresh = _first_missing(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=".staging-", dir=out))
    except OSError as exc:
        if fresh is not None:
            shutil.rmtree(fresh, ignore_errors=True)
        raise output_error(out, exc, "cannot create the output folder") from None
    state = {"committed": False}

    def clean() -> None:
        shutil.rmtree(staging, ignore_errors=True)
        if fresh is not None and not state["committed"]:
            shutil.rmtree(fresh, ignore_errors=True)

    try:
        with interrupt.cleanup(clean):
            yield staging, state
    except OSError as exc:
        where = exc.filename if exc.filename is not None else out
        raise OutputError(str(output_error(where, exc)).replace(str(staging), str(out))) from None
    except ValidateError as exc:
        raise type(exc)(str(exc).replace(str(staging), str(out))) from None
    finally:
        if state["committed"]:
            shutil.rmtree(staging, ignore_errors=True)
        else:
            clean()


def previous_seconds(out: Path) -> dict[str, float]:
    """Each experiment's wall time in the report already in ``out`` (none when there is none or it cannot be read:
    it only orders the two lanes' work, :func:`~validate.run.schedule.longest_first`)."""
    from ..report.html import load_results

    try:
        exps = load_results(out).get("experiments", {})
    except ValidateError:
        return {}
    if not isinstance(exps, dict):
        return {}
    return {n: float(e["wall_time_s"]) for n, e in exps.items()
            if isinstance(e, dict) and isinstance(e.get("wall_time_s"), (int, float))}


def commit(out: Path, staging: Path, done: dict, results: dict) -> Path:
    """Move each experiment's figures into ``out``, draw the summary figures and write results.json and
    every page into the staging folder, then rename them into place: one
    :class:`~validate.atomic.Transaction`, so a full disk or any other failure leaves the previous
    report exactly as it was."""
    from ..atomic import Transaction, write_text
    from ..report import html

    new = staging / "commit"
    with Transaction(staging / "replaced") as tx:
        summaries = _stage_summaries(out, staging, results)
        for n in done:
            src = staging / "figures" / n
            if src.exists():
                tx.move(src, out / "figures" / n)
        if summaries is not None:
            tx.move(summaries, out / html.SUMMARY_DIR)
        pages = html.render_pages(out, results)  # figure paths are checked against their final place
        html.write_results_json(new, results)
        for name, text in pages.items():
            write_text(new / name, text)
        for name in pages:
            if name != html.REPORT_FILE:
                tx.move(new / name, out / name)
        for stale in sorted(out.glob("exp-*.html")):
            if stale.name not in pages:
                tx.remove(stale)
        tx.move(new / html.RESULTS_FILE, out / html.RESULTS_FILE)
        tx.move(new / html.REPORT_FILE, out / html.REPORT_FILE)
    return out / html.REPORT_FILE


def _stage_summaries(out: Path, staging: Path, results: dict) -> Path | None:
    """The report's summary figures (``report.html.draw_summaries``) drawn in the staging folder: the
    current ones are hard-linked in first (no copy, no disk space), so only changed figures are drawn.
    Returns the staged folder (None where this version of the report draws none)."""
    from ..report import html

    draw = getattr(html, "draw_summaries", None)
    if draw is None:
        return None
    staged, current = staging / html.SUMMARY_DIR, out / html.SUMMARY_DIR
    try:
        staged.mkdir(parents=True, exist_ok=True)
        for f in current.glob("*.png") if current.is_dir() else ():
            try:
                os.link(f, staged / f.name)
            except OSError:
                shutil.copy2(f, staged / f.name)  # another file system or no hard links: a copy
    except OSError as exc:
        raise output_error(getattr(exc, "filename", None) or staged, exc) from None
    draw(staging, results)
    return staged

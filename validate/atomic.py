"""Atomic output: write to a temporary file in the destination folder, then rename over the target.

A crash or an error never leaves a half-written report, cache entry or figure behind, and readers
never see a partial file. Inputs are never written: :func:`refuse_input_overwrite` guards that.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO

from .errors import ValidateError


@contextlib.contextmanager
def atomic_path(target: str | os.PathLike[str], suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path beside ``target``; on success it is renamed to ``target``."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix or target.suffix or ".tmp",
                               dir=target.parent)
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp_path, 0o666 & ~umask)  # mkstemp creates 0600; outputs are ordinary files
        os.replace(tmp_path, target)
    finally:
        if tmp_path.exists():
            tmp_path.unlink()


def write_text(target: str | os.PathLike[str], text: str) -> Path:
    with atomic_path(target) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(target)


def write_with(target: str | os.PathLike[str], writer: Callable[[IO[bytes]], None]) -> Path:
    """Open a temporary binary file, let ``writer`` fill it, then move it into place."""
    with atomic_path(target) as tmp:
        with open(tmp, "wb") as fh:
            writer(fh)
    return Path(target)


def refuse_input_overwrite(out_dir: Path, inputs: list[Path]) -> None:
    """Raise if the output folder is, or contains, an input file or folder."""
    out = out_dir.resolve()
    for p in inputs:
        rp = p.resolve()
        if rp == out or (rp.is_file() and rp.parent == out):
            raise ValidateError(f"{out_dir}: output folder holds input {p}; choose another --out")

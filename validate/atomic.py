"""Atomic output: write to a temporary file in the destination folder, then rename over the target.

A crash or an error never leaves a half-written report, cache entry or figure behind, and readers
never see a partial file. Inputs are never written: :func:`refuse_input_overwrite` guards that.

Faults are one line. A write that fails (a full disk, ENOSPC, at any byte; a read-only or vanished
folder) raises :class:`OutputError`, a :class:`~validate.errors.ValidateError` naming the target
and the system's reason ("No space left on device"); the temporary file is removed.

Several files as one change: :class:`Transaction` renames prepared files and folders into place,
keeping what each replaced, and puts everything back if any step fails (the report is then the
previous one, byte for byte). Renames within one file system need no free space, so once every new
file is written (the step a full disk can stop), the swap itself cannot run out of room.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO

from .errors import ValidateError


class OutputError(ValidateError):
    """An output could not be written: ``<path>: <reason>`` (one line)."""


def output_error(path: str | os.PathLike[str], exc: OSError, doing: str = "") -> OutputError:
    """The one-line :class:`OutputError` for an OSError met while writing ``path``."""
    reason = exc.strerror or type(exc).__name__
    return OutputError(f"{path}: {doing + ': ' if doing else ''}{reason}")


@contextlib.contextmanager
def atomic_path(target: str | os.PathLike[str], suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path beside ``target``; on success it is renamed to ``target``."""
    target = Path(target)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix or target.suffix or ".tmp",
                                   dir=target.parent)
        os.close(fd)
    except OSError as exc:
        raise output_error(target, exc) from None
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp_path, 0o666 & ~umask)  # mkstemp creates 0600; outputs are ordinary files
        os.replace(tmp_path, target)
    except OSError as exc:  # the writer's or ours: ENOSPC, EROFS, EIO …
        raise output_error(target, exc) from None
    finally:
        with contextlib.suppress(OSError):
            tmp_path.unlink(missing_ok=True)


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


def check_writable_folder(folder: str | os.PathLike[str]) -> None:
    """Raise the one-line :class:`OutputError` unless ``folder`` is (or can be created as) a writable folder;
    creates nothing, so a command can check its output before it writes anything."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"{folder}: not a folder")
    parent = next((p for p in [folder, *folder.parents] if p.exists()), None)
    if parent is None or not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"{folder}: cannot write here (Permission denied)")


def refuse_input_overwrite(out_dir: Path, inputs: list[Path]) -> None:
    """Raise if the output folder is, or contains, an input file or folder."""
    out = out_dir.resolve()
    for p in inputs:
        rp = p.resolve()
        if rp == out or (rp.is_file() and rp.parent == out):
            raise ValidateError(f"{out_dir}: output folder holds input {p}; choose another --out")


class Transaction:
    """Rename prepared paths into place as one change (module docstring).

    ``move(src, dst)`` renames ``src`` (a file or folder) to ``dst``; a ``dst`` already there is first
    renamed into ``backup_dir`` (same file system). ``remove(dst)`` moves ``dst`` aside the same way.
    ``rollback()`` undoes every step in reverse order; ``commit()`` forgets the backups (the caller
    deletes ``backup_dir``). Used as a context manager it rolls back on any exception (a signal
    included) and commits otherwise.
    """

    def __init__(self, backup_dir: Path) -> None:
        self.backup_dir = Path(backup_dir)
        self._journal: list[tuple[Path, Path | None]] = []  # (destination, what it replaced)

    def _aside(self, dst: Path) -> Path | None:
        if not os.path.lexists(dst):
            return None
        self.backup_dir.mkdir(parents=True, exist_ok=True)
        backup = self.backup_dir / f"{len(self._journal)}-{dst.name}"
        os.rename(dst, backup)
        return backup

    def move(self, src: Path, dst: Path) -> None:
        try:
            dst.parent.mkdir(parents=True, exist_ok=True)
            backup = self._aside(dst)
            self._journal.append((dst, backup))
            os.rename(src, dst)
        except OSError as exc:
            raise output_error(dst, exc) from None

    def remove(self, dst: Path) -> None:
        try:
            backup = self._aside(dst)
        except OSError as exc:
            raise output_error(dst, exc) from None
        if backup is not None:
            self._journal.append((dst, backup))

    def rollback(self) -> None:
        """Put back what every step replaced (best effort: every step is tried)."""
        import shutil

        for dst, backup in reversed(self._journal):
            with contextlib.suppress(OSError):
                if os.path.lexists(dst) and (backup is None or os.path.lexists(backup)):
                    shutil.rmtree(dst) if dst.is_dir() and not dst.is_symlink() else dst.unlink()
                if backup is not None:
                    os.rename(backup, dst)
        self._journal.clear()

    def commit(self) -> None:
        self._journal.clear()

    def __enter__(self) -> Transaction:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: object) -> None:
        if kind is None:
            self.commit()
        else:
            self.rollback()

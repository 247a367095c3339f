"""The probes directory: every .exr/.hdr/.pfm in it becomes an environment.

``--probes DIR`` (or ``VALIDATE_PROBES``) adds every probe found in DIR; a file there that fails
validation is skipped with a one-line reason (listed in the report and printed), so one bad file
does not hide the others. ``--probe FILE`` names a file explicitly: there a bad file is an error.

Published figures (``sh9_coefficients.csv``, ``probe_aliases.csv``) ship with the package in
:mod:`validate.data` (sources in its README.md); ``$VALIDATE_REFERENCE`` may name another folder with
the same files. ``probe_aliases.csv`` maps R&H table rows to Debevec file names; only an angular map
whose file stem *exactly* equals a ``debevec_file`` (e.g. ``grace_probe``) is "one of the paper's
probes". Copies in other layouts or captures (``grace_probe_latlong``, ``ict_grace_*``) are not;
:func:`published_status` says why such a near match is not compared.
"""

from __future__ import annotations

import csv
import os
import re
from collections.abc import Callable
from importlib import resources
from pathlib import Path

from ..errors import ValidateError
from .environment import Environment
from .loaders import EXTENSIONS, load_environment


def default_probes_dir() -> Path | None:
    env = os.environ.get("VALIDATE_PROBES")
    return Path(env) if env else None


def package_reference_dir() -> Path:
    """The published figures shipped with the package (:mod:`validate.data`)."""
    return Path(str(resources.files("validate.data")))


def reference_dir() -> Path:
    """Published figures: ``$VALIDATE_REFERENCE`` if set, else the package's own copy (any cwd)."""
    env = os.environ.get("VALIDATE_REFERENCE")
    if env:
        return Path(env)
    return package_reference_dir()


def probe_files(directory: Path) -> list[Path]:
    if not directory.exists():
        raise ValidateError(f"{directory}: probes directory does not exist")
    if not directory.is_dir():
        raise ValidateError(f"{directory}: --probes needs a directory")
    return sorted(p for p in directory.iterdir() if p.is_file() and p.suffix.lower() in EXTENSIONS)


def load_probes(directory: Path | None, files: list[Path], layout: str, clamp_negative: bool,
                log: Callable[[str], None] = print, only_stems: set[str] | None = None
                ) -> tuple[list[Environment], list[tuple[str, str]]]:
    """Load the probes of ``directory`` (bad ones skipped with a reason) and ``files`` (bad = error).
    ``only_stems`` restricts the directory scan (quick mode: the paper's probes only)."""
    envs: list[Environment] = []
    skipped: list[tuple[str, str]] = []
    names: set[str] = set()
    if directory is not None:
        for p in probe_files(directory):
            if only_stems is not None and p.stem not in only_stems:
                skipped.append((p.name, "not run in --quick mode (only the paper's probes are)"))
                continue
            try:
                env = load_environment(p, "auto", clamp_negative)
            except ValidateError as exc:
                skipped.append((p.name, str(exc)))
                log(f"skipped: {exc}")
                continue
            envs.append(env)
            names.add(env.name)
    for p in files:
        env = load_environment(p, layout, clamp_negative)
        if env.name in names:
            raise ValidateError(f"{p}: a probe named {env.name!r} is already loaded")
        envs.append(env)
        names.add(env.name)
    return envs, skipped


def read_aliases(path: Path | None = None) -> dict[str, tuple[str, str]]:
    """debevec_file stem → (table probe key, display name)."""
    path = path or reference_dir() / "probe_aliases.csv"
    out: dict[str, tuple[str, str]] = {}
    if not path.exists():
        return out
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            if row.get("debevec_file"):
                out[row["debevec_file"].strip()] = (row["probe"].strip(), row["name_in_table"].strip())
    return out


def read_published_sh9(path: Path | None = None) -> dict[str, dict[str, list[float]]]:
    """probe key → {coefficient name → [r, g, b]} from ``sh9_coefficients.csv``."""
    path = path or reference_dir() / "sh9_coefficients.csv"
    out: dict[str, dict[str, list[float]]] = {}
    if not path.exists():
        return out
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            out.setdefault(row["probe"], {})[row["coefficient"]] = [float(row[c]) for c in "rgb"]
    return out


def published_row(env: Environment) -> str | None:
    """The table key of one of the paper's probes (angular map, exact Debevec stem), else None."""
    return published_status(env)[0]


def published_status(env: Environment, aliases: dict[str, tuple[str, str]] | None = None
                     ) -> tuple[str | None, str | None]:
    """(table key, None) for one of the paper's probes; (None, why) for a probe whose name matches a
    published row but which cannot be compared; (None, None) for anything else.

    A match is the exact Debevec stem (``grace_probe``), a stem that starts with it
    (``grace_probe_latlong``, ``uffizi_probe-128``) or one that has the table key as a word
    (``ict_grace_256x128``). Only the exact stem of an angular map is compared: the table is in R&H's
    angular-map ``prefilter`` convention and of those very captures, at ±0.01 after one exposure factor.
    """
    if env.source is None:
        return None, None
    aliases = read_aliases() if aliases is None else aliases
    stem = env.source.stem
    words = set(re.split(r"[^a-z0-9]+", stem.lower()))
    for debevec, (key, shown) in aliases.items():
        if stem == debevec:
            if env.layout == "angular" and env.angular is not None:
                return key, None
            return None, (f"{env.source.name}: named as R&H's '{shown}' probe ({debevec}), but it is a "
                          f"{env.layout} map, not the angular map the published table was computed from "
                          f"(R&H's prefilter convention); coefficients not compared")
        if stem.startswith(debevec) or key in words:
            return None, (f"{env.source.name}: named like R&H's '{shown}' probe, but it is not the Debevec "
                          f"angular map {debevec}.hdr the table was computed from (another capture, layout "
                          f"or resolution); coefficients and the paper's < 1 %/< 5 % claim not applied")
    return None, None

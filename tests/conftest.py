"""Shared fixtures: the Mitsuba variant, an isolated reference cache, and the data folders.

* The process settings of ``python -m validate`` (:func:`validate.run.process.tune`: memory, BLAS and OpenMP
  threads) apply to the test processes too.
* ``backend`` (session, autouse): :func:`validate.backend.init` once, so every test runs with the
  variant active (``llvm_ad_rgb`` here) and ``mi.*`` types usable.
* ``VALIDATE_CACHE`` points at a per-session temporary folder unless the user set it, so tests never
  read (or pollute) a user's cache, while tests within one session still share expensive results.
* ``probes_dir`` / ``reference_dir``: the light probes (``$VALIDATE_PROBES``, default
  ``<repo>/../shared/probes``) and the published figures (``$VALIDATE_REFERENCE``, default
  the package's own copy in ``validate/data``). A test that needs them is skipped, with the reason, when they are
  absent; such tests carry the ``probes`` marker.
* ``load_probe``: loads a probe file from ``probes_dir`` once per session (converting a 1000² angular
  map takes about a second).
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:  # so a bare `pytest` (not `python -m pytest`) finds the package
    sys.path.insert(0, str(REPO))

from validate.run.process import tune  # noqa: E402

tune()  # the run's process settings (validate.run.process), before the libraries below load

from validate.backend import Backend, init  # noqa: E402
from validate.scenes.environment import Environment  # noqa: E402


@pytest.fixture(scope="session", autouse=True)
def isolated_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path | None]:
    """``VALIDATE_CACHE`` = a session temporary folder, unless the user already set it."""
    if "VALIDATE_CACHE" in os.environ:
        value = os.environ["VALIDATE_CACHE"]
        yield None if value == "off" else Path(value)
        return
    path = tmp_path_factory.mktemp("validate_cache")
    os.environ["VALIDATE_CACHE"] = str(path)
    try:
        yield path
    finally:
        os.environ.pop("VALIDATE_CACHE", None)


@pytest.fixture(scope="session", autouse=True)
def backend(isolated_cache: Path | None) -> Backend:
    """The active Mitsuba/drjit backend (chosen once per session)."""
    return init()


def _existing_dir(path: Path, what: str, var: str) -> Path:
    if not path.is_dir():
        pytest.skip(f"{what} not found at {path}: set {var}")
    return path.resolve()  # absolute: tests also hand it to subprocesses that run in other folders


@pytest.fixture(scope="session")
def probes_dir() -> Path:
    """``$VALIDATE_PROBES`` or ``<repo>/../shared/probes``; skips the test when it does not exist."""
    path = Path(os.environ.get("VALIDATE_PROBES") or REPO.parent / "shared" / "probes")
    return _existing_dir(path, "light probes", "VALIDATE_PROBES")


@pytest.fixture(scope="session")
def reference_dir() -> Path:
    """The published figures: ``$VALIDATE_REFERENCE`` or the package's own copy (``validate/data``)."""
    from validate.scenes.probes import reference_dir as published_dir

    return _existing_dir(published_dir(), "published reference figures", "VALIDATE_REFERENCE")


@pytest.fixture(scope="session")
def load_probe(probes_dir: Path) -> Callable[[str], Environment]:
    """``load_probe("grace_probe.hdr")`` → the loaded :class:`Environment` (memoised per session)."""
    from validate.scenes.loaders import load_environment

    loaded: dict[str, Environment] = {}

    def load(filename: str) -> Environment:
        if filename not in loaded:
            path = probes_dir / filename
            if not path.is_file():
                pytest.skip(f"light probe {filename} not found in {probes_dir}: set VALIDATE_PROBES")
            loaded[filename] = load_environment(path)
        return loaded[filename]

    return load

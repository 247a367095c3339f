"""Variant selection (validate.backend): probing happens in a subprocess, so a variant that would
abort the process (drjit's LLVM backend with an old libLLVM) only makes the probe fail."""

from __future__ import annotations

import mitsuba as mi
import pytest

from validate import backend as backend_module
from validate.errors import ValidateError


def test_init_returns_an_available_variant(backend: backend_module.Backend) -> None:
    b = backend_module.init()
    assert b is backend  # chosen once per process
    assert b.variant in mi.variants()
    assert mi.variant() == b.variant
    assert b.reason and b.variant in b.describe()


def test_float_type_matches_variant(backend: backend_module.Backend) -> None:
    ft = backend_module.float_type()
    x = ft([1.0, 2.0, 3.0])
    assert len(x) == 3
    if backend.is_vectorized:
        assert ft is mi.Float


def test_probe_of_bogus_variant_fails_gracefully() -> None:
    ok, msg = backend_module.probe_variant("bogus_variant_rgb", timeout=120.0)
    assert ok is False
    assert msg and "\n" not in msg and len(msg) <= 200


def test_bogus_override_raises_validate_error(monkeypatch: pytest.MonkeyPatch) -> None:
    """VALIDATE_VARIANT=bogus → one-line ValidateError naming it (environment restored afterwards)."""
    monkeypatch.setenv("VALIDATE_VARIANT", "bogus")
    monkeypatch.delenv("VALIDATE_PROBED_VARIANT", raising=False)
    with pytest.raises(ValidateError) as info:
        backend_module.choose_variant()
    msg = str(info.value)
    assert "VALIDATE_VARIANT=bogus" in msg and "\n" not in msg


def test_remembered_probe_is_reused(monkeypatch: pytest.MonkeyPatch, backend: backend_module.Backend) -> None:
    """A child process (or this session) reuses VALIDATE_PROBED_VARIANT instead of probing again."""
    monkeypatch.delenv("VALIDATE_VARIANT", raising=False)
    monkeypatch.setenv("VALIDATE_PROBED_VARIANT", f"{backend.variant}|remembered")
    assert backend_module.choose_variant() == backend_module.Backend(backend.variant, "remembered")

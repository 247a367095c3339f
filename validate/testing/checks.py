"""The family checks behind :mod:`validate.testing` (documented there): each evaluates a function on reference
environments and measures it against Mitsuba ground truth with the suite's metrics."""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..backend import init
from ..errors import ValidateError
from ..experiments.arealights import check as arealights_check
from ..experiments.brdfs import check as brdfs_check
from ..experiments.ibl import check as ibl_check
from ..experiments.inputs import MissingProbe, load_named_environment
from ..experiments.shadows import check as shadows_check
from ..experiments.techniques import CheckResult, Stat
from ..experiments.uberlight import check as uberlight_check
from ..local_models import irradiance
from ..local_models.glsl_technique import technique_from_file
from ..local_models.registry import Technique
from ..metrics.irradiance_error import irradiance_errors
from ..reference.irradiance import reference_irradiance
from ..report.compare import Comparison
from ..report.compare import compare as compare_runs
from ..scenes.latlong import fibonacci_sphere

DEFAULT_ENVIRONMENTS = ("two_tone", "grace_probe")


def _technique(fn: Callable[..., Any] | Technique | str, name: str | None) -> Technique:
    if is_glsl(fn):
        fn = technique_from_file(fn, "irradiance")  # type: ignore[arg-type]
    if isinstance(fn, str):
        fn = irradiance[fn]
    if isinstance(fn, Technique):
        return fn if name is None else Technique(name, fn.family, fn.fn, fn.description)
    if not callable(fn):
        raise ValidateError(f"check_irradiance: {fn!r} is not callable")
    label = name or getattr(fn, "__name__", None) or type(fn).__name__
    return Technique(label, "irradiance", fn, (getattr(fn, "__doc__", None) or "").strip().split("\n")[0])


def _skip_or_raise(exc: MissingProbe, missing: str) -> None:
    if missing == "skip" and "pytest" in sys.modules:
        import pytest

        pytest.skip(str(exc))
    raise exc


def check_irradiance(fn: Callable[[np.ndarray, np.ndarray], np.ndarray] | Technique | str,
                     environments: Iterable[str] = DEFAULT_ENVIRONMENTS, normals: int = 2500,
                     name: str | None = None, missing: str = "skip") -> CheckResult:
    """Measure an irradiance technique against the reference on each environment (module docstring)."""
    if missing not in ("skip", "error"):
        raise ValidateError(f"check_irradiance: missing={missing!r} must be 'skip' or 'error'")
    if not isinstance(normals, (int, np.integer)) or normals < 16:
        raise ValidateError(f"check_irradiance: normals={normals!r} must be an integer ≥ 16")
    names = [environments] if isinstance(environments, str) else list(environments)
    if not names:
        raise ValidateError("check_irradiance: environments is empty")
    tech = _technique(fn, name)
    init()
    envs = []
    for env_name in names:
        try:
            envs.append(load_named_environment(env_name))
        except MissingProbe as exc:
            _skip_or_raise(exc, missing)
    n = fibonacci_sphere(int(normals))
    out: dict[str, dict[str, Stat]] = {}
    for env_name, env in zip(names, envs, strict=True):
        ref = reference_irradiance(env, n)
        e = irradiance.call(tech, env.radiance, n)
        stats = irradiance_errors(ref.irradiance, e, env.total_flux(), ref.uncertainty)
        out[env_name] = {k: Stat(s.mean, s.max, s.mean_uncertainty, s.max_uncertainty) for k, s in stats.items()}
    return CheckResult(tech.name, "irradiance", out)


def is_glsl(fn: object) -> bool:
    """A path (str or Path) to a ``.glsl`` technique file."""
    return isinstance(fn, (str, Path)) and str(fn).endswith(".glsl")


def _accepting_glsl(family: str, impl: Callable[..., Any]) -> Callable[..., Any]:
    """``impl`` (an experiment's check) that also takes a ``.glsl`` file as its first argument."""
    @functools.wraps(impl)  # check.__wrapped__ is the experiment's own function
    def check(*args: Any, **kwargs: Any) -> Any:
        if args and is_glsl(args[0]):  # a GLSL file: compiled on its runtime, checked like a Python function
            args = (technique_from_file(args[0], family), *args[1:])
        return impl(*args, **kwargs)

    return check


check_specular = _accepting_glsl("specular", ibl_check.check_specular)
check_arealight = _accepting_glsl("arealight", arealights_check.check_arealight)
check_shadow = _accepting_glsl("shadow", shadows_check.check_shadow)
check_brdf = _accepting_glsl("brdf", brdfs_check.check_brdf)
check_uberlight = _accepting_glsl("uberlight", uberlight_check.check_uberlight)


def compare(old: str | os.PathLike[str] | Mapping[str, Any], new: str | os.PathLike[str] | Mapping[str, Any]
            ) -> Comparison:
    """Compare two runs (:mod:`validate.testing`'s docstring; the rules are :mod:`validate.report.compare`'s)."""
    return compare_runs(old, new)  # type: ignore[arg-type]

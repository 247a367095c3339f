"""``validate.testing`` — gate your own lighting code on physics from your own pytest suite.

One check function per technique family. Each evaluates your function on reference environments,
measures it against Mitsuba ground truth with the suite's metrics, and returns a
:class:`~validate.experiments.techniques.CheckResult` whose values carry their uncertainty::

    # test_my_model.py (a complete example: examples/test_my_model.py)
    from validate.testing import check_irradiance

    def my_irradiance(radiance, normals):   # (H, W, 3) lat-long, (N, 3) unit normals → (N, 3)
        ...

    def test_my_irradiance():
        r = check_irradiance(my_irradiance, environments=("two_tone", "grace_probe"))
        assert r.flux_luminance.max < 0.05        # worst environment, max over normals
        assert r["two_tone"].flux_luminance.mean < 0.01
        # conservative: demand that the bound clears, not just the value
        assert r.flux_luminance.max + r.flux_luminance.max_uncertainty < 0.05

Run it with ``python -m pytest test_my_model.py`` (from this repository: ``.venv/bin/python -m pytest
examples/``).

``check_irradiance(fn, environments=("two_tone", "grace_probe"), normals=2500, name=None, missing="skip")``
    ``fn(radiance, normals) -> irradiance`` follows the ``irradiance`` family's contract
    (:mod:`validate.local_models.families`): ``radiance`` is an (H, W, 3) float32 lat-long map in
    Mitsuba's ``envmap`` convention (y up; direction (sin φ sin θ, cos θ, −cos φ sin θ); row i at
    θ = iπ/(H − 1), column j at φ = 2π(j + ½)/W), ``normals`` (N, 3) unit vectors, and the result the
    (N, 3) irradiance E(n) = ∫ L(ω) max(0, n·ω) dω (not E/π). A wrong shape, NaN or Inf raises
    :class:`~validate.errors.ValidateError` naming the technique. ``fn`` may also be a registered
    technique (its name or its :class:`~validate.local_models.registry.Technique`).

    ``environments``: built-in names (``constant``, ``two_tone``, ``bandlimited``, ``disc_on_sky``,
    ``near_directional``, ``sunsky_5deg``, ``sunsky_30deg``, ``sunsky_60deg``), probe names resolved as
    ``<probes>/<name>.{hdr,exr,pfm}`` where ``<probes>`` is ``$VALIDATE_PROBES``, else
    ``<checkout>/../shared/probes``, else ``./../shared/probes``, or paths to probe files.

    ``normals``: the number of spherical-Fibonacci normals (quasi-uniform) the error is measured at.

    A probe that cannot be found: ``missing="skip"`` (default) skips the calling test through
    ``pytest.skip`` with the reason (outside pytest it raises :class:`MissingProbe`);
    ``missing="error"`` always raises :class:`MissingProbe`, a :class:`~validate.errors.ValidateError`.

    The metrics (README § Metrics; :mod:`validate.metrics.irradiance_error`) at every normal n, with
    Φ = ∫ L dω and Y the Rec. 709 luminance: ``flux_luminance`` |Y(E′) − Y(E)| / Φ_Y (the normalisation
    of R&H 2001's "< 1 % average, < 5 % max"), ``flux_rgb`` the worst channel of |E′_c − E_c| / Φ_c,
    ``relative`` |Y(E′) − Y(E)| / Y(E) where Y(E) ≥ 10⁻³ max Y(E), ``peak`` |Y(E′) − Y(E)| / max Y(E).
    Each is a :class:`~validate.experiments.techniques.Stat`: ``mean`` and ``max`` over the normals with
    ``mean_uncertainty`` and ``max_uncertainty`` (the reference quadrature's, propagated).

    The reference is cached on disk (``$VALIDATE_CACHE``, default ``~/.cache/validate``), so a second
    run costs only your function.

``CheckResult``
    ``r.<metric>`` is the worst case over the environments checked (largest mean, largest max);
    ``r[env].<metric>`` one environment; ``r.environments[env][metric]`` the same as a dict;
    ``repr(r)`` lists every value ± uncertainty (pytest shows it when an assert fails).

``check_render(render_fn, scenes=...)``
    An engine's rendered pixels against the path tracer, per pixel with uncertainty
    (:mod:`validate.testing_render`, the ``renders`` experiment's judgement).

``compare(old, new) -> Comparison``
    Two runs' ``results.json`` (paths, their folders, or loaded dicts) compared claim by claim and
    technique metric by metric (:mod:`validate.compare`): ``c.regressions`` lists the claims that passed
    and now fail and the metrics worse beyond √(σ_old² + σ_new²); ``c.table()`` the changed rows. A CI
    gate: ``assert not compare("baseline/results.json", "reports/results.json").regressions``.

``check_specular``, ``check_arealight``, ``check_shadow``, ``check_brdf``, ``check_uberlight``
    The same for the ``specular``, ``arealight``, ``shadow``, ``brdf`` and ``uberlight`` families; they are
    implemented by their experiments' ``check`` modules (:mod:`validate.experiments.ibl.check`,
    ``arealights.check``, ``shadows.check``, ``brdfs.check``, ``uberlight.check``) and documented there.

Every check also accepts the path of a ``.glsl`` technique file (``check_brdf("my_brdf.glsl")``): the file
is parsed, compiled on its runtime (an error is ``<file>:<line>: <driver message>``) and checked through
the family's contract like a Python function, without being registered (docs/glsl.md).
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Callable, Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .backend import init
from .compare import Comparison
from .compare import compare as compare_runs
from .errors import ValidateError
from .experiments.arealights import check as arealights_check
from .experiments.brdfs import check as brdfs_check
from .experiments.ibl import check as ibl_check
from .experiments.inputs import MissingProbe, find_probe, load_named_environment, probe_dirs
from .experiments.shadows import check as shadows_check
from .experiments.techniques import CheckResult, Stat
from .experiments.uberlight import check as uberlight_check
from .local_models import irradiance
from .local_models.glsl_technique import technique_from_file
from .local_models.registry import Technique
from .metrics.irradiance_error import irradiance_errors
from .reference.irradiance import reference_irradiance
from .scenes.latlong import fibonacci_sphere
from .testing_render import check_render

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
    """Compare two runs (module docstring; the rules are :mod:`validate.compare`'s)."""
    return compare_runs(old, new)  # type: ignore[arg-type]

__all__ = ["CheckResult", "MissingProbe", "Stat", "check_arealight", "check_brdf", "check_irradiance", "check_render",
           "check_shadow", "check_specular", "check_uberlight", "compare", "find_probe", "load_named_environment",
           "probe_dirs"]

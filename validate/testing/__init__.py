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
    (:mod:`validate.testing.render`, the ``renders`` experiment's judgement).

``check_render_folder(images_dir, engine="engine", scenes=None)``
    Images rendered anywhere (``<scene>.exr``/``.pfm``) for the scenes ``python -m validate scenes export`` wrote,
    judged as ``python -m validate judge`` judges them (docs/scenes.md); ``r.passed``, ``r.summary()``.

``compare(old, new) -> Comparison``
    Two runs' ``results.json`` (paths, their folders, or loaded dicts) compared claim by claim and
    technique metric by metric (:mod:`validate.report.compare`): ``c.regressions`` lists the claims that passed
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

from ..experiments.inputs import MissingProbe, find_probe, load_named_environment, probe_dirs
from ..experiments.techniques import CheckResult, Stat
from .checks import (
    check_arealight,
    check_brdf,
    check_irradiance,
    check_shadow,
    check_specular,
    check_uberlight,
    compare,
)
from .render import check_render, check_render_folder

__all__ = ["CheckResult", "MissingProbe", "Stat", "check_arealight", "check_brdf", "check_irradiance", "check_render",
           "check_render_folder", "check_shadow", "check_specular", "check_uberlight", "compare", "find_probe",
           "load_named_environment", "probe_dirs"]

"""The seeds' listings: stored verbatim, glued and edited as catalogued, run on llvmpipe equal to their Python
transcriptions; the printed equations' readings against closed forms.

Tests that need GL skip with the runtime's reason when the OpenGL 4.5 compatibility profile does not start.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.gl.listing_harness import Edit, apply_edits
from validate.local_models import precision
from validate.local_models.brdf import ganovelli_cook_torrance as gct
from validate.local_models.brdf.common import GeometryDr, fresnel_f0
from validate.local_models.light import ganovelli_lamps as g6
from validate.local_models.listings import runner
from validate.local_models.listings.catalog import LISTINGS, SEED_FILES, SHADERS, listing
from validate.local_models.registry import FAMILIES, define_family
from validate.local_models.uberlight import fore_june_falloff as ff

SEEDS = Path(__file__).resolve().parents[2].parent / "shared" / "seeds"
GL_OK, GL_WHY = runner.gl_status()
needs_gl = pytest.mark.skipif(not GL_OK, reason=f"no OpenGL compatibility runtime: {GL_WHY}")

# GLSL (float32, inputs rounded to float32) against float64: ≈ 60 operations × ≤ 2.5 amplification (the
# superellipse exponents 2/d, −d/2 at d = 0.8) × 2⁻²⁴ ≈ 9·10⁻⁶ of the largest value; llvmpipe's transcendental
# functions are within a few ulp (issue 20's measurement). Measured worst: 2.4·10⁻⁶ (USC Phong, 4096 receivers).
TRANSCRIPTION_BOUND = 1e-5


def _shader_files() -> list[tuple[str, str]]:
    return sorted({(x.seed, f) for x in LISTINGS for f in (x.vert, x.frag) if f is not None})


@pytest.mark.parametrize(("seed", "fname"), _shader_files())
def test_shader_text_is_verbatim(seed: str, fname: str) -> None:
    """Every non-blank line of the stored shader is a line of the seed, in order (nothing rewritten)."""
    path = SEEDS / SEED_FILES[seed]
    if not path.is_file():
        pytest.skip(f"seed text not found at {path}")
    seed_lines = [ln.rstrip() for ln in path.read_text().splitlines()]
    pos = 0
    for line in (SHADERS / fname).read_text().splitlines():
        if not line.strip():
            continue
        pos = seed_lines.index(line.rstrip(), pos) + 1  # ValueError = a line not in the seed (or out of order)


@pytest.mark.parametrize("name", [x.name for x in LISTINGS if x.status != "unrunnable" and x.runs])
def test_catalogued_edits_apply(name: str) -> None:
    """Every edit finds its text the declared number of times; glue goes first."""
    lst = listing(name)
    vert = lst.source("vert")
    assert lst.source("frag")
    if lst.headers[0]:
        assert vert.startswith(lst.headers[0] + "\n#line 1\n")


def test_stale_edit_is_an_error() -> None:
    with pytest.raises(ValidateError, match="expected 1 time"):
        apply_edits("void main() {}", [Edit("vert", "gl Position", "gl_Position", "why")], "vert", "listing x")


def _pairs() -> dict:
    from validate.experiments.listings.compute import _pairs, _receivers
    from validate.experiments.listings.settings import QUICK

    return _pairs(_receivers(type(QUICK)(**{**QUICK.__dict__, "receivers": 96})))


@needs_gl
@pytest.mark.parametrize("name", ["forejune_20_1", "forejune_20_4_disc", "forejune_20_4_grace", "forejune_20_5",
                                  "orange_12_6_12_7", "ganovelli_6_3_6_4", "ganovelli_6_9", "redbook_7_4",
                                  "redbook_7_5", "redbook_7_6", "redbook_7_12", "redbook_7_14", "usc420_l11"])
def test_glsl_listing_equals_python_transcription(name: str) -> None:
    py, gl = _pairs()[name]
    a, b = np.asarray(py(), dtype=np.float64), np.asarray(gl(), dtype=np.float64)
    assert np.max(np.abs(a)) > 0
    assert np.max(np.abs(a - b)) <= TRANSCRIPTION_BOUND * np.max(np.abs(a))


BATCHED = ["forejune_20_1", "forejune_20_4_disc", "forejune_20_4_grace", "forejune_20_5", "ganovelli_6_3_6_4",
           "ganovelli_6_9", "redbook_7_4", "redbook_7_5", "redbook_7_6", "redbook_7_12", "redbook_7_14", "usc420_l11"]


@needs_gl
@pytest.mark.parametrize("name", BATCHED)
def test_one_draw_equals_one_draw_per_receiver(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """The batched draw (placement uniform declared as a vertex input, one glDrawArrays for all receivers) gives
    the same float32 bits as one draw per receiver with the placement a uniform (the listing as printed)."""
    from validate.gl import listing_harness as lh

    calls: list[bool] = []
    real = lh.batched_vertex_shader

    def spy(*a: object) -> str | None:
        out = real(*a)  # type: ignore[arg-type]
        calls.append(out is not None)
        return out

    gl = _pairs()[name][1]
    monkeypatch.setattr(lh, "batched_vertex_shader", spy)
    one = np.asarray(gl())
    assert calls and all(calls)  # every render of this listing took the batched path
    monkeypatch.setattr(lh, "batched_vertex_shader", lambda *a: None)
    per = np.asarray(gl())
    assert one.shape == per.shape and np.array_equal(one, per, equal_nan=True)


def test_batched_declaration_only() -> None:
    """Only the one placement declaration changes (same line count); a name also in the fragment stage, a missing
    or repeated declaration, or the fixed-function placement keep the per-receiver draws."""
    from validate.gl.listing_harness import batched_vertex_shader as bvs

    vs = ("#version 150\nin vec3 p;\nuniform mat4 P;\nuniform mat4 M;\n"
          "void main() { gl_Position = P * M * vec4(p, 1); }\n")
    out = bvs(vs, "void main() {}", "P")
    assert out == vs.replace("uniform mat4 P;", "in mat4 P;")
    assert bvs(vs.replace("#version 150\n", ""), "void main() {}", "P") == vs.replace(
        "#version 150\n", "").replace("uniform mat4 P;", "attribute mat4 P;")
    assert bvs(vs, "uniform mat4 P; void main() {}", "P") is None
    assert bvs(vs, "void main() {}", "Q") is None
    assert bvs(vs + "uniform mat4 P;\n", "void main() {}", "P") is None
    assert bvs(vs, "void main() {}", None) is None


@needs_gl
def test_version_glue_is_needed() -> None:
    """Without `#version 120` Fore June's disc shader does not compile: `radians ( 20 )` passes an int (GLSL 1.10)."""
    from validate.gl import runtime
    from validate.gl.egl import ShaderError

    lst = listing("forejune_20_4_disc")
    ctx = runtime.get("llvmpipe-compat")
    with ctx, pytest.raises(ShaderError, match="radians"):
        ctx.program(lst.text("vert"), lst.source("frag"))


def test_gl_techniques_not_registered_without_gl(monkeypatch: pytest.MonkeyPatch) -> None:
    fam = FAMILIES.get("test_listings_family") or define_family("test_listings_family", "test", lambda *a: (1,))
    monkeypatch.setattr(runner, "gl_status", lambda: (False, "no GL in this test"))
    runner.register_gl(fam, "a_glsl_listing", "x", "redbook_7_4")(lambda: None)
    assert "a_glsl_listing" not in fam
    assert "test_listings_family/a_glsl_listing" in runner.GL_SKIPPED


# -- printed equations ------------------------------------------------------------------------------------------
K, M, D0 = 0.25, 1.0, 2.0


@pytest.mark.parametrize("alpha", [1.0, 2.0])
def test_fore_june_listing_form_is_c1_and_printed_is_not(alpha: float) -> None:
    """Listing: slope −Kα/d₀ on both sides of d₀ and I → M as d → 0; printed (d₀/d)^β: slope +Kα/d₀ inside, I → 0.
    Tolerance 10⁻⁴ relative: one-sided differences of width 10⁻⁶ d₀ are first-order accurate (≈ 10⁻⁶)."""
    lo, hi = ff.slopes_at_d0(K, M, D0, alpha, "listing")
    assert abs(hi + K * alpha / D0) < 1e-4 * K * alpha / D0 and abs(lo - hi) < 1e-4 * abs(hi)
    plo, _ = ff.slopes_at_d0(K, M, D0, alpha, "printed")
    assert abs(plo - K * alpha / D0) < 1e-4 * K * alpha / D0
    assert ff.falloff_listing(np.array([1e-9]), K, M, D0, alpha)[0] == pytest.approx(M, rel=1e-6)
    assert ff.falloff_printed(np.array([1e-3]), K, M, D0, alpha)[0] < 1e-6 * M
    for f in (ff.falloff_listing, ff.falloff_printed):  # both equal K at d₀
        assert f(np.array([D0]), K, M, D0, alpha)[0] == pytest.approx(K, rel=1e-12)


def test_ganovelli_cook_torrance_readings_at_normal_incidence() -> None:
    """l = v = n: D = 1/m² (no π, eq. 6.61), G = min(1, 2, g2) = 1, F = F₀ (eq. 6.66 at n·l = 1); the literal
    reading is F₀/(π m²), the n·l reading the same (n·l = 1), exact to float64 rounding."""
    n = np.array([[0.0, 0.0, 1.0]])
    params = {"alpha": 0.3, "eta": 0.2, "k": 3.0}
    f0 = fresnel_f0(params["eta"], params["k"])
    with precision.computing_in("float64"):  # the family computes in float32; the closed form is checked in float64
        g = GeometryDr(n, n, n)
        for with_nl in (False, True):
            spec = gct.ganovelli_specular(params, g, with_nl, 1.0).to_np(1)
            np.testing.assert_allclose(spec[0], f0 / (math.pi * 0.09), rtol=1e-12)


def test_ganovelli_g2_as_printed_lacks_the_factor_two() -> None:
    """Where G2 = (n·h)(n·l)/(v·h) is the minimum, restoring the 2 of eq. 6.62 doubles the specular term."""
    n = np.array([[0.0, 0.0, 1.0]])
    th_l, th_v = math.radians(80.0), math.radians(10.0)
    lt = np.array([[math.sin(th_l), 0.0, math.cos(th_l)]])
    vw = np.array([[-math.sin(th_v), 0.0, math.cos(th_v)]])
    p = {"alpha": 0.3, "eta": 0.2, "k": 3.0}
    with precision.computing_in("float64"):
        g = GeometryDr(n, lt, vw)
        one, two = (gct.ganovelli_specular(p, g, False, f).to_np(1) for f in (1.0, 2.0))
        ch, cl, vh = (precision.to_np(x)[0] for x in (g.ch, g.cl, g.vh))
    assert 2.0 * ch * cl / vh < 1.0  # G2 with the 2 is still below 1: G = G2 in both
    np.testing.assert_allclose(two, 2.0 * one, rtol=1e-12)


def test_ganovelli_lamp_factor_is_closed_form() -> None:
    """Listing 6.9's r = 0.03·3.14·3.14·d: E / (I cos θ/d²) = 1/(0.03·3.14²)² = 11.43 exactly (float64)."""
    pts = np.array([[0.5, 0.0, -0.2], [1.5, 0.0, 0.7]])
    nrm = np.tile([0.0, 1.0, 0.0], (2, 1))
    pos = np.array([0.0, 2.0, 0.0])
    to = pos - pts
    d = np.linalg.norm(to, axis=1)
    inv_sq = 3.0 * to[:, 1] / d / d ** 2
    np.testing.assert_allclose(g6.python_lamp(pos, 3.0, pts, nrm) / inv_sq, 1.0 / (0.03 * 3.14 * 3.14) ** 2,
                               rtol=1e-12)


@pytest.mark.slow
def test_listings_experiment_claims_hold() -> None:
    """The experiment at QUICK settings: every claim passes and every power check fails."""
    from validate.experiments.base import Context
    from validate.experiments.listings import QUICK, claims, compute

    m = compute(Context(out_dir=Path("."), quick=True, show_progress=False), QUICK)
    for c in claims(m):
        assert c.passed, c.id
        assert c.power is not None and c.power.fails, c.id


@pytest.mark.slow
def test_listings_experiment_without_gl(monkeypatch: pytest.MonkeyPatch) -> None:
    """No GL: the experiment says why, has no transcription rows, and the Python claims still hold with power."""
    import sys

    from validate.experiments.base import Context
    from validate.experiments.listings import QUICK, claims, compute, findings

    module = sys.modules["validate.experiments.listings.compute"]
    monkeypatch.setattr(module, "gl_status", lambda: (False, "no GL in this test"))
    m = compute(Context(out_dir=Path("."), quick=True, show_progress=False), QUICK)
    assert not m.transcription and "no GL in this test" in findings(m)[1]
    for c in claims(m):
        assert c.passed and c.power is not None and c.power.fails, c.id


def test_index_names_every_catalogued_listing() -> None:
    """docs/listings.md (the index) names every catalogued listing by its book number."""
    doc = (Path(__file__).resolve().parents[2] / "docs" / "listings.md").read_text()
    missing = [x.name for x in LISTINGS if x.number not in doc]
    assert not missing

"""GLSL techniques: the built-in transcriptions equal their Python originals within stated float32 bounds,
the header and plug-in paths, the one-line compile error, and the no-GL path.

Every GL test is skipped, with the reason, where llvmpipe cannot start.
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.gl import runtime
from validate.local_models import family
from validate.local_models import glsl_technique as gt

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "my_brdf.glsl"
SPECULAR_EXAMPLES = (REPO / "examples" / "my_specular.glsl", REPO / "examples" / "my_sphere_light.glsl")
UBERLIGHT_EXAMPLE = REPO / "examples" / "my_uberlight.glsl"
EPS = 2.0 ** -24  # float32 unit roundoff
OK, WHY = runtime.available("llvmpipe")
needs_gl = pytest.mark.skipif(not OK, reason=f"no llvmpipe GL: {WHY}")

# Float32 bounds of a transcription against its float64 (or float32 drjit) Python original. Inputs are
# rounded to float32 on upload (ε each) and every operation adds ≤ ε (IEEE; llvmpipe's pow/exp ≤ 5 ulp):
# * brdf: x^s has condition number s, so the relative error of (n·h)^s is ≤ s × (the ≈ 16ε error of n·h
#   after normalize(l + v)), plus ≈ 8 × 16ε for the rest; a light or viewer within ε of the horizon may
#   flip the zero branch, where q ≤ 16ε·max q (the ABS term). Measured: 2.4e-5 relative at s = 40,
#   under BRDF_REL(40) = 4.6e-5.
# * light: E = I cos θ / d² with cos θ an absolute-error quantity (grazing receivers): |ΔE| ≤ 32ε · I/d²
#   (measured 9.2ε over 20 000 random receivers).
# * sh9: a sum of 9 terms: |ΔE| ≤ 16ε · Σ|terms| (Higham, Accuracy and Stability of Numerical
#   Algorithms, 2nd ed., §4.2: γ_n Σ|x_i| for recursive summation, n = 9 plus ≤ 4 products per term).
# * env_radiance(d) at texel centres: θ and φ to a few ε rad (Newton-refined atan; Mesa's raw acos errs
#   1.6e-4 rad and would fail this by 100×), × (H − 1)/π texels per radian, × neighbour differences ≤ 1;
#   measured 13.8ε on a 9 × 16 map.
# * specular (split sum): the shader's float32 r = 2(n·v)n − v is within 8ε per component of the host's (inputs
#   rounded, one dot product, two products); the face coordinate s/m_a (m_a ≥ 1/√3) moves by ≤ 16√3ε < 32ε, the
#   texel coordinate by ≤ (N/2)·32ε = 16ε·N, and a bilinear lookup by that times the largest neighbour difference
#   ΔP of the map, in each axis: 2N·ΔP·16ε, plus its own rounding (≤ 16ε·max P). The DFG factor S = F0 A + B
#   likewise: μ moves by ≤ 16ε × n cells/unit × ΔS, plus rounding. |ΔL| ≤ 16ε [S(2NΔP + P) + P(nΔS + S)],
#   maxima over the map and table (:func:`split_sum_bound`); measured ≤ 2.9 % of it (3.1ε, α = 0.3, 0.6).
# * specular_arealight (representative point): GGX D has condition number 4(1 − α²)/α² in n·h at the peak
#   (d ln D/d cos θ_h at cos θ_h = 1), on the ≈ 16ε error of n·h, as brdf_rel(s) with s → 4/α²; the cosines
#   n·l, n·v are absolute-error quantities where G1 → 0 at the horizon: + 16ε·max L (as for brdf). Measured
#   ≤ 17 % of (4/α² + 8)·16ε|L| + 16ε max L over 20 000 receivers, α = 0.02…1.
# * uberlight (inverse square): G = A(x, y, z)·D(z) is a smooth function of the light coordinates (edges > 0; a
#   hard edge is a step, which no float bound covers), so |ΔG| ≤ |∇G|₁ δ + 2|z ∂A/∂z|·D·η + 32ε (first order):
#   δ = 8ε(|p| + |c| + |p − c|) the float32 error of each light coordinate (p, c rounded, one subtraction, a
#   3-term dot product with rounded axes, Higham §3.1), η the relative error of inner/outer from the pow chain
#   (llvmpipe's pow = exp2(e log2 x): ≈ 8ε(1 + |e ln x|) per pow; e₁e₂ = −1 makes the chain's total
#   8ε(3 + 2|e₂| + max|ln a|, |ln b| + |e₂ ln S|)), entering as a radial scaling of (x', y') — inner and outer both
#   scale by 1/λ when (x', y') scale by λ — hence through z ∂A/∂z; 2× for the two sides (drjit is float32 too).
#   The cosines n·l, n·h are absolute-error quantities: Δc = 2δ/d + 16ε (h = (l + v)/|l + v| amplifies by
#   2/|l + v|), (n·h)^s as brdf_rel; F = 1/d² gains 2δ/d + 4ε relative; + 32ε L for the products
#   (:func:`uberlight_bound`). Measured ≤ 5.7 % of it (≤ 29ε·max L) over 20 000 receivers, roundness 0.2, 1, 3.
LIGHT_ULPS = 32.0
ENV_LOOKUP_ULPS = 32.0
SUM_ULPS = 16.0


def brdf_rel(s: float) -> float:
    return (s + 8.0) * 16.0 * EPS


def split_sum_bound(padded: np.ndarray, face: int, table: object, f0: float) -> float:
    """16ε [S(2NΔP + P) + P(nΔS + S)] (the specular note above) from the map's padded faces and the DFG table."""
    pad = np.asarray(padded, dtype=np.float64)
    d_p = max(np.nanmax(np.abs(np.diff(pad, axis=1))), np.nanmax(np.abs(np.diff(pad, axis=2))))
    p_max = np.nanmax(pad)
    s = f0 * table.a + table.b  # type: ignore[attr-defined]
    d_s = max(np.abs(np.diff(s, axis=0)).max(), np.abs(np.diff(s, axis=1)).max())
    return 16 * EPS * (s.max() * (2 * face * d_p + p_max) + p_max * (s.shape[0] * d_s + s.max()))


def uberlight_bound(light: dict, pts: np.ndarray, n: np.ndarray, v: np.ndarray, mat: dict) -> np.ndarray:
    """Per-receiver |L_GLSL − L_Python| bound of the uberlight note above (float64, gradients by central
    differences of the numpy shaping, step 10⁻⁶ of each coordinate)."""
    from validate.local_models.uberlight import common as uc

    pos = np.asarray(light["position"], dtype=np.float64)
    lc, r = uc.light_coordinates(light, pts), pts - pos
    d = np.linalg.norm(r, axis=1)
    delta = 8 * EPS * (np.linalg.norm(pts, axis=1) + np.linalg.norm(pos) + d)

    def shape(q: np.ndarray) -> np.ndarray:
        return uc.superellipse_shape_np(light, q[:, 0], q[:, 1], q[:, 2])
    grad, z_dadz = np.zeros(len(lc)), np.zeros(len(lc))
    for k in range(3):
        hk = (1e-6 * (np.abs(lc[:, k]) + 1e-3))[:, None] * np.eye(3)[k]
        up, dn = lc + hk, lc - hk
        grad += np.abs(shape(up) * uc.distance_shape_np(light, up[:, 2])
                       - shape(dn) * uc.distance_shape_np(light, dn[:, 2])) / (2 * hk[:, k])
        z_dadz = np.abs(shape(up) - shape(dn)) / (2 * hk[:, k]) * np.abs(lc[:, 2])  # k = 2 last
    e2 = -float(light["roundness"]) / 2
    z = np.where(lc[:, 2] > 0, lc[:, 2], 1.0)
    logs = []
    for w, h in ((light["width"], light["height"]),
                 (light["width"] + light["width_edge"], light["height"] + light["height_edge"])):
        a, b = (np.maximum(np.abs(c * lc[:, k] / z), 1e-30) for c, k in ((h, 0), (w, 1)))
        logs.append(np.maximum(np.abs(np.log(a)), np.abs(np.log(b)))
                    + abs(e2) * np.abs(np.log(a ** (-1 / e2) + b ** (-1 / e2))))
    eta = 8 * EPS * (3 + 2 * abs(e2) + np.maximum(*logs))
    g = shape(lc) * uc.distance_shape_np(light, lc[:, 2])
    d_g = grad * delta + 2 * z_dadz * uc.distance_shape_np(light, lc[:, 2]) * eta + 32 * EPS
    hv = v - r / d[:, None]
    lh = np.linalg.norm(hv, axis=1)
    ndl = np.maximum(np.sum(n * -r, axis=1) / d, 0.0)
    ndh = np.maximum(np.sum(n * hv, axis=1) / lh, 0.0)
    rho = np.broadcast_to(np.asarray(mat["albedo"], dtype=np.float64), d.shape) / np.pi
    ks, s = float(mat["ks"]), float(mat["specular_exponent"])
    refl = rho * ndl + ks * ndh ** s
    dc = 2 * delta / d + 16 * EPS
    d_r = rho * dc + ks * (s * ndh ** (s - 1) * 2 * dc / lh + brdf_rel(s) * ndh ** s) + 16 * EPS * refl
    f = float(light["intensity"]) / d ** 2
    return f * (d_g * refl + g * (2 * delta / d + 4 * EPS) * refl + g * d_r + 32 * EPS * g * refl)


def _unit(a: np.ndarray) -> np.ndarray:
    return a / np.linalg.norm(a, axis=1, keepdims=True)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20)


@pytest.fixture
def unregister() -> Iterator[list[tuple[str, str]]]:
    """Techniques a test registers, removed afterwards (the registry is process-wide)."""
    added: list[tuple[str, str]] = []
    yield added
    for fam, name in added:
        family(fam).unregister(name)


@needs_gl
def test_builtins_registered_with_their_file() -> None:
    for fam, name in (("brdf", "glsl_blinn_phong_normalized"), ("light", "glsl_point_inverse_square"),
                      ("irradiance", "glsl_sh9"), ("shadow", "glsl_shadow_hard"), ("arealight", "glsl_inverse_square"),
                      ("specular", "glsl_split_sum_ggx"), ("specular_arealight", "glsl_representative_point"),
                      ("uberlight", "glsl_uberlight_inverse_square")):
        t = family(fam)[name]
        assert t.builtin and t.meta["runtime"] == "llvmpipe" and t.meta["glsl"].endswith(".glsl")
    assert family("light")["glsl_point_inverse_square"].meta["lights"] == ("point",)
    assert family("shadow")["glsl_shadow_hard"].meta["memory_bytes_per_texel"] == 4  # header values parse as JSON
    assert family("specular")["glsl_split_sum_ggx"].meta["brdf"] == ("ggx",)
    assert family("specular_arealight")["glsl_representative_point"].meta["shapes"] == ("sphere",)


@needs_gl
@pytest.mark.parametrize("s", [1.0, 40.0, 200.0])
def test_brdf_transcription(rng: np.random.Generator, s: float) -> None:
    n, l, v = (_unit(rng.standard_normal((4000, 3))) for _ in range(3))
    params = {"albedo": [0.8, 0.5, 0.2], "ks": 0.3, "exponent": s}
    fam = family("brdf")
    g = fam.call("glsl_blinn_phong_normalized", params, n, l, v)
    p = fam.call("blinn_phong_normalized", params, n, l, v)
    assert (p > 0).sum() > 1000  # the comparison covers lit configurations, not only zeros
    assert np.all(np.abs(g - p) <= brdf_rel(s) * np.abs(p) + 16 * EPS * p.max())


@needs_gl
def test_light_transcription(rng: np.random.Generator) -> None:
    n = _unit(rng.standard_normal((5000, 3)))
    pts = rng.uniform(-1.0, 1.0, (5000, 3))
    pos = np.array([0.3, 2.0, 0.1])
    light = {"type": "point", "position": pos, "intensity": 5.0}
    fam = family("light")
    g = fam.call("glsl_point_inverse_square", light, pts, n)
    p = fam.call("point_inverse_square", light, pts, n)
    scale = 5.0 / np.sum((pos - pts) ** 2, axis=1)
    assert (p > 0).sum() > 1000
    assert np.all(np.abs(g - p) <= LIGHT_ULPS * EPS * scale)


@needs_gl
@pytest.mark.parametrize("shape", ["disc", "sphere"])
def test_arealight_transcription(rng: np.random.Generator, shape: str) -> None:
    """glsl_inverse_square vs inverse_square: E = πr²L cos ψ cos θ/d², both cosines absolute-error
    quantities, so |ΔE| ≤ 32ε·πr²L/d² as for the point light (measured 7.2ε)."""
    n = _unit(rng.standard_normal((5000, 3)))
    pts = np.c_[rng.uniform(-2, 2, 5000), rng.uniform(-2, 0.5, 5000), rng.uniform(-2, 2, 5000)]
    light = {"shape": shape, "center": np.array([0.1, 1.5, 0.2]), "normal": np.array([0.0, -1.0, 0.0]),
             "radius": 0.3, "radiance": 4.0}
    fam = family("arealight")
    g, p = fam.call("glsl_inverse_square", light, pts, n), fam.call("inverse_square", light, pts, n)
    scale = np.pi * 0.3**2 * 4.0 / np.sum((light["center"] - pts) ** 2, axis=1)
    assert (p > 0).sum() > 1000 and fam["glsl_inverse_square"].meta["shapes"] == ("sphere", "disc")
    assert np.all(np.abs(g - p) <= LIGHT_ULPS * EPS * scale)


@needs_gl
def test_specular_transcription(rng: np.random.Generator) -> None:
    """glsl_split_sum_ggx vs split_sum_ggx on random and on axis / edge / corner reflection vectors (face seams),
    within :func:`split_sum_bound`; the harness's sparse map covers the shader's r (no NaN read)."""
    from validate.local_models.specular import split_sum as ss
    from validate.local_models.specular.common import reflect

    n, v = _unit(rng.standard_normal((2000, 3))), _unit(rng.standard_normal((2000, 3)))
    v = np.where(np.sum(n * v, axis=1, keepdims=True) < 0, -v, v)
    axes = _unit(np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [0, 1, 1], [1, 0, 1], [1, 1, 1]], float))
    n, v = np.r_[n, axes, -axes], np.r_[v, axes, -axes]
    rad = rng.uniform(0.0, 2.0, (16, 32, 3))
    fam = family("specular")
    for alpha in (0.3, 0.6):
        brdf = {"model": "ggx", "alpha": alpha, "f0": 0.7}
        g, p = fam.call("glsl_split_sum_ggx", rad, brdf, n, v), fam.call("split_sum_ggx", rad, brdf, n, v)
        cube = ss.cached_ggx_cube(rad, alpha, reflect(n, v))
        assert np.all(np.isfinite(g)) and p.min() > 0.1  # lit everywhere: the bound is not met by zeros
        assert np.all(np.abs(g - p) <= split_sum_bound(cube.padded, cube.face_size, ss.default_dfg_table(), 0.7))
    with pytest.raises(ValidateError, match=r"glsl_split_sum_ggx.*split_sum\.glsl.*BRDF model 'phong'"):
        fam.call("glsl_split_sum_ggx", rad, {"model": "phong", "exponent": 10.0}, n, v)


@needs_gl
def test_specular_arealight_transcription(rng: np.random.Generator) -> None:
    n, v = _unit(rng.standard_normal((20000, 3))), _unit(rng.standard_normal((20000, 3)))
    pts = rng.uniform(-2.0, 2.0, (20000, 3))
    light = {"shape": "sphere", "center": np.array([0.1, 2.5, 0.2]), "radius": 0.4, "radiance": 3.0}
    fam = family("specular_arealight")
    for alpha in (0.1, 0.3, 1.0):
        brdf = {"alpha": alpha, "f0": [0.9, 0.5, 0.04]}
        g = fam.call("glsl_representative_point", light, brdf, pts, n, v)
        p = fam.call("representative_point", light, brdf, pts, n, v)
        assert (p > 0).sum() > 10000
        assert np.all(np.abs(g - p) <= (4 / alpha**2 + 8) * 16 * EPS * p + 16 * EPS * p.max())
    with pytest.raises(ValidateError, match=r"glsl_representative_point.*light shape 'disc'"):
        fam.call("glsl_representative_point", dict(light, shape="disc", normal=(0, -1, 0)), brdf, pts, n, v)


def _uberlight_case(rng: np.random.Generator, n_pts: int) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray, dict]:
    """A tilted überlight above receivers in front of and behind it, soft edges and distance shaping on."""
    fwd = _unit(np.array([[0.1, -1.0, 0.05]]))[0]
    x = _unit(np.cross(fwd, [0.0, 0.0, 1.0])[None])[0]
    axes, pos = np.stack([x, np.cross(fwd, x), fwd]), np.array([0.2, 2.0, 0.1])
    z = rng.uniform(-0.5, 3.5, n_pts)  # 4 in 5 inside the cone |x'|, |y'| < 0.8 (beam and penumbra), 1 in 5 anywhere
    lc = np.c_[rng.uniform(-0.8, 0.8, (n_pts, 2)) * np.abs(z)[:, None], z]
    pts = np.where((np.arange(n_pts) % 5 == 0)[:, None], rng.uniform(-2, 2, (n_pts, 3)), pos + lc @ axes)
    light = {"position": pos, "axes": axes, "intensity": 50.0,
             "width": 0.5, "height": 0.3, "width_edge": 0.1, "height_edge": 0.05, "roundness": 1.0, "near": 0.5,
             "far": 2.5, "near_edge": 0.3, "far_edge": 0.5}
    mat = {"albedo": rng.uniform(0.2, 0.9, n_pts), "ks": 0.3, "specular_exponent": 20.0}
    return light, pts, _unit(rng.standard_normal((n_pts, 3))), _unit(rng.standard_normal((n_pts, 3))), mat


@needs_gl
def test_uberlight_transcription(rng: np.random.Generator) -> None:
    """glsl_uberlight_inverse_square vs uberlight_inverse_square within :func:`uberlight_bound` (roundness 0.2, 1,
    3); a width 0.1 % too large on the GLSL side breaks it (the bound is tight enough to see a real bug)."""
    from validate.local_models.uberlight import common as uc

    light, pts, n, v, mat = _uberlight_case(rng, 20000)
    fam = family("uberlight")
    for rnd in (0.2, 1.0, 3.0):
        lr = dict(light, roundness=rnd)
        g, p = (fam.call(t, lr, pts, n, v, mat) for t in ("glsl_uberlight_inverse_square", "uberlight_inverse_square"))
        bound = uberlight_bound(lr, pts, n, v, mat)
        lc = uc.light_coordinates(lr, pts)
        shaped = uc.superellipse_shape_np(lr, *lc.T) * uc.distance_shape_np(lr, lc[:, 2])
        assert (p > 0).sum() > 500 and ((p > 0) & (shaped < 1)).sum() > 200  # lit, many in a penumbra
        assert np.all(np.abs(g - p) <= bound), float(np.max(np.abs(g - p) / np.maximum(bound, 1e-300)))
    p, bound = fam.call("uberlight_inverse_square", light, pts, n, v, mat), uberlight_bound(light, pts, n, v, mat)
    wide = fam.call("glsl_uberlight_inverse_square", dict(light, width=0.5005), pts, n, v, mat)
    assert (np.abs(wide - p) > bound).sum() > 100  # roundness 1, the width 0.1 % too large: fails by far
    shadow = rng.uniform(0.0, 1.0, len(pts))
    base = fam.call("glsl_uberlight_inverse_square", light, pts, n, v, mat)
    shadowed = fam.call("glsl_uberlight_inverse_square", light, pts, n, v, mat, shadow=shadow)
    assert np.array_equal(shadowed, base * shadow)  # the host's visibility multiplies, as in the Python techniques


@needs_gl
def test_uberlight_example_plugin(rng: np.random.Generator) -> None:
    """The example compiles and, at roundness 1 with hard edges and no distance shaping (its exact case), equals
    uberlight_inverse_square with ks = 0 away from the edge (|A change| within 10⁻⁴ of the edge excluded)."""
    from validate.local_models.uberlight.common import NO_DISTANCE_SHAPING

    tech = gt.technique_from_file(UBERLIGHT_EXAMPLE, "uberlight")
    light, pts, n, v, mat = _uberlight_case(rng, 5000)
    light = dict(light, width_edge=0.0, height_edge=0.0, **NO_DISTANCE_SHAPING)
    mat = dict(mat, ks=0.0)
    fam = family("uberlight")
    g, p = fam.call(tech, light, pts, n, v, mat), fam.call("uberlight_inverse_square", light, pts, n, v, mat)
    far = (np.abs(fam.call("uberlight_inverse_square", dict(light, width=0.5001, height=0.30006), pts, n, v, mat) - p)
           == 0) & (np.abs(fam.call("uberlight_inverse_square", dict(light, width=0.4999, height=0.29994), pts, n, v,
                                    mat) - p) == 0)
    assert (p[far] > 0).sum() > 100 and far.sum() > 0.9 * len(p)
    assert np.allclose(g[far], p[far], rtol=1e-5, atol=1e-6 * p.max())


@needs_gl
@pytest.mark.parametrize("path", SPECULAR_EXAMPLES, ids=lambda p: p.name)
def test_specular_example_plugins(path: Path, rng: np.random.Generator) -> None:
    """The two example plug-ins compile and give finite, non-negative, non-zero radiance (their accuracy is
    what `run ibl` / `run arealights` measure)."""
    tech = gt.technique_from_file(path)
    n = _unit(rng.standard_normal((500, 3)))
    v = _unit(n + 0.5 * _unit(rng.standard_normal((500, 3))))
    if tech.family == "specular":
        out = family("specular").call(tech, rng.uniform(0.0, 1.0, (8, 16, 3)), {"model": "ggx", "alpha": 0.6}, n, v)
    else:
        light = {"shape": "sphere", "center": np.array([0.0, 3.0, 0.0]), "radius": 0.5, "radiance": 2.0}
        out = family("specular_arealight").call(tech, light, {"alpha": 0.5}, np.zeros((500, 3)), n, v)
    assert np.all(np.isfinite(out)) and out.min() >= 0.0 and out.max() > 0.0


@needs_gl
@pytest.mark.parametrize("fam", ["specular", "specular_arealight", "uberlight"])
def test_specular_families_compile_error_is_one_line(fam: str, tmp_path: Path) -> None:
    """A compile error is one line naming file:line (the CLI prints it as `validate: error: ...`, exit 2: the
    brdf test above runs that path)."""
    f = tmp_path / "broken.glsl"
    entry = {"specular": "vec3 specular(vec3 n, vec3 v)", "specular_arealight": "vec3 shade(vec3 p, vec3 n, vec3 v)",
             "uberlight": "vec3 shade(vec3 p, vec3 n, vec3 v, float albedo)"}[fam]
    f.write_text(f"// validate: family={fam}\n// validate: name=t_broken\n{entry} {{\n    return prefiltered(n)\n}}\n")
    with pytest.raises(ValidateError) as exc:
        gt.load_glsl(f)
    assert str(exc.value).startswith(f"{f}:5: syntax error") and "\n" not in str(exc.value), str(exc.value)
    assert "t_broken" not in family(fam)


@needs_gl
def test_light_shadow_is_the_hosts(rng: np.random.Generator) -> None:
    """V comes from the scene's shadow-ray test, as for the Python technique: everything occluded → 0."""
    n = np.tile([0.0, 1.0, 0.0], (50, 1))
    pts = np.c_[rng.uniform(-1, 1, 50), np.zeros(50), rng.uniform(-1, 1, 50)]
    light = {"type": "point", "position": np.array([0.0, 2.0, 0.0]), "intensity": 1.0}
    none = family("light").call("glsl_point_inverse_square", light, pts, n,
                                visible=lambda o, nn, t: np.zeros(len(o), dtype=bool))
    assert np.all(none == 0.0)


@needs_gl
def test_irradiance_transcription(rng: np.random.Generator) -> None:
    from validate.local_models.irradiance.sh import C1, C2, C3, C4, C5, project_environment

    rad = rng.uniform(0.0, 2.0, (32, 64, 3))
    n = _unit(rng.standard_normal((3000, 3)))
    fam = family("irradiance")
    g, p = fam.call("glsl_sh9", rad, n), fam.call("sh9", rad, n)
    c = np.abs(project_environment(rad, 2))
    x, y, z = (np.abs(n[:, k])[:, None] for k in range(3))
    terms = (C1 * c[8] * (x * x + y * y) + (C3 + C5) * c[6] * (z * z + 1) + C4 * c[0]
             + 2 * C1 * (c[4] * x * y + c[7] * x * z + c[5] * y * z) + 2 * C2 * (c[3] * x + c[1] * y + c[2] * z))
    assert np.all(np.abs(g - p) <= SUM_ULPS * EPS * terms)


@needs_gl
def test_shadow_transcription(rng: np.random.Generator) -> None:
    """glsl_shadow_hard equals hard receiver for receiver on a synthetic D24 map: both compare the same
    float32 z_r with the same float32 D + o; a disagreement is allowed only where |z_r − (D + o)| is within
    4ε (a fused multiply-add may round the offset differently); measured 0 of 20 000."""
    from validate.backend import float_type
    from validate.local_models.shadow import shadow_map as smod
    from validate.scenes.shadow_scenes import DiscLight

    F = float_type()
    light = DiscLight((0.0, 3.0, 0.0), (0.0, 0.0, 0.0), 0.5, 10.0)
    pts = np.c_[rng.uniform(-2, 2, 20000), np.zeros(20000), rng.uniform(-2, 2, 20000)]
    view = smod.fit_light_view(light, pts)
    view.near, view.far = 0.5, 3.5
    r = 128
    depth = rng.uniform(0.3, 1.0, (r, r))
    depth[depth > 0.9] = 1.0  # empty texels
    dw = smod.quantise_depth(F(depth.ravel().astype(np.float32)))
    slope = rng.uniform(0.0, 1e-4, r * r)
    sm = smod.ShadowMap(view, r, dw, F(slope.astype(np.float32)))
    n = np.tile([0.0, 1.0, 0.0], (len(pts), 1))
    g = family("shadow").call("glsl_shadow_hard", sm, light, pts, n)
    p = family("shadow").call("hard", sm, light, pts, n)
    assert 0.05 < p.mean() < 0.95  # both lit and shadowed receivers are compared
    x, y, z_w, _ = sm.window_coords(pts)
    i, j = np.floor(x).astype(int), np.floor(y).astype(int)
    inside = (i >= 0) & (j >= 0) & (i < r) & (j < r)
    occ = np.ones(len(pts)) * 2.0
    d = np.array(dw, dtype=np.float64).reshape(r, r)
    occ[inside] = d[j[inside], i[inside]] + 2.0 * slope.reshape(r, r)[j[inside], i[inside]] + 4.0 * 2.0 ** -24
    near_tie = np.abs(z_w - occ) < 4 * EPS
    assert np.all((g == p) | near_tie)


@needs_gl
def test_env_radiance_lookup_matches_mitsuba_convention(tmp_path: Path, unregister: list) -> None:
    """The declared helper env_radiance(d) returns the map's texel at each texel-centre direction."""
    from validate.scenes import latlong

    (tmp_path / "look.glsl").write_text("// validate: family=irradiance\n// validate: name=t_lookup\n"
                                        "vec3 irradiance(vec3 n) { return env_radiance(n); }\n")
    tech = gt.technique_from_file(tmp_path / "look.glsl", "irradiance")
    rad = np.random.default_rng(3).uniform(0.0, 1.0, (9, 16, 3))
    th, ph = np.meshgrid(latlong.row_theta(9)[1:-1], latlong.col_phi(16), indexing="ij")
    d = latlong.spherical_to_direction(th, ph).reshape(-1, 3)
    out = family("irradiance").call(tech, rad, d)
    assert np.allclose(out, rad[1:-1].reshape(-1, 3), rtol=0, atol=ENV_LOOKUP_ULPS * EPS)


def test_header_errors(tmp_path: Path) -> None:
    f = tmp_path / "h.glsl"
    f.write_text("// validate: family=nope\n")
    with pytest.raises(ValidateError, match="h.glsl: header"):
        gt.parse_glsl(f)
    f.write_text("// validate: family=brdf\n// validate: thresholds={bad\n")
    with pytest.raises(ValidateError, match="thresholds= is not JSON"):
        gt.parse_glsl(f)
    src = gt.parse_glsl(EXAMPLE)
    assert src.name == "my_modified_phong" and src.thresholds == {"max_rel.modphong_s20": 1e-4,
                                                                  "max_rel.diffuse_r0.8": 1e-4}


@needs_gl
def test_broken_plugin_is_one_line_exit_2_nothing_written(tmp_path: Path, capsys: pytest.CaptureFixture,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    from validate.cli import main

    monkeypatch.chdir(tmp_path)
    Path("broken.glsl").write_text("// validate: family=brdf\n// validate: name=t_broken\n"
                                   "vec3 brdf(vec3 n, vec3 l, vec3 v) {\n    return vec3(1.0)\n}\n")
    assert main(["run", "brdfs", "--quick", "--plugin", "broken.glsl", "--out", "out"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("validate: error: broken.glsl:5: syntax error"), err
    assert not Path("out").exists() and "t_broken" not in family("brdf")


@needs_gl
def test_signature_mismatch_is_named(tmp_path: Path) -> None:
    f = tmp_path / "sig.glsl"
    f.write_text("// validate: family=brdf\nvec3 brdf(vec3 n, vec3 l) { return n; }\n")
    with pytest.raises(ValidateError, match=r"sig\.glsl"):
        gt.technique_from_file(f)


@needs_gl
def test_list_shows_plugin_and_builtins(capsys: pytest.CaptureFixture, unregister: list) -> None:
    from validate.cli import main

    unregister.append(("brdf", "my_modified_phong"))
    assert main(["list", "--plugin", str(EXAMPLE)]) == 0
    out = capsys.readouterr().out
    assert "my_modified_phong" in out and "[GLSL llvmpipe] [plug-in]" in out
    assert "glsl_sh9" in out and "GLSL techniques (llvmpipe): registered" in out
    assert "GLSL entry point (docs/glsl.md): vec3 brdf(vec3 n, vec3 l, vec3 v)" in out


def test_list_tag_names_runtime_and_seed() -> None:
    from validate.cli.commands import _glsl_tag
    from validate.local_models.registry import Technique

    t = Technique("x", "brdf", lambda: None, "", meta={"glsl": "x.glsl", "runtime": "webgl2",
                                                        "seed": "Fore June ch. 20, eq. 20.47"})
    assert _glsl_tag(t) == " [GLSL webgl2; seed Fore June ch. 20, eq. 20.47]"
    assert _glsl_tag(Technique("y", "brdf", lambda: None, "")) == ""


def test_without_gl_not_registered_and_said_why() -> None:
    """A process without GL: no GLSL technique registered, `list` says why (runs with or without GL)."""
    env = dict(os.environ, VALIDATE_NO_GL="1", PYTHONPATH=str(REPO))
    out = subprocess.run([sys.executable, "-m", "validate", "list"], cwd=REPO, env=env, capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "GLSL techniques (llvmpipe): not registered: VALIDATE_NO_GL is set" in out.stdout
    assert "glsl_sh9" not in out.stdout


def test_glsl_plugin_without_gl_is_one_line(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture) -> None:
    from validate.cli import main

    monkeypatch.setattr(gt, "gl_status", lambda kind="llvmpipe": (False, "no EGL display"))
    monkeypatch.chdir(REPO)
    assert main(["list", "--plugin", "examples/my_brdf.glsl"]) == 2
    assert capsys.readouterr().err.strip() == ("validate: error: examples/my_brdf.glsl: GL runtime llvmpipe "
                                               "unavailable: no EGL display")
    assert "my_modified_phong" not in family("brdf")


@pytest.mark.slow
@pytest.mark.parametrize("fname", ["irradiance/sh9.glsl", "brdf/blinn_phong_normalized.glsl",
                                   "light/point_inverse_square.glsl"])
def test_same_file_on_webgl2(rng: np.random.Generator, fname: str) -> None:
    """Each built-in file run on Chromium WebGL2 (SwiftShader) equals its llvmpipe run: these shaders use
    only +, −, ×, /, sqrt, normalize and pow, which both implement to a few ulp (SwiftShader's coarse sin/cos
    are not involved). Bound: 64 ulp of the output scale (measured ≤ 8 ulp for sh9, 2.3e-5 relative for
    pow(n·h, 40), 1.9e-5 relative for the light at grazing receivers, all inside the llvmpipe bounds above)."""
    ok, why = runtime.available("webgl2")
    if not ok:
        pytest.skip(f"no WebGL2: {why}")
    src = gt.parse_glsl(gt.BUILTIN_DIR / fname)
    tech = gt.technique_from_file(gt.BUILTIN_DIR / fname, runtime="webgl2", name="t_webgl2")
    n = _unit(rng.standard_normal((3000, 3)))
    args = {"irradiance": (rng.uniform(0.0, 2.0, (32, 64, 3)), n),
            "brdf": ({"albedo": [0.8, 0.5, 0.2], "ks": 0.3, "exponent": 40.0}, n, _unit(rng.standard_normal((3000, 3))),
                     _unit(rng.standard_normal((3000, 3)))),
            "light": ({"type": "point", "position": np.array([0.3, 2.0, 0.1]), "intensity": 5.0},
                      rng.uniform(-1.0, 1.0, (3000, 3)), n)}[src.family]
    fam = family(src.family)
    web, llvm = fam.call(tech, *args), fam.call(src.name, *args)
    scale = np.abs(llvm).max()
    rel = brdf_rel(40.0) if src.family == "brdf" else 0.0
    assert np.all(np.abs(web - llvm) <= rel * np.abs(llvm) + 64 * EPS * scale)  # chromium stays up (atexit)


@needs_gl
def test_check_irradiance_accepts_a_glsl_file() -> None:
    """validate.testing: a .glsl path is compiled and measured like its Python original — the same metric
    to the transcription's float32 bound (E agrees to 16ε·Σ|terms| ≲ 1e-6 of Φ/π; 1e-5 of the flux leaves
    10× margin while a wrong SH order or a missing 2 in eq. 12 moves it by > 1e-2)."""
    from validate.testing import check_irradiance

    path = gt.BUILTIN_DIR / "irradiance" / "sh9.glsl"
    g = check_irradiance(str(path), environments=("two_tone",), normals=200)
    p = check_irradiance("sh9", environments=("two_tone",), normals=200)
    assert g.technique == "glsl_sh9"
    assert abs(g.flux_luminance.max - p.flux_luminance.max) < 1e-5
    with pytest.raises(ValidateError, match=r"a irradiance technique \(header family=\), not brdf"):
        gt.technique_from_file(path, "brdf")


@needs_gl
@pytest.mark.slow
def test_check_brdf_accepts_the_example() -> None:
    """The example's declared bound (max_rel.modphong_s20 < 1e-4, Mitsuba's modphong in float32) holds
    through validate.testing, the bound clearing with its uncertainty."""
    from validate.testing import check_brdf

    r = check_brdf(str(EXAMPLE), ["modphong_s20"])
    assert r.max_rel.max + r.max_rel.max_uncertainty < 1e-4

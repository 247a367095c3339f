"""The seeds' hemisphere and spherical-harmonic listings (fixed lighting: no family contract), run and transcribed.

* Fore June Listing 20-1 [1, §20.2]: C = mix(groundColor, skyColor, ½ + ½ n·skyDirection), n =
  normalize(vPosition.xyz) (objType 0: the sphere's normal is its position) — eq. 20.7;
* Fore June SH disc source [1, §20.4.3]: E(z) = C0 (1 − cos α) + C1 sin²α z + C2 cos α (1 − cos²α)(3z² − 1),
  α = 20°, z = n_z — eq. 20.30;
* Fore June SH Grace Cathedral [1, §20.4.4]: eq. 20.33 with Table 20-1's coefficients;
* Red Book Example 7.12 [2]: a = ½ + ½ cos θ, Color = mix(Ground, Sky, a), cos θ = n·normalize(LightPosition − p);
* Red Book Example 7.14 [2]: eq. 7.1 with the Old Town Square coefficients × ScaleFactor.

These compute lighting the book hard-codes (a two-colour sky, one SH environment), so they are checked
against their float64 transcriptions only (the irradiance family's contract takes an environment map).
Host state: mvpMatrix / MVPMatrix = the per-receiver placement, MVMatrix = NormalMatrix = I.

References
  [1] Fore June, *An Introduction to 3D Computer Graphics …*, ch. 20, Listing 20-1, §20.4.3–20.4.4.
  [2] J. Kessenich, G. Sellers, D. Shreiner, *OpenGL Programming Guide*, ch. 7, Examples 7.12 and 7.14.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ...gl.listing_harness import Placement, homogeneous
from .runner import run, unit

SKY, GROUND, SKY_DIR = (0.5, 0.5, 1.0, 1.0), (0.2, 1.0, 0.2, 1.0), (0.0, 1.0, 0.0)  # Figure 20-3's values
GRACE = np.array([[0.79, 0.44, 0.54], [0.39, 0.35, 0.60], [-0.34, -0.18, -0.27], [-0.29, -0.06, 0.01],
                  [-0.11, -0.05, -0.12], [-0.26, -0.22, -0.47], [-0.16, -0.09, -0.15], [0.56, 0.21, 0.14],
                  [0.21, -0.05, -0.30]])  # L00, L1-1, L10, L11, L2-2, L2-1, L20, L21, L22 (Table 20-1)
OLD_TOWN = np.array([[0.871297, 0.875222, 0.864470], [0.175058, 0.245335, 0.312891], [0.034675, 0.036107, 0.037362],
                     [-0.004629, -0.029448, -0.048028], [-0.120535, -0.121160, -0.117507],
                     [0.003242, 0.003624, 0.007511], [-0.028667, -0.024926, -0.020998],
                     [-0.077539, -0.086325, -0.091591], [-0.161784, -0.191783, -0.219152]])  # Example 7.14
C1, C2, C3, C4, C5 = 0.429043, 0.511664, 0.743125, 0.886227, 0.247708


def sh_eq(n: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Eq. 20.33 / 7.1: c1 L22 (x² − y²) + c3 L20 z² + c4 L00 − c5 L20 + 2c1 (L2−2 xy + L21 xz + L2−1 yz)
    + 2c2 (L11 x + L1−1 y + L10 z), (N, 3)."""
    x, y, z = (n[:, k:k + 1] for k in range(3))
    l00, l1m1, l10, l11, l2m2, l2m1, l20, l21, l22 = c
    return (C1 * l22 * (x * x - y * y) + C3 * l20 * z * z + C4 * l00 - C5 * l20
            + 2 * C1 * (l2m2 * x * y + l21 * x * z + l2m1 * y * z) + 2 * C2 * (l11 * x + l1m1 * y + l10 * z))


def python(name: str, points: np.ndarray, normals: np.ndarray | None = None, scale: float = 1.0) -> np.ndarray:
    """(N, 3) the listing's colour in float64."""
    p = np.asarray(points, dtype=np.float64)
    if name == "forejune_20_1":
        f = 0.5 + 0.5 * unit(p) @ np.asarray(SKY_DIR)
        return (1 - f)[:, None] * np.asarray(GROUND[:3]) + f[:, None] * np.asarray(SKY[:3])
    if name == "forejune_20_4_disc":
        z = unit(p)[:, 2]
        a = np.radians(20.0)
        e = 1.57079 * (1 - np.cos(a)) + 1.57080 * np.sin(a) ** 2 * z + 0.490874 * np.cos(a) * (
            1 - np.cos(a) ** 2) * (3 * z * z - 1)
        return np.repeat(e[:, None], 3, axis=1)
    if name == "forejune_20_4_grace":
        return sh_eq(unit(p), GRACE)
    if name == "redbook_7_12":
        a = 0.5 + 0.5 * np.sum(unit(normals) * unit(np.asarray(SKY_DIR) * 10.0 - p), axis=1)
        return (1 - a)[:, None] * np.asarray(GROUND[:3]) + a[:, None] * np.asarray(SKY[:3])
    return sh_eq(unit(normals), OLD_TOWN) * scale  # redbook_7_14


def glsl(name: str, points: np.ndarray, normals: np.ndarray | None = None, scale: float = 1.0) -> np.ndarray:
    """(N, 3) the listing run with the host state of the module docstring."""
    p4 = homogeneous(points)
    kw: dict[str, Any]
    if name.startswith("forejune"):
        kw = {"placement": Placement("mvpMatrix"), "attributes": {"vPosition": p4},
              "uniforms": {"objType": 0, "skyColor": SKY, "groundColor": GROUND, "skyDirection": SKY_DIR}}
    else:
        kw = {"placement": Placement("MVPMatrix"), "attributes": {"VertexPosition": p4, "VertexNormal": normals},
              "uniforms": {"MVMatrix": np.eye(4), "NormalMatrix": np.eye(3), "ScaleFactor": scale,
                           "LightPosition": tuple(10.0 * np.asarray(SKY_DIR)), "SkyColor": SKY[:3],
                           "GroundColor": GROUND[:3]}}
    return run(name, p4, **kw)[:, :3].astype(np.float64)


NAMES = ("forejune_20_1", "forejune_20_4_disc", "forejune_20_4_grace", "redbook_7_12", "redbook_7_14")

__all__ = ["GRACE", "NAMES", "OLD_TOWN", "glsl", "python", "sh_eq"]

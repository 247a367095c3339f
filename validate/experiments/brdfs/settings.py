"""``brdfs`` settings: everything that differs between ``--quick`` and the full run (:data:`QUICK`, :data:`FULL`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

NAME = "brdfs"



@dataclass(frozen=True)
class Settings:
    grid: int  # Gauss–Legendre nodes in cos θ_l and cos θ_v, and Δφ nodes
    furnace: tuple[int, int]  # (cos θ nodes, φ nodes) of the furnace quadrature
    furnace_views_deg: tuple[float, ...]
    alphas: tuple[float, ...]  # Beckmann roughness of the conductor materials
    ggx_alphas: tuple[float, ...]
    phong_exponents: tuple[float, ...]  # modified-Phong materials
    sweep_alphas: tuple[float, ...]  # energy sweep (mirror F = 1)
    sigmas_deg: tuple[float, ...]  # V-groove slope deviations (first: the Lambert limit)
    thetas_deg: tuple[float, ...]
    dphis_deg: tuple[float, ...]
    n_slope: int
    n_orient: int
    paths: int
    depth: int
    gouraud_levels: tuple[int, ...] = (1, 2, 3)  # icosphere subdivisions (80 … 1280 triangles)
    gouraud_exponents: tuple[float, ...] = (5.0, 20.0, 100.0)  # modified-Phong exponents of the sweep
    gouraud_image: int = 80
    env_image: int = 20  # sphere under an environment: pixels across
    env_nodes: int = 12  # local quadrature: Gauss–Legendre cos θ nodes (× 2·nodes φ) about each normal
    env_spp: int = 64  # Mitsuba path-traced spp (4 passes)
    albedo: float = 0.8
    image: int = 64
    minnaert_ks: tuple[float, ...] = tuple(float(k) for k in np.round(np.arange(0.5, 1.51, 0.05), 2))


QUICK = Settings(grid=20, furnace=(48, 96), furnace_views_deg=(0.0, 45.0, 75.0), alphas=(0.2, 0.5), ggx_alphas=(0.3,),
                 phong_exponents=(20.0,), sweep_alphas=(0.1, 0.2, 0.3, 0.5, 0.8), sigmas_deg=(2.0, 20.0, 40.0),
                 thetas_deg=(0.0, 30.0, 60.0, 75.0), dphis_deg=(0.0, 90.0, 180.0), n_slope=5, n_orient=6,
                 paths=128, depth=10, image=48)
FULL = Settings(grid=40, furnace=(128, 256), furnace_views_deg=(0.0, 30.0, 45.0, 60.0, 75.0, 85.0),
                alphas=(0.1, 0.2, 0.3, 0.5), ggx_alphas=(0.1, 0.3), phong_exponents=(20.0, 100.0),
                sweep_alphas=(0.05, 0.1, 0.2, 0.3, 0.5, 0.8, 1.0), sigmas_deg=(2.0, 10.0, 20.0, 30.0, 40.0),
                thetas_deg=(0.0, 20.0, 40.0, 60.0, 75.0, 85.0), dphis_deg=(0.0, 45.0, 90.0, 135.0, 180.0),
                n_slope=8, n_orient=8, paths=512, depth=12, image=96, gouraud_levels=(1, 2, 3, 4, 5, 6),
                gouraud_exponents=(5.0, 20.0, 100.0, 500.0), gouraud_image=192, env_image=48, env_nodes=48,
                env_spp=256)

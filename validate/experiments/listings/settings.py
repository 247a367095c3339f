"""Settings of the ``listings`` experiment (one frozen dataclass, QUICK and FULL)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Settings:
    receivers: int  # random receivers per GLSL-vs-Python transcription check
    brdf_grid: int  # Gauss–Legendre nodes (cos θ_l, cos θ_v, Δφ) of the Cook–Torrance comparison (and n/2)
    ct_alphas: tuple[float, ...]  # Beckmann roughness of Mitsuba's conductor
    plane_half: float  # the point-light receivers: the plane y = 0, x, z ∈ [−h, h]
    plane_nodes: int  # receivers per side
    falloff_nodes: int  # distances in (0, 20 r] for the falloff comparison
    projector_size: tuple[int, int]  # (width, height) of the projector render
    texture: int  # projector texture size
    barndoor_spp: int = 16  # path-traced barn door: samples per pixel per pass
    barndoor_passes: int = 4
    barndoor_depth: float = 0.1  # m: disc-to-hole depth of the barn door
    fov_deg: float = 70.0
    seed: int = 1234


QUICK = Settings(receivers=512, brdf_grid=20, ct_alphas=(0.2, 0.5), plane_half=3.0, plane_nodes=24,
                 falloff_nodes=2000, projector_size=(64, 48), texture=512)
FULL = Settings(receivers=4096, brdf_grid=40, ct_alphas=(0.1, 0.2, 0.3, 0.5), plane_half=3.0, plane_nodes=64,
                falloff_nodes=20000, projector_size=(128, 96), texture=1024, barndoor_spp=64, barndoor_passes=8)

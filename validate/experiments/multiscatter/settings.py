"""``multiscatter`` settings: everything that differs between ``--quick`` and the full run
(:data:`QUICK`, :data:`FULL`)."""

from __future__ import annotations

from dataclasses import dataclass

NAME = "multiscatter"



@dataclass(frozen=True)
class Settings:
    alphas: tuple[float, ...]
    mus: tuple[float, ...]
    metalness: tuple[float, ...]
    nodes: int  # cos θ_l nodes (φ: 2×)
    walkers: int  # Heitz et al. 2016 random walks per (α, μ_v)
    f0s: tuple[float, ...] = (0.04, 0.5)
    walk_alphas: tuple[float, ...] = (0.3, 0.6, 1.0)
    walk_mu: float = 0.5
    walk_f0s: tuple[float, ...] = (1.0, 0.9, 0.5, 0.04)
    # the random walk as a Mitsuba BSDF (validate.reference.microsurface_bsdf): its own checks
    bsdf_checks: bool = True
    chi2_cases: tuple[tuple[float, float], ...] = ((0.3, 30.0), (0.3, 70.0), (0.6, 50.0), (1.0, 20.0))  # (α, θ_i°)
    chi2_samples: int = 400_000
    chi2_res: int = 51  # cos θ rows (φ: res/2 columns), Mitsuba's ChiSquareTest layout
    chi2_walks: int = 32  # walks per pdf point and repeat (4 repeats)
    recip_f0s: tuple[float, ...] = (1.0, 0.5)
    recip_lanes: int = 256  # × 64 walks per direction pair and side
    furnace_mus: tuple[float, ...] = (0.2, 0.7)
    furnace_directions: int = 200_000
    render_spp: int = 32  # 32 × 32 pixels


QUICK = Settings(alphas=(0.25, 0.5, 0.75, 1.0), mus=(0.1, 0.3, 0.5, 0.8, 1.0), metalness=(0.0, 0.5, 1.0), nodes=128,
                 walkers=100_000)
FULL = Settings(alphas=(0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0), mus=(0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.0),
                metalness=(0.0, 0.25, 0.5, 0.75, 1.0), nodes=192, walkers=2_000_000,
                chi2_cases=((0.1, 30.0), (0.3, 30.0), (0.3, 70.0), (0.6, 50.0), (1.0, 20.0), (1.0, 80.0)),
                chi2_samples=2_000_000, chi2_res=101, recip_lanes=1024, furnace_directions=1_000_000, render_spp=128)

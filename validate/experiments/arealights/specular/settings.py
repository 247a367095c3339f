"""Settings of the specular part of ``arealights``: a field of the parent's
:class:`~validate.experiments.arealights.settings.Settings`, whose ``QUICK`` and ``FULL`` hold its values."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SpecularSettings:
    """The specular part (:mod:`validate.experiments.arealights.specular`): GGX α, light half-angles σ, quadrature
    nodes, the render check."""

    alphas: tuple[float, ...]
    sigmas_deg: tuple[float, ...]
    nodes: int
    render_pixels: int
    render_spp: int

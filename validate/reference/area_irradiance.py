"""Irradiance measured by Mitsuba's ``irradiancemeter``, with Monte Carlo uncertainty, and the test
that decides whether a closed form agrees with it.

Measurement (:func:`measure_irradiance`), for a :class:`~validate.scenes.area_lights.MeterScene`
and each receiver normal n_i:

* the receiver disc is turned to n_i (``receiver.to_world``; the kernel is compiled once per scene);
* P independent passes, pass k rendered with ``mi.render(scene, spp=S, seed=seed·2²⁰ + i·P + k)``
  (seeds never repeat across normals, passes or base seeds < 2¹¹); the film has F×F pixels, every
  pixel an independent stream of S samples (the meter maps the film position to the point on the
  receiver, so pixels stratify the receiver), and the pass value is the float64 mean of the F² pixels.
  A 1×1 film is *not* used: Mitsuba accumulates a pixel's samples in float32, and 2¹⁸–2²⁰ samples
  in one pixel drift by 0.15–0.3 % (measured on a constant sky, where every sample equals π); with
  S ≤ 256 samples per pixel the drift is ≤ 2·10⁻⁶;
* estimate m_i = mean of the P pass values, standard error s_i = sample std / √P (P − 1 dof).
  Where no sample hit the light in any pass (s_i = 0), the resolution of the measurement, one
  sample's contribution π L_max / (P F² S), stands in for s_i.

Agreement with a prediction q_i (:func:`compare`): t_i = (m_i − q_i)/s_i, Student t with P − 1 dof
under H₀ (pass means ≈ normal by the CLT), converted to a standard-normal quantile
z_i = sign(t_i) Φ⁻¹(F_t(|t_i|)) so every value has the same null distribution. The prediction is
consistent when max_i |z_i| < z*, the Šidák-corrected two-sided critical value for M tests at
family-wise level α (default 1 %): z* = Φ⁻¹(1 − α₁/2), α₁ = 1 − (1 − α)^{1/M} [2]
(:mod:`validate.stats`). Only the first channel is tested: lights are grey and the three
channels share every path.

Cached with :func:`validate.reference.cache.cached` (key: the scene description, the normals, the
sampling settings, Mitsuba/drjit versions and variant).

References
  [1] Mitsuba 3 documentation, ``irradiancemeter`` sensor: "measures the incident power per unit
      area over a shape which it is attached to"; implementation samples a position on the shape and
      a cosine-weighted direction, weight π (src/sensors/irradiancemeter.cpp).
  [2] Z. Šidák, "Rectangular confidence regions for the means of multivariate normal
      distributions", JASA 62 (1967) 626–633.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..backend import init
from ..errors import ValidateError
from ..scenes.area_lights import MeterScene, receiver_to_world
from ..stats import mean_and_stderr, sidak_critical, t_to_z
from .cache import array_digest, cached

SEED_STRIDE = 1 << 20  # seeds of base seed s start at s·2²⁰
DEFAULT_ALPHA = 0.01  # family-wise significance level of the agreement test


@dataclass
class MeterIrradiance:
    """Mitsuba irradiance at each normal: ``mean`` (N,), standard error ``stderr`` (N,) and settings."""

    mean: np.ndarray
    stderr: np.ndarray
    passes: int
    spp: int
    film: int
    seed: int

    @property
    def samples(self) -> int:
        """Samples per normal over all passes."""
        return self.passes * self.spp * self.film * self.film

    def to_json(self) -> dict:
        return {"mean": self.mean.tolist(), "stderr": self.stderr.tolist(), "passes": self.passes, "spp": self.spp,
                "film": self.film, "seed": self.seed, "samples_per_normal": self.samples,
                "integrator": "path, max_depth = 1", "sampler": "independent", "sensor": "irradiancemeter"}


def measure_irradiance(meter: MeterScene, normals: np.ndarray, spp: int = 32, passes: int = 16,
                       seed: int = 0) -> MeterIrradiance:
    """Irradiance at the receiver for every normal (N, 3) — see the module docstring."""
    normals = np.ascontiguousarray(normals, dtype=np.float64).reshape(-1, 3)
    if passes < 4:
        raise ValidateError(f"irradiance meter: passes = {passes}; need ≥ 4 for a standard error with 3 dof")
    if not (1 <= spp <= 256):
        raise ValidateError(f"irradiance meter: spp = {spp} per pixel; accepted range 1–256 (float32 film)")
    if not (0 <= seed < 2048) or normals.shape[0] * passes >= SEED_STRIDE:
        raise ValidateError(f"irradiance meter: seed {seed} must lie in [0, 2048) and normals × passes < 2²⁰")
    film = int(meter.key.get("film", 0)) or int(meter.scene["receiver"]["sensor"]["film"]["width"])

    def compute() -> dict[str, np.ndarray]:
        import mitsuba as mi

        init()
        scene = mi.load_dict(meter.scene)
        params = mi.traverse(scene)
        values = np.zeros((normals.shape[0], passes, 3))
        for i, n in enumerate(normals):
            params["receiver.to_world"] = receiver_to_world(meter.position, n, meter.receiver_radius)
            params.update()
            for k in range(passes):
                img = mi.render(scene, spp=spp, seed=seed * SEED_STRIDE + i * passes + k)
                values[i, k] = np.asarray(img, dtype=np.float64).reshape(-1, 3).mean(axis=0)
        return {"values": values}

    parts = {"scene": meter.key, "normals": array_digest(normals), "spp": spp, "passes": passes, "seed": seed,
             "meter": "irradiancemeter/path1/independent/v1"}
    values = cached("area_irradiance", parts, compute)["values"][..., 0]
    mean, stderr = mean_and_stderr(values, axis=1)
    return MeterIrradiance(mean, stderr, passes, spp, film, seed)


def resolution(meas: MeterIrradiance, radiance_max: float) -> float:
    """One sample's contribution to the estimate: π L_max / (samples per normal)."""
    return float(np.pi * radiance_max / meas.samples)


@dataclass
class Agreement:
    """Outcome of :func:`compare`: z per normal, the worst |z|, the critical value and the verdict."""

    z: np.ndarray
    max_abs_z: float
    critical: float
    max_abs_deviation: float  # max |m − q| (units of E)
    alpha: float

    @property
    def consistent(self) -> bool:
        return bool(self.max_abs_z < self.critical)

    def to_json(self) -> dict:
        return {"z": self.z.tolist(), "max_abs_z": self.max_abs_z, "critical_z": self.critical,
                "max_abs_deviation": self.max_abs_deviation, "alpha": self.alpha, "consistent": self.consistent}


def compare(meas: MeterIrradiance, predicted: np.ndarray, radiance_max: float,
            alpha: float = DEFAULT_ALPHA) -> Agreement:
    """Test the prediction q (N,) against the measurement (module docstring); Šidák over the N normals."""
    q = np.asarray(predicted, dtype=np.float64).reshape(-1)
    if q.shape != meas.mean.shape:
        raise ValidateError(f"compare: {q.shape[0]} predictions for {meas.mean.shape[0]} measured normals")
    s = np.maximum(meas.stderr, resolution(meas, radiance_max))
    z = t_to_z((meas.mean - q) / s, meas.passes - 1)
    return Agreement(z, float(np.max(np.abs(z))), sidak_critical(q.size, alpha),
                     float(np.max(np.abs(meas.mean - q))), alpha)

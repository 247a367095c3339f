"""Scene queries with ray counts that are not a multiple of the packet width (validate.backend.padded_count).

On the LLVM variant, Mitsuba's ``Scene.ray_test``/``ray_intersect`` read a ray array past its end when its length
is ragged; that read faults (SIGSEGV, the process dies) when the buffer ends a few bytes before an unmapped page.
``GLIBC_TUNABLES=glibc.malloc.mmap_threshold=4096`` gives every allocation its own mapping, so no malloc slack hides
the over-read: unpadded, 135 154 rays (the ``lights`` disc frame's count) crash on every run.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from validate.backend import RAY_PACKET, pad_rows, padded_count

ROOT = Path(__file__).resolve().parents[2]

# 135 154 segments from z = −3 to z = +3 through a sphere of radius 0.5 at the origin: blocked iff x² + y² < 0.25
CHILD = r"""
import numpy as np
from validate.backend import load_scene
from validate.reference.shadow_render import segment_visible

n = 135154
xy = np.random.default_rng(7).uniform(-1.0, 1.0, size=(n, 2))
origins = np.c_[xy, np.full(n, -3.0)]
targets = np.c_[xy, np.full(n, 3.0)]
normals = np.tile([0.0, 0.0, 1.0], (n, 1))
scene = load_scene({"type": "scene", "s": {"type": "sphere", "radius": 0.5}})
free = segment_visible(scene, origins, normals, targets)
r = np.hypot(xy[:, 0], xy[:, 1])
clear = np.abs(r - 0.5) > 1e-3  # away from the silhouette (float32 rays, tessellation-free sphere)
wrong = int(np.sum(free[clear] != (r[clear] >= 0.5)))
print(f"rays {free.size} blocked {int(np.sum(~free))} wrong {wrong}")
"""


def test_padded_count_and_rows():
    assert [padded_count(k) for k in (0, 1, RAY_PACKET, RAY_PACKET + 1, 135154)] == [64, 64, 64, 128, 135168]
    a = np.arange(15.0).reshape(5, 3)
    p = pad_rows(a, 8)
    assert p.dtype == np.float32 and p.flags["C_CONTIGUOUS"] and p.shape == (8, 3)
    assert np.array_equal(p[:5], a) and np.array_equal(p[5:], np.tile(a[-1], (3, 1)))
    assert pad_rows(np.zeros((0, 3)), 64).shape == (64, 3)


def test_shadow_rays_of_a_ragged_count_survive_an_unmapped_tail():
    """Unpadded this child dies with SIGSEGV (returncode −11); padded it answers every segment right."""
    env = dict(os.environ, GLIBC_TUNABLES="glibc.malloc.mmap_threshold=4096:glibc.malloc.perturb=165")
    proc = subprocess.run([sys.executable, "-c", CHILD], cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, f"returncode {proc.returncode}: {proc.stderr[-2000:]}"
    rays, blocked, wrong = (int(w) for w in proc.stdout.split()[1::2])
    assert rays == 135154 and wrong == 0
    assert abs(blocked / rays - np.pi * 0.25 / 4.0) < 0.01  # area fraction of the disc in the [−1, 1]² square

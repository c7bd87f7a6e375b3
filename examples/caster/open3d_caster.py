#!/usr/bin/env python3
"""Open3D's RaycastingScene as a whole caster for `rayproof check --caster` (docs/check.md,
"Whole casters"): it reads the mesh once into a scene (float32, as Open3D stores it), then answers
each batch of rays with Open3D's cast_rays, one `t triangle` line per ray (`inf -1` for a miss).

    rayproof check --caster 'o3d=/usr/bin/python3 examples/caster/open3d_caster.py' --mesh mesh.off

Open3D runs in this child process: where it aborts (Debian's Embree asserts on a ray with a NaN,
an infinity or a zero direction), rayproof reports the crash and goes on."""
import os
import sys

import numpy as np
import open3d as o3d
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402


def main():
    V, T = read_mesh("rayproof-caster", np.float32, np.uint32)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(V), o3d.core.Tensor(T))
    for R in batches(6, np.float32):
        ans = scene.cast_rays(o3d.core.Tensor(R))
        t = ans["t_hit"].numpy()
        ids = ans["primitive_ids"].numpy()
        answer("%r %d\n" % (float(a), int(b)) if np.isfinite(a) else "inf -1\n" for a, b in zip(t, ids))


if __name__ == "__main__":
    main()
